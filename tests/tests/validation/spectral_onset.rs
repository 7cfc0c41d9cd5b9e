//! Crack onset (paper §3, σ_crit; Fig. 7a for the delay by friction): in the centre-crack case
//! with μ = 0 the crack starts when the applied shear is within 10 % of the plane-strain LEFM value
//! τ_c = sqrt(G_c E/(π a (1 − ν²))) = 63.7 kPa (docs/cases.md); friction (μ = 0.3) delays the onset.

use spectral::loading::ramp_value;

use crate::spectral_common::{center_crack, center_crack_a, onset_time, scene};

const TOL_ONSET_REL: f64 = 0.10; // onset shear within 10 % of the LEFM τ_c; not tuned

#[test]
fn onset_matches_lefm_and_friction_delays_it() {
    let s = scene("center-crack", &[]);
    let g_c = s.sigma_c * s.delta_c / 2.0;
    let nu = s.poisson_ratio;
    let tau_c = (g_c * s.youngs_modulus / (std::f64::consts::PI * s.half_length * (1.0 - nu * nu))).sqrt();
    let t0 = onset_time(center_crack(0.0), center_crack_a()).expect("μ = 0 crack never started");
    let t3 = onset_time(center_crack(0.3), center_crack_a()).expect("μ = 0.3 crack never started");
    let tau_onset = ramp_value(&s.shear, t0);
    println!(
        "τ_c (LEFM) = {tau_c:.1} Pa; μ = 0 onset at t = {t0:.6e} s (t/T = {:.4}), s_xy = {tau_onset:.1} Pa ({:+.2} %); μ = 0.3 onset at t = {t3:.6e} s (t/T = {:.4}), s_xy = {:.1} Pa",
        t0 / s.duration,
        100.0 * (tau_onset / tau_c - 1.0),
        t3 / s.duration,
        ramp_value(&s.shear, t3)
    );
    assert!(
        (tau_onset / tau_c - 1.0).abs() <= TOL_ONSET_REL,
        "onset shear {tau_onset} vs τ_c {tau_c}"
    );
    assert!(t3 > t0, "friction did not delay the onset");
}
