//! Paper Section 4 — a crack along a sinusoidal weak interface, then into a planar strong one —
//! at paper resolution (750 × 250 elements, h = δ_c, T = 0.06 s), run once with the
//! standard model (contact through the cohesive law, eq. 4) and once with the hybrid model
//! (node-to-segment contact). Every claim of the two runs is asserted in one test, and every
//! measured figure is printed first.

use compare::quasi_static::LIMIT as MAX_KINETIC_OVER_INTERNAL;
use compare::sinusoid::metrics::{SinusoidSummary, mean_residual_stress, summarise};
use validation::{scene_text, with_overrides};

// The KKT claims (docs/cases.md, decisions after measurement). The hybrid model satisfies the
// contact conditions: its share of crack-face nodes carrying a compressive traction while open is
// at most 1 % throughout. Contact zone (true distance < 0) against traction zone (compressive
// traction > 0): they differ exactly where the conditions fail in either direction, so the same
// 1 % bound. The standard model violates them measurably (paper Figure 11 in numbers): a largest
// violating share of at least 2 % (the spurious opening of a frozen pair grows like κ s²/2, so a
// fixed larger share is a property of the path, not of the method), a compressive traction of at
// least σ_c of the strong interface on an open node, and contact and traction zones differing on
// at least 5 % of the crack-face nodes. Not tuned.
const MAX_HYBRID_KKT_SHARE: f64 = 0.01;
const MAX_HYBRID_ZONE_MISMATCH: f64 = 0.01;
const MIN_STANDARD_KKT_SHARE: f64 = 0.02;
const MIN_STANDARD_ZONE_MISMATCH: f64 = 0.05;
const TOL_BALANCE_REL: f64 = 0.01; // energy residual < 1 % of the boundary work, as for the centre crack; not tuned

fn run(model: &str) -> (fem::Scene, fem::RunOutput, f64) {
    let text = with_overrides(
        &scene_text("sinusoidal-interface"),
        &[("fem.model", Some(toml::Value::String(model.to_string())))],
    );
    let scene = fem::Scene::from_toml_str(&text).unwrap();
    let started = std::time::Instant::now();
    let out = fem::run(&scene).unwrap_or_else(|e| panic!("{model} run: {e}"));
    (scene, out, started.elapsed().as_secs_f64())
}

fn worst_balance(out: &fem::RunOutput) -> f64 {
    out.energy
        .iter()
        .filter(|e| e.boundary_work > 0.0)
        .map(|e| (e.residual / e.boundary_work).abs())
        .fold(0.0, f64::max)
}

fn report(s: &SinusoidSummary, out: &fem::RunOutput, wall: f64, a: f64) {
    println!(
        "{:>8}: wall {wall:.1} s ({} steps); max KKT share {:.4}; slip > 2h at t/T = {:.3}, min share after {:.4}; \
         max violating traction {:.3e} Pa; max zone mismatch {:.4}; mean residual stress (t >= T/2) {:.4e} Pa, final {:.4e} Pa; \
         onset t/T = {:.3}; max E_kin/E_int from onset + 0.05 T {:.4} (whole run {:.4}); final tip {:.3} a, cz tip {:.3} a; \
         worst |residual|/W_ext {:.2e}",
        s.model,
        out.steps,
        s.max_kkt_share,
        s.t_slip_2h / 0.06,
        s.min_kkt_share_after_slip,
        s.max_violating_traction,
        s.max_zone_mismatch_share,
        s.mean_residual_stress_second_half,
        s.final_residual_stress,
        s.onset / 0.06,
        s.max_kinetic_over_internal_quasi_static,
        s.max_kinetic_over_internal,
        s.final_tip_right / a,
        s.final_cz_tip_right / a,
        worst_balance(out),
    );
}

fn run_both() -> (
    SinusoidSummary,
    fem::RunOutput,
    SinusoidSummary,
    fem::RunOutput,
    f64,
) {
    let (scene, std_out, std_wall) = run("standard");
    let (_, hyb_out, hyb_wall) = run("hybrid");
    let (a, h, t_end) = (scene.half_length(), scene.fem.element_size, scene.duration());
    let std_s = summarise("standard", &std_out, a, h, t_end);
    let hyb_s = summarise("hybrid", &hyb_out, a, h, t_end);
    report(&std_s, &std_out, std_wall, a);
    report(&hyb_s, &hyb_out, hyb_wall, a);
    (std_s, std_out, hyb_s, hyb_out, a)
}

