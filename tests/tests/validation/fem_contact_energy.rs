//! An energy audit of contact that can fail on bad contact. The energy balance sums the contact
//! and friction work from the same forces the solver applies, so it checks the time integration
//! only. These checks compare the applied forces with quantities computed independently from the
//! geometry:
//! - frictionless contact is conservative: the work done by the contact forces, W_con, is the
//!   negative of the energy stored in the penalty springs, Σ w A ½ ε_n p², at every sample, so
//!   over every loading–unloading cycle the net contact work returns to the change of stored
//!   energy;
//! - friction dissipates: at every slave, the work done against the friction traction on the
//!   actual (kinematic) slip is never negative, and over a long slide it equals the Coulomb bound
//!   ∫ μ p_N |v_slip| dt.
//!
//! A contact force that is not conservative fails the first (the fem crate's unit test
//! `a_non_conservative_penalty_fails_the_audit` injects one).

use validation::{scene_text, with_overrides};

// Frictionless pressed blocks under a step pressure: the stack rings, the contact loads and
// unloads through every cycle. |W_con + E_stored| stays below 1 % of the largest stored energy:
// the integration error, second order in Δt (measured below: it falls 4× per halving of Δt); a
// penalty halved while its springs are loaded (the fem crate's injected fault) misses by 3.4e-2.
// Not tuned.
const TOL_CONSERVATION: f64 = 0.01;
// Friction: no slave returns more than 1e-3 of the largest slave's work (round-off and the
// elastic part of the regularised law); the total over the 20 h slide is the Coulomb bound within
// 2 % (the elastic slip of the regularised law, Δs − Δs_p, is counted in the bound but stored,
// not dissipated, once per stick phase). Not tuned.
const TOL_NEGATIVE_WORK: f64 = 1e-3;
const TOL_COULOMB_REL: f64 = 0.02;

fn step_pressure(alpha: f64) -> fem::RunOutput {
    let step: toml::Table =
        "kind = 'traction'\ninitial = 0.0\nfinal = -0.05e6\nramp_start = 0.0\nramp_end = 0.0"
            .parse()
            .unwrap();
    let text = with_overrides(
        &scene_text("tiny-fem-contact-pressure"),
        &[
            ("fem.boundary.top.y", Some(toml::Value::Table(step))),
            ("fem.time_step_safety", Some(toml::Value::Float(alpha))),
            ("fem.output_interval", Some(toml::Value::Float(1e-5))),
        ],
    );
    fem::run(&fem::Scene::from_toml_str(&text).unwrap()).unwrap()
}

#[test]
fn frictionless_contact_returns_what_it_stores() {
    let errors: Vec<f64> = [0.5, 0.25]
        .into_iter()
        .map(|alpha| {
            let out = step_pressure(alpha);
            let e = out.contact_conservation_error();
            let unloaded = out
                .energy
                .windows(3)
                .filter(|w| w[1].contact_stored < w[0].contact_stored && w[1].contact_stored < w[2].contact_stored)
                .count();
            println!(
                "alpha = {alpha}: max |W_con + E_stored| / max E_stored = {e:.3e} over {} samples, {unloaded} unloading minima",
                out.energy.len()
            );
            assert!(unloaded >= 5, "the contact must load and unload repeatedly");
            e
        })
        .collect();
    println!(
        "ratio for half the step: {:.2} (second order: 4)",
        errors[0] / errors[1]
    );
    assert!(errors[0] <= TOL_CONSERVATION && errors[1] <= TOL_CONSERVATION);
    assert!(
        errors[0] / errors[1] > 3.0,
        "the error must be the integration error"
    );
}

#[test]
fn friction_never_returns_energy_and_dissipates_the_coulomb_bound() {
    let out = fem::run(&fem::Scene::from_toml_str(&scene_text("tiny-fem-contact-sliding")).unwrap()).unwrap();
    assert!(!out.friction.is_empty(), "friction must act");
    let largest = out.friction.iter().map(|r| r.friction_work).fold(0.0, f64::max);
    let most_negative = out.friction.iter().map(|r| r.friction_work).fold(0.0, f64::min);
    let work: f64 = out.friction.iter().map(|r| r.friction_work).sum();
    let bound: f64 = out.friction.iter().map(|r| r.coulomb_work).sum();
    let booked = out.energy.last().unwrap().friction_dissipated;
    println!(
        "{} slaves: most negative work {most_negative:.3e} J/m against the largest {largest:.3e} J/m; \
         total work against friction {work:.5e} J/m, Coulomb bound {bound:.5e} J/m ({:+.3} %), booked \
         dissipation {booked:.5e} J/m ({:+.3} %)",
        out.friction.len(),
        100.0 * (work / bound - 1.0),
        100.0 * (booked / bound - 1.0)
    );
    assert!(most_negative >= -TOL_NEGATIVE_WORK * largest);
    assert!((work / bound - 1.0).abs() <= TOL_COULOMB_REL);
    assert!((booked / bound - 1.0).abs() <= TOL_COULOMB_REL);
}
