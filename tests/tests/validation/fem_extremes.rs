//! Stability at the extremes: the FE model on the small centre crack
//! (scenes/tiny-fem-center-crack.toml: every feature of the paper's case — pre-crack contact
//! with friction, cohesive insertion, Westergaard boundary field — on 40 × 20 elements) with
//! penalties from 1 to 10,000 E per metre, elements smaller than δ_c, μ = 1 and a time step at
//! 0.95 of the stable estimate. Each run must finish without NaN and close its energy balance;
//! interpenetration must fall as ε_n grows; bad steps and bad geometry are refused.

use validation::{scene_text, with_overrides};

const TOL_BALANCE_REL: f64 = 0.01; // energy residual < 1 % of W_ext (docs/fem-model.md §8.3); not tuned
const YOUNGS_MODULUS: f64 = 70e6; // Pa, the tiny scene's [material]

fn float(v: f64) -> Option<toml::Value> {
    Some(toml::Value::Float(v))
}

fn run(label: &str, overrides: &[(&str, Option<toml::Value>)]) -> fem::RunOutput {
    let text = with_overrides(&scene_text("tiny-fem-center-crack"), overrides);
    let scene = fem::Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{label}: {e}"));
    let out = fem::run(&scene).unwrap_or_else(|e| panic!("{label}: the run must finish: {e}"));
    check_sane(label, &out);
    out
}

/// No NaN anywhere in the records, and |residual| ≤ 1 % of W_ext at every sample once the
/// boundary has done measurable work (before that the ratio is 0/0).
fn check_sane(label: &str, out: &fem::RunOutput) {
    let finite_energy = out.energy.iter().all(|e| {
        [
            e.kinetic,
            e.strain,
            e.cohesive,
            e.boundary_work,
            e.residual,
            e.contact_work,
        ]
        .iter()
        .all(|v| v.is_finite())
    });
    let finite_tips = out
        .tips
        .iter()
        .all(|r| r.tip_right.is_finite() && r.tip_left.is_finite());
    assert!(finite_energy && finite_tips, "{label}: non-finite records");
    let (worst, w_final) = validation::worst_energy_residual(out);
    assert!(
        w_final > 0.0,
        "{label}: the boundary must do work, W_ext = {w_final}"
    );
    println!(
        "{label}: worst |residual|/W_ext = {worst:.2e} (tol {TOL_BALANCE_REL}), W_ext(T) = {w_final:.3e} J/m"
    );
    assert!(
        worst < TOL_BALANCE_REL,
        "{label}: energy residual {worst:.3e} of W_ext"
    );
}

fn max_penetration(out: &fem::RunOutput) -> f64 {
    out.contact.iter().map(|c| c.max_penetration).fold(0.0, f64::max)
}

#[test]
fn penalties_from_one_to_ten_thousand_e_per_metre_run_and_penetration_falls() {
    let mut pens = Vec::new();
    for factor in [1.0, 300.0, 10_000.0] {
        let eps = factor * YOUNGS_MODULUS;
        let label = format!("eps_n = {factor} E/m");
        let out = run(
            &label,
            &[
                ("fem.eps_n", float(eps)),
                ("fem.eps_t", float(eps)),
                ("fem.time_step", None),
            ],
        );
        let p = max_penetration(&out);
        println!(
            "{label}: time step {:.3e} s, max penetration {p:.3e} m",
            out.time_step
        );
        pens.push(p);
    }
    assert!(
        pens[0] > pens[1] && pens[1] > pens[2],
        "penetration must fall as eps_n grows: {pens:?}"
    );
}

#[test]
fn elements_smaller_than_the_critical_opening() {
    // h = 1 mm = δ_c/2; σ_c lowered to keep G_c = σ_c δ_c/2 = 40 J/m² so the crack still runs.
    let out = run(
        "h = delta_c/2",
        &[
            ("interface.delta_c", float(2e-3)),
            ("interface.sigma_c", float(0.04e6)),
        ],
    );
    let inserted = out.interface.iter().filter(|r| r.inserted).count();
    assert!(
        inserted > 0,
        "cohesive elements must be inserted for the case to mean anything"
    );
}

#[test]
fn friction_coefficient_one() {
    run("mu = 1", &[("friction.friction_coeff", float(1.0))]);
}

/// The small scene at α = 0.95. Its 0.1 ms normal ramp is 1.5 wave transits of the 20 mm block:
/// an impact rather than a quasi-static load, the hardest start for the energy balance. Measured:
/// worst |residual|/W_ext = 9.1e-3 at t = 0.46 ms (the crack run); 1.4e-3 at α = 0.5. The
/// residual at the end of the ramp converges as Δt² (2.0e-5, 5.4e-6, 1.1e-6 J/m at α = 0.95, 0.5,
/// 0.25): see `reactions` in fem/src/solver/central_difference.rs.
#[test]
fn time_step_at_095_of_the_stable_estimate_small_scene() {
    let out = run(
        "alpha = 0.95 (small scene)",
        &[("fem.time_step_safety", float(0.95))],
    );
    println!("alpha = 0.95: time step {:.3e} s", out.time_step);
}

/// The paper's centre crack (500 × 250 elements, μ = 0.3) at α = 0.95: finishes, no NaN,
/// energy residual under 1 % of the boundary work (measured 4.3e-3, ~20 s).
#[test]
fn time_step_at_095_of_the_stable_estimate_paper_case() {
    let text = with_overrides(
        &scene_text("center-crack"),
        &[("fem.time_step_safety", float(0.95))],
    );
    let scene = fem::Scene::from_toml_str(&text).unwrap();
    let out =
        fem::run(&scene).unwrap_or_else(|e| panic!("alpha = 0.95, paper case: the run must finish: {e}"));
    println!("alpha = 0.95, paper case: time step {:.3e} s", out.time_step);
    check_sane("alpha = 0.95, paper case", &out);
}

#[test]
fn a_time_step_above_the_stable_limit_is_refused_with_the_limit() {
    let base = fem::Scene::from_toml_str(&scene_text("tiny-fem-center-crack")).unwrap();
    let limit = base.stable_limit();
    let text = with_overrides(
        &scene_text("tiny-fem-center-crack"),
        &[
            ("fem.time_step_safety", None),
            ("fem.time_step", float(1.01 * limit)),
        ],
    );
    let err = fem::Scene::from_toml_str(&text).expect_err("a step above the limit must be refused");
    let msg = err.to_string();
    println!("{msg}");
    assert!(
        msg.contains("stable limit") && msg.contains(&format!("{limit}")),
        "{msg}"
    );
}

#[test]
fn a_mesh_that_does_not_fit_the_geometry_is_refused() {
    let text = scene_text("tiny-fem-center-crack");
    let cases: [(&str, Option<toml::Value>, &str); 2] = [
        ("fem.element_size", float(1.5e-3), "fem.element_size"),
        ("crack.half_length", float(0.0105), "crack tip"),
    ];
    for (key, value, expected) in cases {
        let err = fem::Scene::from_toml_str(&with_overrides(&text, &[(key, value)]))
            .expect_err("inconsistent geometry must be refused");
        let msg = err.to_string();
        println!("{key}: {msg}");
        assert!(msg.contains(expected), "{key}: {msg}");
    }
}