#[test]
fn standard_against_hybrid_on_the_sinusoidal_interface() {
    let (std_s, std_out, hyb_s, hyb_out, a) = run_both();
    // the chosen loading does what the case asks (docs/cases.md): the weak interface cracks fully (right branch,
    // the one eq. 17 integrates), its faces touch behind the tip, and the crack enters the
    // strong interface by more than its process zone (l_p^s = 0.08a)
    let junction = 2.5 * a;
    for (s, out) in [(&std_s, &std_out), (&hyb_s, &hyb_out)] {
        assert!(
            s.final_tip_right > junction + 0.08 * a,
            "{}: crack did not propagate into the strong interface",
            s.model
        );
        assert!(
            out.kkt.iter().any(|r| r.compressive_nodes > 0),
            "{}: faces never in contact",
            s.model
        );
    }
    assert!(
        worst_balance(&hyb_out) < TOL_BALANCE_REL,
        "hybrid: energy balance"
    );
    // paper §4.2: the weak interface starts damaging first (the strong one only once the crack
    // gets there)
    for (s, out) in [(&std_s, &std_out), (&hyb_s, &hyb_out)] {
        let first = |weak: bool| {
            out.arrivals
                .iter()
                .filter(|r| (r.x.abs() > junction) != weak && r.x.abs() > a)
                .map(|r| r.insertion_time)
                .filter(|t| t.is_finite())
                .fold(f64::INFINITY, f64::min)
        };
        println!(
            "{}: first insertion on the weak interface t/T = {:.4}, on the strong interface t/T = {:.4}",
            s.model,
            first(true) / 0.06,
            first(false) / 0.06
        );
        assert!(
            first(true) < first(false),
            "{}: the strong interface damaged first",
            s.model
        );
    }
    assert!(
        hyb_s.max_kkt_share <= MAX_HYBRID_KKT_SHARE,
        "hybrid KKT-violation share {} > {MAX_HYBRID_KKT_SHARE}",
        hyb_s.max_kkt_share
    );
    assert!(
        hyb_s.max_zone_mismatch_share <= MAX_HYBRID_ZONE_MISMATCH,
        "hybrid contact and traction zones differ on {} of the crack-face nodes",
        hyb_s.max_zone_mismatch_share
    );
    assert!(std_s.t_slip_2h.is_finite(), "standard: the faces never slid 2h");
    // the standard model violates the KKT conditions (paper Figure 11a)
    let sigma_c_strong = 0.4e6; // Pa, σ_c of the strong interface (the scene's [interface])
    assert!(
        std_s.max_kkt_share >= MIN_STANDARD_KKT_SHARE,
        "standard KKT-violation share {} < {MIN_STANDARD_KKT_SHARE}",
        std_s.max_kkt_share
    );
    assert!(
        std_s.max_violating_traction >= sigma_c_strong,
        "standard: largest traction on an open node {} Pa < σ_c^s",
        std_s.max_violating_traction
    );
    assert!(
        std_s.max_zone_mismatch_share >= MIN_STANDARD_ZONE_MISMATCH,
        "standard: contact and traction zones differ on only {} of the nodes",
        std_s.max_zone_mismatch_share
    );
    // paper App. B in the phase its Figure B.14b treats as quasi-static: from 0.05 T after the
    // onset to T (the weak process zone fails at once at the onset; before it the imposed motion
    // itself carries E_kin/E_int ≈ (a²/3c²)(σ̇/σ)², which diverges as t → 0)
    assert!(
        hyb_s.max_kinetic_over_internal_quasi_static <= MAX_KINETIC_OVER_INTERNAL,
        "hybrid: E_kin/E_int reaches {} between onset + 0.05 T and T",
        hyb_s.max_kinetic_over_internal_quasi_static
    );
    // paper Figure 12: residual stress while the crack is arrested at the strong interface with
    // its weak faces in contact — from the later of the two "weak branch cracked" times to the
    // earlier of the two "entered the strong interface" times (later, the standard run is no
    // longer energy-consistent: docs/results.md)
    let t0 = std_s.t_weak_cracked.max(hyb_s.t_weak_cracked);
    let t1 = std_s.t_strong_entered.min(hyb_s.t_strong_entered);
    let (rs_std, rs_hyb) = (
        mean_residual_stress(&std_out, t0, t1),
        mean_residual_stress(&hyb_out, t0, t1),
    );
    println!(
        "arrest phase t/T = {:.3} .. {:.3}: mean residual stress standard {rs_std:.4e} Pa, hybrid {rs_hyb:.4e} Pa",
        t0 / 0.06,
        t1 / 0.06
    );
    assert!(
        t1 > t0,
        "no arrest phase: the crack never paused at the strong interface"
    );
    assert!(
        rs_std > rs_hyb,
        "residual stress: standard {rs_std} <= hybrid {rs_hyb}"
    );
    // paper §4.2 and Appendix E (Figure E.16): the standard model's wrong contact tractions
    // resist the shear more, so the hybrid crack enters the strong interface earlier, i.e. at a
    // lower far-field shear. A sign, no tolerance.
    println!(
        "crack tip past 2.58a (entered the strong interface): standard t/T = {:.4}, hybrid t/T = {:.4}",
        std_s.t_strong_entered / 0.06,
        hyb_s.t_strong_entered / 0.06
    );
    assert!(
        hyb_s.t_strong_entered < std_s.t_strong_entered,
        "hybrid did not enter the strong interface first"
    );
}
