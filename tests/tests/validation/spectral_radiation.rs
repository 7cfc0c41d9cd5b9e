//! Radiation damping (the impedance term of paper eq. 13) is exact (docs/spectral-model.md §7.3).
//! (i) An intact interface under a uniform load stays exactly at rest; (ii) a zero-strength interface
//! under a uniform shear step (normal closed by contact) gives face velocities ±τ_0 c_s/μ; (iii) the
//! mode-I analogue gives ±σ_0 c_s/(ημ). Only k = 0 is excited, so f ≡ 0 and the values hold to
//! round-off.

use crate::spectral_common::{f, run, scene};

/// Every point broken at t = 0: a free (zero-strength) interface.
fn broken() -> (&'static str, Option<toml::Value>) {
    (
        "spectral.initial_interface",
        Some(toml::Value::String("broken".into())),
    )
}

const TOL_ROUNDOFF: f64 = 1e-12; // exact "to round-off" (relative to the exact velocity); not tuned

/// Largest relative deviation of `pick` from `exact` over every field record.
pub fn max_rel_dev(
    out: &spectral::RunOutput,
    pick: impl Fn(&spectral::FieldRecord) -> f64,
    exact: f64,
) -> f64 {
    out.fields
        .iter()
        .map(|r| (pick(r) - exact).abs() / exact.abs())
        .fold(0.0, f64::max)
}

#[test]
fn intact_interface_stays_at_rest() {
    let s = scene("tiny-spectral-radiation", &[f("crack.half_length", 0.0)]);
    let out = run(&s);
    let moved = out
        .fields
        .iter()
        .map(|r| r.slip.abs() + r.opening.abs() + r.vx_top.abs() + r.vy_top.abs())
        .fold(0.0, f64::max);
    println!("intact: {} samples, max |u|+|v| = {moved:e}", out.fields.len());
    assert!(!out.fields.is_empty());
    assert_eq!(moved, 0.0, "intact interface moved");
}

#[test]
fn free_interface_under_shear_step_radiates_exactly() {
    let s = scene("tiny-spectral-radiation", &[broken()]);
    let w = s.wave_speeds();
    let tau0 = s.shear.r#final;
    let v = tau0 * w.cs / s.shear_modulus();
    let out = run(&s);
    let dev_top = max_rel_dev(&out, |r| r.vx_top, v);
    let dev_bottom = max_rel_dev(&out, |r| r.vx_bottom, -v);
    let dev_slip = out
        .fields
        .iter()
        .map(|r| (r.slip - 2.0 * v * r.t).abs() / (2.0 * v * s.duration))
        .fold(0.0, f64::max);
    let t1 = out
        .fields
        .iter()
        .map(|r| r.shear_traction.abs())
        .fold(0.0, f64::max);
    println!(
        "mode II: v = ±{v:.6}; rel. dev top {dev_top:.1e} bottom {dev_bottom:.1e} slip {dev_slip:.1e}; max|T1| = {t1:e}"
    );
    assert!(dev_top <= TOL_ROUNDOFF && dev_bottom <= TOL_ROUNDOFF && dev_slip <= TOL_ROUNDOFF);
    assert_eq!(t1, 0.0);
}

#[test]
fn free_interface_under_tension_step_radiates_exactly() {
    let s = scene(
        "tiny-spectral-radiation",
        &[
            broken(),
            f("loading.shear.final", 0.0),
            f("loading.normal.final", 0.2),
        ],
    );
    let w = s.wave_speeds();
    let v = 0.2 * w.cs / (s.eta() * s.shear_modulus());
    let out = run(&s);
    let dev_top = max_rel_dev(&out, |r| r.vy_top, v);
    let dev_bottom = max_rel_dev(&out, |r| r.vy_bottom, -v);
    println!("mode I: v = ±{v:.6}; rel. dev top {dev_top:.1e} bottom {dev_bottom:.1e}");
    assert!(dev_top <= TOL_ROUNDOFF && dev_bottom <= TOL_ROUNDOFF);
}
