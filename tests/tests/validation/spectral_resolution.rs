//! Grid convergence (docs/spectral-model.md §7.9): onset time and mean tip speed of the centre-crack
//! case (μ = 0) change by less than 1 % between Δx (N = 4096, paper resolution ≈ l_p/10) and Δx/2
//! (N = 8192), at the same c_s Δt/Δx.

use crate::spectral_common::{center_crack, center_crack_a, f, mean_tip_speed, onset_time, run, scene};

const TOL_RESOLUTION_REL: f64 = 0.01; // < 1 % change between Δx and Δx/2; not tuned

#[test]
fn onset_and_speed_converged_in_grid_spacing() {
    let coarse = center_crack(0.0);
    let fine = run(&scene(
        "center-crack",
        &[
            f("friction.friction_coeff", 0.0),
            ("spectral.grid_points", Some(toml::Value::Integer(8192))),
        ],
    ));
    let (o1, o2) = (
        onset_time(coarse, center_crack_a()).expect("onset"),
        onset_time(&fine, center_crack_a()).expect("onset"),
    );
    let (v1, v2) = (mean_tip_speed(coarse), mean_tip_speed(&fine));
    println!(
        "Δx = {:.3e} m: onset {o1:.6e} s, mean speed (2a→6a) {v1:.3} m/s; Δx/2: onset {o2:.6e} s, mean speed {v2:.3} m/s; changes {:+.3} %, {:+.3} %",
        coarse.grid_spacing,
        100.0 * (o2 / o1 - 1.0),
        100.0 * (v2 / v1 - 1.0)
    );
    assert!(
        (o2 / o1 - 1.0).abs() < TOL_RESOLUTION_REL,
        "onset changed by more than 1 %"
    );
    assert!(
        (v2 / v1 - 1.0).abs() < TOL_RESOLUTION_REL,
        "mean tip speed changed by more than 1 %"
    );
}
