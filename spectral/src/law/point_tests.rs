//! The friction rules of the point law, each against its analytic dissipation (docs/spectral-model.md
//! §5.5), and the point's sign and branch rules.

use super::*;

/// The centre crack's interface (paper Table 1: σ_c = 0.4 MPa, δ_c = 0.1 mm, β = κ = 1) with its
/// material's impedances (μ = 25.9 MPa, c_s = 145.2 m/s, η = 2.08), μ = 0.3, and Δt/t* = 0.05.
fn law(rule: ContactFriction) -> PointLaw {
    let z = 25.926e6 / 145.18;
    PointLaw {
        cohesive: CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0),
        z_shear: Impedances::equal(z),
        z_normal: Impedances::equal(2.0817 * z),
        dt: 1e-8,
        friction_coeff: 0.3,
        relax: Some(0.05),
        contact: true,
        rule,
    }
}

/// Compression on both faces [Pa].
const PRESSURE: f64 = 0.05e6;

fn drive(point: &Point, shear: f64, normal: f64) -> Drive {
    // the jumps follow from the face velocities of the previous steps: kept by the caller
    let _ = point;
    Drive {
        shear: (shear, shear),
        normal: (normal, normal),
        opening: 0.0,
        slip: 0.0,
    }
}

/// Shears one point at the constant slip rate `rate` [m/s] under the constant compression
/// [`PRESSURE`] until the slip reaches `slip_end` [m], after letting σ̃ settle on the compression;
/// returns the dissipated work ∫ T_1 dδ_t [J/m²] and the last point.
///
/// Each step first asks the law for its shear strength τ_n (a probe under a shear far above any
/// strength slips at T_1 = τ_n; the law is pure, so the probe changes nothing), then drives both
/// faces with S_1 = τ_n + Z·rate/2, which slips at exactly `rate` against T_1 = τ_n.
fn shear_through(law: &PointLaw, rate: f64, slip_end: f64) -> (f64, Point) {
    let mut p = Point::at_rest(Strength::intact(&law.cohesive));
    let (mut opening, mut slip) = (0.0, 0.0);
    for _ in 0..2000 {
        p = step(law, &drive(&p, 0.0, -PRESSURE), &p);
    }
    let mut work = 0.0;
    while slip < slip_end {
        let at = |shear| Drive {
            opening,
            slip,
            ..drive(&p, shear, -PRESSURE)
        };
        let tau = step(law, &at(1e12), &p).traction[0];
        let next = step(law, &at(tau + 0.5 * law.z_shear.top * rate), &p);
        let d_slip = law.dt * (next.v[0] - next.v[2]);
        work += next.traction[0] * d_slip;
        slip += d_slip;
        opening += law.dt * (next.v[1] - next.v[3]);
        p = next;
    }
    (work, p)
}

/// `all_faces` (paper §2.3, Fig. 4d): a closed point sheared through its whole cohesive law under
/// constant compression p dissipates G_II + μ p δ_end, the cohesive energy plus Coulomb friction
/// over the whole slip. `failed_only` dissipates G_II + μ p (δ_end − δ_ct): friction from the
/// break on. Tolerance 1e-3 of the total: the strength is taken at the start of each slip
/// increment (a left Riemann sum of a line of slope σ_c/δ_c), which overestimates G_II by
/// Δδ/δ_c = 2.5e-4 of it, and the first increment, still intact, lacks μ p Δδ.
#[test]
fn a_closed_point_sheared_through_its_law_dissipates_g_ii_plus_coulomb_work() {
    let (g_ii, delta_ct, mu) = (20.0, 1e-4, 0.3);
    let slip_end = 2.0 * delta_ct;
    let rate = delta_ct / 4000.0 / 1e-8; // Δδ = δ_c/4000 per step
    for (rule, friction_slip) in [
        (ContactFriction::AllFaces, slip_end),
        (ContactFriction::FailedOnly, slip_end - delta_ct),
    ] {
        let (work, last) = shear_through(&law(rule), rate, slip_end);
        let expected = g_ii + mu * PRESSURE * friction_slip;
        let rel = work / expected - 1.0;
        println!("{rule:?}: dissipated {work:.6} J/m² against {expected:.6} ({rel:+.2e})");
        assert!(rel.abs() < 1e-3, "{rule:?}: {work} against {expected}");
        assert!(last.in_contact && last.strength.state == PointState::Contact);
    }
}

