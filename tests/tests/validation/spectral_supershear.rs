//! Supershear transition (Andrews 1976; Geubelle & Kubair 2001; docs/spectral-model.md §7.7): with
//! S = 1.0 the rupture becomes supershear (tip speed > c_s, settling between √2 c_s and c_d) at a
//! crack half-length within a factor 2 of Andrews' transition length L = 9.8 (1.77 − S)^(−3) L_c,
//! L_c = μ(τ_p − τ_r)δ_c/(2π(1 − ν)(τ_0 − τ_r)²); with S = 2.5 it never does.

use crate::spectral_common::{andrews_s10, andrews_s25, scene, speed_between, windowed_speeds};

const FACTOR_ANDREWS: f64 = 2.0; // transition length within a factor 2 of Andrews; not tuned
const WINDOW: f64 = 3.0; // §7.7: least squares over 3 time units

#[test]
fn s10_becomes_supershear_near_andrews_length_and_s25_does_not() {
    let s = scene("tiny-spectral-andrews", &[]);
    let (w, mu, nu) = (s.wave_speeds(), s.shear_modulus(), s.poisson_ratio);
    let (tau_p, tau_0, delta_c, t_end) = (1.0, 0.5, 1.0, 45.0);
    let big_s = (tau_p - tau_0) / tau_0;
    let l_c = mu * tau_p * delta_c / (2.0 * std::f64::consts::PI * (1.0 - nu) * tau_0 * tau_0);
    let andrews = 9.8 * (1.77 - big_s).powi(-3) * l_c;
    let out = andrews_s10();
    let speeds = windowed_speeds(&out.tips, s.center_x, WINDOW);
    let first = speeds.iter().find(|v| v.2 > w.cs).copied();
    let v_settle = speed_between(&out.tips, 0.75 * t_end, t_end);
    let v25 = windowed_speeds(&andrews_s25().tips, s.center_x, WINDOW)
        .iter()
        .map(|v| v.2)
        .fold(0.0, f64::max);
    println!(
        "S = 1.0: Andrews L = {andrews:.2}; first supershear window at t = {:?}, half-length {:?}; settled speed {:.4} c_s (√2 = 1.4142, c_d/c_s = {:.4}); S = 2.5 max speed {:.4} c_s",
        first.map(|v| v.0),
        first.map(|v| v.1),
        v_settle / w.cs,
        w.cd / w.cs,
        v25 / w.cs
    );
    let (_, half, _) = first.expect("S = 1.0 rupture never exceeded c_s");
    assert!(
        half >= andrews / FACTOR_ANDREWS && half <= andrews * FACTOR_ANDREWS,
        "transition at {half}, Andrews {andrews}"
    );
    assert!(
        v_settle > 2f64.sqrt() * w.cs && v_settle < w.cd,
        "settled speed {v_settle} not in (√2 c_s, c_d)"
    );
    assert!(v25 < w.cs, "S = 2.5 became supershear ({v25})");
}
