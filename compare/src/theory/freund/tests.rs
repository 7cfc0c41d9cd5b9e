//! Tests of the universal functions, the equation of motion and the Andrews fit.

use super::*;

/// Material with unit shear speed, so speeds in the tests read as `v/c_s`.
fn mat(nu: f64) -> Material {
    Material::from_nu(nu, 1.0).expect("invariant: test Poisson ratio is in (-1, 1/2)")
}

/// Root in (0, 1) of the Rayleigh cubic `ξ³ − 8ξ² + (24 − 16κ)ξ − 16(1 − κ) = 0`,
/// `ξ = (v/c_s)²`, `κ = (c_s/c_d)²`, by plain bisection on the polynomial (independent of
/// the square-root form used by the library). Returns `v/c_s`.
fn rayleigh_from_cubic(nu: f64) -> f64 {
    let kappa = (1.0 - 2.0 * nu) / (2.0 * (1.0 - nu));
    let cubic = |xi: f64| ((xi - 8.0) * xi + 24.0 - 16.0 * kappa) * xi - 16.0 * (1.0 - kappa);
    let (mut lo, mut hi) = (1e-12, 1.0);
    assert!(
        cubic(lo) < 0.0 && cubic(hi) > 0.0,
        "cubic must bracket exactly one root in (0, 1)"
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if cubic(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).sqrt()
}

/// Naive `R(v)` straight from its definition (test helper for the cancellation test).
fn naive_rayleigh(m: &Material, v: f64) -> f64 {
    let alpha_d = (1.0 - (v / m.cd()).powi(2)).sqrt();
    let alpha_s = (1.0 - (v / m.cs()).powi(2)).sqrt();
    4.0 * alpha_d * alpha_s - (1.0 + alpha_s * alpha_s).powi(2)
}

/// Naive slowness integral: Gauss–Legendre directly in `η` (no end-point substitution),
/// the weight `x/(1 − xη)`, in units of `c_s`. Test helper for the quadrature regression test.
fn naive_ln_s_plus_behind(m: &Material, x: f64, n: usize) -> f64 {
    let a = m.cs() / m.cd();
    let integral = gauss_legendre(n, |t| {
        let eta = a + 0.5 * (1.0 - a) * (t + 1.0);
        let num = 4.0 * eta * eta * (eta * eta - a * a).sqrt() * (1.0 - eta * eta).sqrt();
        let theta = (num / (1.0 - 2.0 * eta * eta).powi(2)).atan();
        0.5 * (1.0 - a) * theta * x / (1.0 - x * eta)
    });
    integral / PI
}

#[test]
fn gauss_legendre_is_exact_for_polynomials() {
    // An n-point rule integrates degree 2n-1 exactly; 1e-13 allows only round-off, so a wrong
    // node or weight formula fails.
    let exact = 2.0 / 31.0 + 2.0 / 3.0;
    let got = gauss_legendre(16, |t| t.powi(30) + t * t + t.powi(7));
    assert!((got - exact).abs() < 1e-13, "got {got}, want {exact}");
}

#[test]
fn rayleigh_speed_nu_quarter_is_classical() {
    // For ν = 1/4 the cubic factors and c_R/c_s = sqrt(2 − 2/√3) = 0.919402 (6 digits as
    // asked); bisection to machine precision is checked at 1e-13 against the closed form.
    let cr = mat(0.25).rayleigh_speed();
    let closed = (2.0 - 2.0 / 3.0_f64.sqrt()).sqrt();
    assert!((cr - 0.919402).abs() < 1e-6, "c_R/c_s = {cr}");
    assert!(
        (cr - closed).abs() < 1e-13,
        "c_R/c_s = {cr}, closed form {closed}"
    );
}

#[test]
fn rayleigh_speed_nu_035_matches_cubic() {
    // Both roots are found to machine precision by different formulas; 1e-12 leaves room
    // for round-off only.
    let cr = mat(0.35).rayleigh_speed();
    let cubic = rayleigh_from_cubic(0.35);
    assert!((cr - cubic).abs() < 1e-12, "library {cr}, cubic {cubic}");
}

#[test]
fn from_nu_round_trips_and_rejects_bad_input() {
    // ν is recovered through c_d/c_s; 1e-14 is round-off level.
    for nu in [-0.5, 0.0, 0.25, 0.35, 0.49] {
        assert!((mat(nu).nu() - nu).abs() < 1e-14, "nu {nu}");
    }
    assert!(Material::from_nu(0.5, 1.0).is_none());
    assert!(Material::from_nu(-1.0, 1.0).is_none());
    assert!(Material::new(1.1, 1.0).is_none());
    assert!(Material::new(2.0, 0.0).is_none());
}

#[test]
fn wiener_hopf_factorisation_identity() {
    // R(ζ) = 2(b² − a²)(c² − ζ²) S₊(ζ) S₊(−ζ) on (−a, a) and beyond b (units c_s = 1). A wrong
    // sign in the exponent or a wrong θ changes the product by O(10%); 1e-12 is the
    // quadrature/round-off level.
    for nu in [0.0, 0.25, 0.35, 0.45] {
        let m = mat(nu);
        let (a, c) = (m.a_hat(), 1.0 / m.rayleigh_speed());
        let big_c = 2.0 * (1.0 - a * a);
        for z in [0.0, 0.3 * a, -0.7 * a, 0.95 * a] {
            let r = (1.0 - 2.0 * z * z).powi(2) + 4.0 * z * z * (a * a - z * z).sqrt() * (1.0 - z * z).sqrt();
            let product = big_c * (c * c - z * z) * m.s_plus(z) * m.s_plus(-z);
            assert!(
                (product / r - 1.0).abs() < 1e-12,
                "nu {nu} zeta {z}: {product} vs {r}"
            );
        }
        for v in [0.3, 0.6, 0.9] {
            let z = 1.0 / v;
            let r = -m.rayleigh_function(v) / v.powi(4);
            let product = big_c * (c * c - z * z) * m.s_plus(z) * m.s_plus(-z);
            assert!(
                (product / r - 1.0).abs() < 1e-12,
                "nu {nu} v {v}: {product} vs {r}"
            );
        }
    }
}

#[test]
fn k_has_both_printed_forms() {
    // k = (1 − v/c_R) S₊(−1/v)/sqrt(1 − v/c_w) must equal the form with S₊(+1/v):
    // (1−ν) c_s² R(v) / (v² (1 + v/c_R) S₊(1/v) sqrt(1 − v/c_w)), with c_w = c_d (mode I) or
    // c_s (mode II). The two S₊ values come from different quadrature weights and agree to
    // round-off, so 1e-11 relative is generous; the wrong wave speed for a mode fails it.
    let m = mat(0.3);
    let cr = m.rayleigh_speed();
    for (mode, cw) in [(Mode::I, m.cd()), (Mode::II, m.cs())] {
        for f in [0.1, 0.5, 0.9, 0.99] {
            let v = f * cr;
            let other = m.rayleigh_function(v)
                / (m.inv_one_minus_nu() * v * v * (1.0 + f))
                / (m.s_plus(1.0 / v) * (1.0 - v / cw).sqrt());
            let k = m.k_of_v(mode, v);
            assert!(
                (k / other - 1.0).abs() < 1e-11,
                "{mode:?} v/c_R {f}: {k} vs {other}"
            );
        }
    }
}

#[test]
fn energy_factor_matches_definition() {
    // At moderate speed R(v) has no cancellation, so the rearranged A must agree with the
    // textbook expression to round-off (1e-13).
    let m = mat(0.35);
    for v in [0.2, 0.5, 0.8] {
        let r = naive_rayleigh(&m, v);
        let alpha_d = (1.0 - (v / m.cd()).powi(2)).sqrt();
        let alpha_s = (1.0 - v * v).sqrt();
        let scale = v * v * m.inv_one_minus_nu() / r;
        assert!((m.a_of_v(Mode::I, v) / (scale * alpha_d) - 1.0).abs() < 1e-13);
        assert!((m.a_of_v(Mode::II, v) / (scale * alpha_s) - 1.0).abs() < 1e-13);
    }
}

#[test]
fn g_tends_to_one_at_low_speed() {
    // g = 1 − O(v/c_R) with slope ≈ 1.2 here, so 1e-3 at v = 1e-4 c_R has 8x margin while a
    // wrong normalisation of A (e.g. a missing 1 − ν) is off by tens of percent.
    for nu in [0.25, 0.35] {
        let m = mat(nu);
        let v = 1e-4 * m.rayleigh_speed();
        for mode in [Mode::I, Mode::II] {
            let g = m.g_of_v(mode, v);
            assert!((g - 1.0).abs() < 1e-3, "nu {nu} {mode:?}: g = {g}");
            assert!((m.k_of_v(mode, 0.0) - 1.0).abs() < 1e-15 && (m.a_of_v(mode, 0.0) - 1.0).abs() < 1e-15);
        }
    }
}

#[test]
fn g_vanishes_at_rayleigh_speed_and_decreases() {
    // g ≈ 2(1 − v/c_R) near c_R, so g(0.999 c_R) ≈ 0.002 < 0.01; a k without the (1 − v/c_R)
    // zero would give g → ∞. Monotonicity on 200 points catches sign errors in the integral.
    for nu in [0.25, 0.35] {
        let m = mat(nu);
        let cr = m.rayleigh_speed();
        for mode in [Mode::I, Mode::II] {
            assert!(m.g_of_v(mode, 0.999 * cr) < 0.01);
            assert_eq!(m.g_of_v(mode, cr), 0.0);
            let mut previous = m.g_of_v(mode, 0.0);
            for i in 1..=200 {
                let g = m.g_of_v(mode, cr * i as f64 / 201.0);
                assert!(
                    g < previous && g > 0.0,
                    "nu {nu} {mode:?} step {i}: {g} !< {previous}"
                );
                previous = g;
            }
        }
    }
}

#[test]
fn quadrature_converges() {
    // Doubling the nodes must change g by < 1e-10 (requested); the rule is geometrically
    // convergent after the end-point substitution, so a slip back to algebraic convergence fails.
    for nu in [0.25, 0.35, 0.45] {
        let m = mat(nu);
        let cr = m.rayleigh_speed();
        for f in [0.5, 0.95] {
            for mode in [Mode::I, Mode::II] {
                let coarse = m.g_with_nodes(mode, f * cr, QUAD_NODES);
                let fine = m.g_with_nodes(mode, f * cr, 2 * QUAD_NODES);
                assert!((coarse - fine).abs() < 1e-10, "nu {nu} f {f}: {coarse} vs {fine}");
            }
        }
    }
}

#[test]
fn speed_at_half_length_inverts_g() {
    // Bisection to machine precision on a function of slope O(1/c_R): g(v(x)) = 1/x to 1e-12.
    let m = mat(0.35);
    let mut previous = 0.0;
    for x in [1.000001, 1.01, 1.5, 2.0, 5.0, 20.0, 1e3, 1e6] {
        for mode in [Mode::I, Mode::II] {
            let v = m.speed_at_half_length(mode, x);
            let g = m.g_of_v(mode, v);
            assert!((g - 1.0 / x).abs() < 1e-12, "{mode:?} x {x}: g {g}");
        }
        let v = m.speed_at_half_length(Mode::II, x);
        assert!(v > previous, "speed must increase with a/L_c");
        previous = v;
    }
    assert_eq!(m.speed_at_half_length(Mode::I, 1.0), 0.0);
    assert_eq!(m.speed_at_half_length(Mode::I, 0.3), 0.0);
    assert_eq!(m.speed_at_half_length(Mode::I, f64::INFINITY), m.rayleigh_speed());
}

#[test]
fn stable_rayleigh_beats_naive_at_low_speed() {
    // At v = 1e-6 c_s the two terms of R are ≈ 4 and cancel to ≈ 1e-12, so the naive form
    // keeps ~3 digits; A(v) = 1 + O(1e-12) exactly. Measured: naive error ~1e-4, ours ~1e-15.
    let m = mat(0.25);
    let v = 1e-6;
    let alpha_d = (1.0 - (v / m.cd()).powi(2)).sqrt();
    let naive_a = v * v * alpha_d * m.inv_one_minus_nu() / naive_rayleigh(&m, v);
    let ours = m.a_of_v(Mode::I, v);
    assert!((ours - 1.0).abs() < 1e-11, "stable A = {ours}");
    assert!(
        (naive_a - 1.0).abs() > 1e-6,
        "naive A = {naive_a} unexpectedly accurate"
    );
}

#[test]
fn substitution_beats_naive_quadrature() {
    // Square-root end points make plain Gauss–Legendre in η converge only algebraically.
    // Reference: the substituted rule with 256 nodes. Measured at 64 nodes: naive error
    // ~1e-6, ours < 1e-14 (asserted < 1e-12 and > 1e-8 respectively).
    let m = mat(0.35);
    let x = 0.95 * m.rayleigh_speed();
    let reference = m.ln_s_plus_behind(x, 256);
    let ours = m.ln_s_plus_behind(x, QUAD_NODES);
    let naive = naive_ln_s_plus_behind(&m, x, QUAD_NODES);
    assert!((ours - reference).abs() < 1e-12, "ours {ours} vs {reference}");
    assert!((naive - reference).abs() > 1e-8, "naive {naive} vs {reference}");
}

#[test]
fn approximations_of_k_and_g() {
    // Closed-form approximations over (0, 0.9 c_R], measured on a 1000-point grid:
    // k_I vs (1 − v/c_R)/sqrt(1 − h v), with h = 1/c_d + (2/π)∫θ dη so that k'(0) is exact:
    //   max relative error 2.9% (ν = 0.25) and 7.3% (ν = 0.35), both at 0.9 c_R;
    // g_I vs 1 − v/c_R: max absolute error 0.057 (ν = 0.25) and 0.056 (ν = 0.35), in units
    //   of g(0) = 1 (relative error reaches 48% at 0.9 c_R).
    // Bounds are those maxima plus 15-20%; dropping S₊ (k ≈ (1 − v/c_R)/sqrt(1 − v/c_d)) or
    // misplacing the mode's wave speed breaks them by a wide margin.
    for (nu, k_tol, g_tol) in [(0.25, 0.035, 0.065), (0.35, 0.085, 0.065)] {
        let m = mat(nu);
        let cr = m.rayleigh_speed();
        let h = m.a_hat() + 2.0 * m.theta_integral(QUAD_NODES, |_| 1.0) / PI;
        for i in 1..=90 {
            let v = cr * i as f64 / 100.0;
            let approx = (1.0 - v / cr) / (1.0 - h * v).sqrt();
            let k = m.k_of_v(Mode::I, v);
            assert!(
                (approx / k - 1.0).abs() < k_tol,
                "nu {nu} v {v}: k {k} approx {approx}"
            );
            let g = m.g_of_v(Mode::I, v);
            assert!((g - (1.0 - v / cr)).abs() < g_tol, "nu {nu} v {v}: g {g}");
        }
    }
}

#[test]
fn griffith_and_andrews_lengths() {
    // Pure algebra; 1e-12 relative is round-off.
    let (mu, nu, gc, load) = (30e9, 0.25, 1e3, 5e6);
    let lc = griffith_length(mu, nu, gc, load);
    assert!((static_energy_release_rate(mu, nu, lc, load) / gc - 1.0).abs() < 1e-12);
    let (tau_s, tau_0, tau_d, dc) = (70e6, 60e6, 50e6, 0.4);
    let s = seismic_ratio(tau_s, tau_0, tau_d).expect("invariant: valid stresses");
    assert!((s - 1.0).abs() < 1e-12);
    let la = andrews_critical_length(mu, nu, dc, tau_s, tau_0, tau_d).expect("invariant: valid input");
    // (λ + μ)/(λ + 2μ) = 1/(2(1 − ν)): half the Griffith half-length
    let direct = mu * dc * (tau_s - tau_d) / (2.0 * PI * (1.0 - nu) * (tau_0 - tau_d).powi(2));
    assert!(
        (la / (0.5 * griffith_length(mu, nu, 0.5 * (tau_s - tau_d) * dc, tau_0 - tau_d)) - 1.0).abs() < 1e-12
    );
    assert!((la / direct - 1.0).abs() < 1e-12);
    let l = andrews_transition_distance(s, la).expect("invariant: S < 1.77");
    assert!((l / (9.8 * la / 0.77_f64.powi(3)) - 1.0).abs() < 1e-12);
    assert!(andrews_transition_distance(1.77, la).is_none());
    assert!(andrews_transition_distance(-0.1, la).is_none());
    assert!(seismic_ratio(50e6, 60e6, 50e6).is_none());
}
