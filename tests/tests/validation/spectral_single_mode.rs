//! Single-mode dynamic responses (docs/spectral-model.md §7.4–7.5). A step load
//! τ_0 cos(kx) (mode II: shear strength 0, normal stuck) or σ_0 cos(kx) (mode I: normal strength 0,
//! no contact, shear stuck) on the half-space operator; the slip/opening histories d_II(T), d_I(T)
//! and the normal face displacement w(T) match the exact (Laplace-inverted) values, with max error
//! ≤ 2e-3 at N = 64 and first-order convergence (error at N = 128 ≤ 0.6 × error at N = 64).
//! The operator and the per-point laws are the ones the solver uses.

use std::f64::consts::PI;

use spectral::law::Impedances;
use spectral::law::contact::{self, NormalInput};
use spectral::law::friction::solve_shear;
use spectral::{Convolution, FaceFields, FastStorage, HalfSpaceParams, HalfSpaces};

use crate::spectral_common::{eta_035, reference_rows};

const TOL_N64: f64 = 2e-3; // single mode: max error at N = 64; not tuned
const RATIO_N128: f64 = 0.6; // error(N = 128) ≤ 0.6 error(N = 64) (first order); not tuned

/// Loading mode of the single-mode test.
#[derive(Clone, Copy, PartialEq, Debug)]
pub enum Mode {
    /// Shear load, shear strength 0, normal stuck.
    II,
    /// Normal load, normal strength 0, no contact, shear stuck.
    I,
}

/// History of (T, d, w) at the sample points (d at cos kx = 1, w at sin kx = 1), normalised by
/// 2 τ_0/(μ k); μ = c_s = 1, X = N, β = 0.2, tcut = 100, until T = 20.
pub fn response(
    n: usize,
    mode: Mode,
    convolution: Convolution,
    fast_storage: FastStorage,
) -> Vec<(f64, f64, f64)> {
    let (mu, cs, eta, beta) = (1.0, 1.0, eta_035(), 0.2);
    let x_len = n as f64;
    let k = 2.0 * PI / x_len;
    let dt = beta * 1.0 / cs;
    let d_t = k * cs * dt;
    let steps = (20.0 / d_t).ceil() as usize + 2;
    let p = HalfSpaceParams {
        shear_modulus: mu,
        cs,
        eta,
        grid_points: n,
        length: x_len,
        cs_dt_over_dx: beta,
        kernel_cutoff: 100.0,
        max_steps: steps,
        convolution,
        fast_tolerance: spectral::DEFAULT_FAST_TOLERANCE,
        fast_storage,
    };
    let mut hs = HalfSpaces::new(&p).expect("operator builds");
    let (z, zn) = (mu / cs, eta * mu / cs);
    let (mut u, mut v, mut f) = (FaceFields::zeros(n), FaceFields::zeros(n), FaceFields::zeros(n));
    let scale = mu * k / 2.0; // load amplitude 1
    let mut out = Vec::with_capacity(steps);
    for step in 0..steps {
        hs.step(&u, &mut f);
        for m in 0..n {
            let load = (k * m as f64).cos();
            let (t1, t2) = if mode == Mode::II {
                (load, 0.0)
            } else {
                (0.0, load)
            };
            let (s1t, s1b, s2t, s2b) = (
                t1 + f.top_x[m],
                t1 + f.bottom_x[m],
                t2 + f.top_y[m],
                t2 + f.bottom_y[m],
            );
            let sh = solve_shear(
                s1t,
                s1b,
                if mode == Mode::II { 0.0 } else { f64::MAX },
                Impedances::equal(z),
            );
            let strength = if mode == Mode::I { 0.0 } else { f64::MAX };
            let opening = u.top_y[m] - u.bottom_y[m];
            let nr = contact::solve(&NormalInput {
                s_top: s2t,
                s_bottom: s2b,
                strength,
                opening,
                impedance: Impedances::equal(zn),
                dt,
                contact: false,
            });
            (v.top_x[m], v.bottom_x[m], v.top_y[m], v.bottom_y[m]) =
                (sh.v_top, sh.v_bottom, nr.v_top, nr.v_bottom);
        }
        let d = if mode == Mode::II {
            u.top_x[0] - u.bottom_x[0]
        } else {
            u.top_y[0] - u.bottom_y[0]
        };
        out.push((step as f64 * d_t, d * scale, u.top_y[n / 4] * scale));
        for m in 0..n {
            u.top_x[m] += dt * v.top_x[m];
            u.top_y[m] += dt * v.top_y[m];
            u.bottom_x[m] += dt * v.bottom_x[m];
            u.bottom_y[m] += dt * v.bottom_y[m];
        }
    }
    out
}

/// Linear interpolation of column `c` (1: d, 2: w) at T.
pub fn at(hist: &[(f64, f64, f64)], t: f64, c: usize) -> f64 {
    let i = hist
        .iter()
        .position(|r| r.0 >= t)
        .expect("T inside the history")
        .max(1);
    let (a, b) = (hist[i - 1], hist[i]);
    let pick = |r: (f64, f64, f64)| if c == 1 { r.1 } else { r.2 };
    pick(a) + (pick(b) - pick(a)) * (t - a.0) / (b.0 - a.0)
}

/// Max errors (d_II, d_I, w) against the reference tables at N, the fast path's states stored
/// in double precision.
pub fn errors(n: usize, convolution: Convolution) -> [f64; 3] {
    errors_stored(n, convolution, FastStorage::F64)
}

/// [`errors`] with the fast path's states stored as `fast_storage` says.
pub fn errors_stored(n: usize, convolution: Convolution, fast_storage: FastStorage) -> [f64; 3] {
    let h2 = response(n, Mode::II, convolution, fast_storage);
    let h1 = response(n, Mode::I, convolution, fast_storage);
    let (mut e2, mut e1, mut ew) = (0.0f64, 0.0f64, 0.0f64);
    for r in reference_rows("spectral-single-mode-nu035.csv") {
        e2 = e2.max((at(&h2, r[0], 1) - r[1]).abs());
        e1 = e1.max((at(&h1, r[0], 1) - r[2]).abs());
    }
    for r in reference_rows("spectral-single-mode-w-nu035.csv") {
        ew = ew.max((at(&h2, r[0], 2) - r[1]).abs());
    }
    [e2, e1, ew]
}

#[test]
fn single_mode_responses_converge_at_first_order() {
    let e64 = errors(64, Convolution::Direct);
    let e128 = errors(128, Convolution::Direct);
    for (i, name) in ["d_II", "d_I", "w"].iter().enumerate() {
        println!(
            "{name}: max error N=64 {:.3e}, N=128 {:.3e}, ratio {:.3}",
            e64[i],
            e128[i],
            e128[i] / e64[i]
        );
    }
    for i in 0..3 {
        assert!(e64[i] <= TOL_N64, "N = 64 error {} > {TOL_N64}", e64[i]);
        assert!(
            e128[i] <= RATIO_N128 * e64[i],
            "not first order: {} > 0.6 × {}",
            e128[i],
            e64[i]
        );
    }
}
