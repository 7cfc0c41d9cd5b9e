//! Absorbing boundaries (docs/fem-model.md §7): viscous dashpots, ρc_d on the normal and ρc_s on
//! the tangential velocity (Lysmer & Kuhlemeyer 1969), let a plane wave at normal incidence out
//! of the body. The P and S pulses of the wave-speed test (`tiny-fem-plate`: a smooth displacement
//! ramp on the left side, rollers on top and bottom) run into the right side, made absorbing.
//!
//! The reflection is measured at a probe 50 mm before that side as the difference between this
//! run and the same run in a plate twice as long, where nothing comes back within the run: the
//! difference is the reflected wave alone, without the grid's dispersion tail of the incident
//! pulse. Its peak over the incident pulse's peak velocity is the reflection coefficient.
//! The same measurement with the right side free must find a full reflection, so that the test
//! can fail. The energy balance must close with the absorbed work included.

use crate::fem_wave_speeds::{P_BOUNDARY, S_BOUNDARY};
use validation::{scene_text, with_overrides};

/// The analytic reflection at normal incidence is 0; the bound, stated before measuring:
/// less than 2 % of the incident amplitude (what is left is the lumped dashpot's discretisation
/// error and the corner nodes, whose held component has no dashpot).
const TOL_REFLECTION: f64 = 0.02;

/// A free end reflects a plane wave whole (velocity doubled at the end, the reflected pulse as large
/// as the incident one): the measurement must see at least this much of it.
const FREE_END_REFLECTION_MIN: f64 = 0.9;

/// Energy balance with the absorbed work, relative to the work put in, once the pulse has left:
/// the plate's O(Δt²) residual, with a margin; a missing or misbooked absorbed work would leave a
/// residual of the order of the whole W_ext.
const TOL_BALANCE_REL: f64 = 1e-3;

fn table(text: &str) -> toml::Value {
    toml::Value::Table(text.parse().expect("valid TOML table"))
}

/// Runs the plate with `boundary` (and, if `absorbing`, the right side absorbing) over
/// `x_max` [m] and `duration` [s].
fn run(boundary: &str, absorbing: bool, x_max: f64, duration: f64) -> fem::RunOutput {
    let mut b = table(boundary);
    if absorbing {
        b.as_table_mut()
            .expect("a table")
            .insert("right".into(), table("absorbing = true"));
    }
    let text = with_overrides(
        &scene_text("tiny-fem-plate"),
        &[
            ("fem.boundary", Some(b)),
            ("loading.duration", Some(toml::Value::Float(duration))),
            (
                "fem.x_range",
                Some(toml::Value::Array(vec![0.0.into(), x_max.into()])),
            ),
            ("fem.probes", Some(table("p = [[0.15, 0.0]]")["p"].clone())),
            ("fem.output_interval", Some(toml::Value::Float(1e-6))),
        ],
    );
    fem::run(&fem::Scene::from_toml_str(&text).unwrap()).unwrap()
}

/// Velocity component `c` of the probe at every sample.
fn velocity(out: &fem::RunOutput, c: usize) -> Vec<f64> {
    out.probes
        .iter()
        .map(|p| if c == 0 { p.vx } else { p.vy })
        .collect()
}

/// (reflection coefficient, reflected peak [m/s], incident peak [m/s]) of a pulse in component
/// `c` against the side at x = 0.2 m, absorbing or free.
fn reflection(boundary: &str, c: usize, duration: f64, absorbing: bool) -> (f64, f64, f64) {
    let near = velocity(&run(boundary, absorbing, 0.2, duration), c);
    let far = velocity(&run(boundary, false, 0.4, duration), c);
    assert_eq!(near.len(), far.len());
    let incident = far.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let reflected = near
        .iter()
        .zip(&far)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    (reflected / incident, reflected, incident)
}

/// P pulse (c_d = 302 m/s, 15 mm long): reaches the side at 0.66 ms and is back at the probe by
/// 0.83–0.88 ms; 1.0 ms covers it.
#[test]
fn a_plane_p_pulse_leaves_through_an_absorbing_side() {
    let (r, reflected, incident) = reflection(P_BOUNDARY, 0, 1.0e-3, true);
    println!(
        "P at normal incidence: reflected {reflected:.4e} m/s of {incident:.4e} m/s, R = {:.3} % (tol {} %)",
        100.0 * r,
        100.0 * TOL_REFLECTION
    );
    assert!(r < TOL_REFLECTION);
}

/// S pulse (c_s = 145 m/s, 14.5 mm long): back at the probe by 1.72–1.82 ms; 2.0 ms covers it.
#[test]
fn a_plane_s_pulse_leaves_through_an_absorbing_side() {
    let (r, reflected, incident) = reflection(S_BOUNDARY, 1, 2.0e-3, true);
    println!(
        "S at normal incidence: reflected {reflected:.4e} m/s of {incident:.4e} m/s, R = {:.3} % (tol {} %)",
        100.0 * r,
        100.0 * TOL_REFLECTION
    );
    assert!(r < TOL_REFLECTION);
}

/// The same measurement on a free right side sees the whole pulse come back.
#[test]
fn the_reflection_measurement_sees_a_free_end() {
    let (r, ..) = reflection(P_BOUNDARY, 0, 1.0e-3, false);
    println!("P at a free end: R = {r:.3}");
    assert!(r > FREE_END_REFLECTION_MIN);
}

/// After the P pulse has left, the plate is at rest, shifted by the ramp's 10 µm: the work the
/// left side put in is all absorbed, and the balance W_ext = E_kin + E_strain + E_abs closes.
///
/// The gate reads the end of the run. While a pulse is in flight, the measured E_kin + E_strain
/// of central differences differs from the conserved discrete energy by O((ωΔt)²): here 1.6e-3
/// of W_ext from the end of the ramp until the pulse reaches the absorbing side, as in a plate
/// without one, and it goes with the pulse. A first version of this test read the worst sample of
/// the whole run (`worst_energy_residual`) and measured 2.0e-2, at the first microseconds of the
/// ramp where W_ext is still small; the dashpots play no part there. The worst sample is printed.
#[test]
fn the_energy_balance_closes_with_the_absorbed_work() {
    let out = run(P_BOUNDARY, true, 0.2, 1.0e-3);
    let last = out.energy.last().unwrap();
    let (worst, w_ext) = validation::worst_energy_residual(&out);
    let (share, end) = (last.absorbed_work / w_ext, last.residual.abs() / w_ext);
    println!(
        "W_ext = {w_ext:.4e} J/m, E_abs = {:.4e} J/m ({share:.5} of W_ext), E_kin + E_strain left {:.3e} J/m; \
         |residual|/W_ext at the end {end:.2e} (tol {TOL_BALANCE_REL:e}), worst over the run {worst:.2e}",
        last.absorbed_work,
        last.kinetic + last.strain
    );
    assert!(end < TOL_BALANCE_REL);
    // the pulse has left the plate: what the left side put in was absorbed (the rest is the
    // grid's dispersion tail, still on its way out)
    assert!(share > 0.99, "absorbed share {share}");
}
