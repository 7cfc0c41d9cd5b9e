//! Conditions on the physical points of a Gmsh mesh (`[fem.boundary.NAME]` on a point): a beam in
//! three-point bending (`meshes/beam.msh`, `scenes/tiny-fem-beam-bending.toml`), 0.9 m × 0.1 m on
//! a pin and a roller 0.8 m apart, a point force of 1 kN/m at the top's middle ramped over 4.5
//! periods of the first bending mode and then held. In the held phase (t ≥ 0.26 s, 1.8 periods):
//! 1. the mid-span deflection is that of Timoshenko's beam theory;
//! 2. the supports carry the force (`boundary.csv`'s reactions), half each: the force acts at the
//!    point's node and nowhere else;
//! 3. the energy balance closes with the point force's work in W_ext.

use validation::{shared_repo_run, worst_energy_residual};

const SCENE: &str = "tiny-fem-beam-bending";
/// The held phase: from 0.01 s after the ramp's end to the end of the run [s].
const HOLD_FROM: f64 = 0.26;
/// Span [m], depth [m] and the point force [N/m] of the scene.
const SPAN: f64 = 0.8;
const DEPTH: f64 = 0.1;
const FORCE: f64 = 1000.0;

/// Mean over the held phase of `value` of the records of `part` in `boundary.csv`.
fn held_mean(out: &fem::RunOutput, part: &str, value: impl Fn(&fem::BoundaryRecord) -> f64) -> f64 {
    let k = out
        .boundary_parts
        .iter()
        .position(|p| p == part)
        .unwrap_or_else(|| panic!("no part {part} in {:?}", out.boundary_parts)) as u16;
    let v: Vec<f64> = out
        .boundary
        .iter()
        .filter(|r| r.part == k && r.t >= HOLD_FROM)
        .map(value)
        .collect();
    assert!(v.len() > 50, "{} samples of {part} in the held phase", v.len());
    v.iter().sum::<f64>() / v.len() as f64
}

/// Mid-span deflection against a Timoshenko beam, simply supported, loaded at mid-span:
/// δ = F S³/(48 E' I) + F S/(4 κ G d), I = d³/12, plane strain E' = E/(1 − ν²), κ = 5/6.
///
/// Tolerance 2.5 %. Beam theory leaves out the 2D fields under the point load and at the point
/// supports (of order (d/S)² and (d/S)³ of the deflection; here (d/S)² = 1.6 %), and the
/// triangles are a little stiff in bending. Measured −1.78 % on this mesh (h = 2.5 mm at
/// mid-span); −1.38 % on the same `.geo` with every size halved (41 k triangles): the 2D solution
/// lies about 1.0–1.3 % below beam theory (extrapolating at first or second order in h) and this
/// mesh adds about 0.5 %. A force at another node, of another size or counted twice is off by far
/// more than 2.5 % (twice: +100 %).
#[test]
fn a_point_force_bends_the_beam_as_beam_theory_predicts() {
    let (scene, out) = shared_repo_run(SCENE);
    let (e, nu) = (scene.material.youngs_modulus, scene.material.poisson_ratio);
    let e_plane = e / (1.0 - nu * nu); // Pa
    let g = e / (2.0 * (1.0 + nu)); // Pa
    let bending = FORCE * SPAN.powi(3) / (4.0 * e_plane * DEPTH.powi(3)); // F S³/(48 E' d³/12), m
    let shear = FORCE * SPAN / (4.0 * (5.0 / 6.0) * g * DEPTH); // m
    let held: Vec<f64> = out
        .probes
        .iter()
        .filter(|p| p.t >= HOLD_FROM)
        .map(|p| p.uy)
        .collect();
    let deflection = -held.iter().sum::<f64>() / held.len() as f64; // m
    let rel = deflection / (bending + shear) - 1.0;
    println!(
        "mid-span deflection {deflection:.5e} m, Timoshenko {:.5e} m (bending {bending:.5e}, shear \
         {shear:.5e}): {:+.2} %",
        bending + shear,
        100.0 * rel
    );
    assert!(
        rel.abs() <= 0.025,
        "deflection off beam theory by {:+.2} %",
        100.0 * rel
    );
}

/// The supports' reactions balance the point force, half each.
///
/// - Sum: tolerance 0.5 % of F. In the held phase the beam still rings at ±0.45 % of its
///   deflection, so the inertia it takes from the supports is of that order; averaged over the
///   phase it is less (measured −0.07 %).
/// - Split: R_right − R_left = F x/(S/2) for a force at x, so |R_right − R_left| ≤ 1e-3 F places
///   the force within 0.4 mm of mid-span, less than a sixth of the 2.5 mm elements there (the
///   unstructured mesh is not symmetric; measured 3e-5).
/// - The pin's horizontal reaction: nothing pulls along the beam; ≤ 1e-3 F (measured 2.6e-4).
#[test]
fn the_supports_carry_the_point_force_half_each() {
    let (_, out) = shared_repo_run(SCENE);
    let load = held_mean(out, "load", |r| r.fy);
    let left = held_mean(out, "support_left", |r| r.fy);
    let right = held_mean(out, "support_right", |r| r.fy);
    let pin_x = held_mean(out, "support_left", |r| r.fx);
    println!("load {load:.3} N/m, reactions {left:.3} + {right:.3} N/m, pin x {pin_x:.3e} N/m");
    assert_eq!(load, -FORCE, "the load part reports the force applied");
    let sum = (left + right + load) / FORCE;
    assert!(
        sum.abs() <= 5e-3,
        "reactions off the force by {:+.3} %",
        100.0 * sum
    );
    let split = (right - left) / FORCE;
    assert!(split.abs() <= 1e-3, "reactions split unevenly: {split:+.2e} F");
    assert!(
        (pin_x / FORCE).abs() <= 1e-3,
        "horizontal reaction {pin_x:.3e} N/m"
    );
}

/// The energy balance closes with the point force's work in W_ext: |residual| < 1 % of W_ext,
/// the threshold of the other FE tests (measured below).
#[test]
fn the_point_force_work_closes_the_energy_balance() {
    let (_, out) = shared_repo_run(SCENE);
    let (worst, w) = worst_energy_residual(out);
    println!("W_ext {w:.4e} J/m, worst |residual|/W_ext {worst:.2e}");
    assert!(w > 0.0, "the force must do work");
    assert!(worst < 0.01, "energy residual {worst:.2e} of W_ext");
}