/// The same shear under the same compression with μ = 0 dissipates G_II alone under both rules:
/// friction is the only difference between them.
#[test]
fn without_friction_both_rules_dissipate_g_ii() {
    for rule in [ContactFriction::AllFaces, ContactFriction::FailedOnly] {
        let law = PointLaw {
            friction_coeff: 0.0,
            ..law(rule)
        };
        let (work, _) = shear_through(&law, 1e-4 / 4000.0 / 1e-8, 2e-4);
        assert!((work / 20.0 - 1.0).abs() < 1e-3, "{rule:?}: {work}");
    }
}

/// A damaged point in contact with σ̃ from the compression it had, driven now by tension (stuck
/// below its normal strength, then open above it): friction never acts, whatever μ. Both
/// branches give the bits of μ = 0, and σ̃ relaxes towards 0.
#[test]
fn friction_never_acts_on_an_open_point() {
    let cohesive = CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0);
    let damaged = cohesive::update(&cohesive, 0.0, 0.3e-4, Strength::intact(&cohesive));
    assert_eq!(damaged.state, PointState::Cohesive);
    let old = Point {
        reg_normal: -PRESSURE,
        ..Point::at_rest(damaged)
    };
    for tension in [0.1e6, 0.5e6] {
        let d = Drive {
            shear: (0.35e6, 0.35e6),
            normal: (tension, tension),
            opening: 0.0,
            slip: 0.3e-4,
        };
        let with = step(&law(ContactFriction::AllFaces), &d, &old);
        let without = step(
            &PointLaw {
                friction_coeff: 0.0,
                ..law(ContactFriction::AllFaces)
            },
            &d,
            &old,
        );
        assert!(!with.friction_on && with.traction[1] >= 0.0);
        assert_eq!(with.traction, without.traction);
        assert_eq!(with.v, without.v);
        assert!(with.reg_normal > old.reg_normal && with.reg_normal < 0.0);
        // slipping at the cohesive strength alone
        assert_eq!(with.traction[0], with.strength.tau);
    }
}

/// An intact point carries its peak shear strength τ_max, compressed or not: friction acts only
/// once the point has begun to weaken (the FE model's facet before insertion has none either).
#[test]
fn an_intact_closed_point_slips_at_its_peak_strength_alone() {
    let law = law(ContactFriction::AllFaces);
    let mut p = Point::at_rest(Strength::intact(&law.cohesive));
    for _ in 0..200 {
        p = step(&law, &drive(&p, 0.0, -PRESSURE), &p);
    }
    assert!(
        p.reg_normal < -0.99 * PRESSURE,
        "σ̃ follows the compression: {}",
        p.reg_normal
    );
    let r = step(&law, &drive(&p, 1e12, -PRESSURE), &p);
    assert!(r.slipping && !r.friction_on);
    assert_eq!(r.traction[0], law.cohesive.tau_max);
}

/// Once weakened, a closed point's strength is τ_s + μ|σ̃| under `all_faces` and τ_s under
/// `failed_only`: the sign of the superposed friction follows the slip (T_1 resists it).
#[test]
fn a_weakened_closed_point_adds_friction_to_its_cohesive_strength_in_either_direction() {
    let cohesive = CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0);
    let damaged = cohesive::update(&cohesive, 0.0, 0.5e-4, Strength::intact(&cohesive));
    let old = Point {
        reg_normal: -PRESSURE,
        ..Point::at_rest(damaged)
    };
    for sign in [1.0, -1.0] {
        let d = Drive {
            slip: sign * 0.5e-4,
            ..drive(&old, sign * 1e12, -PRESSURE)
        };
        let all = step(&law(ContactFriction::AllFaces), &d, &old);
        let failed = step(&law(ContactFriction::FailedOnly), &d, &old);
        let friction = 0.3 * all.reg_normal.abs();
        assert!(all.friction_on && !failed.friction_on);
        assert!((all.traction[0] - sign * (damaged.tau + friction)).abs() < 1e-6);
        assert!((failed.traction[0] - sign * damaged.tau).abs() < 1e-6);
    }
}
