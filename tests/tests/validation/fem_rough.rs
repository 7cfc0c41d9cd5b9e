//! Beyond the paper (its Section 5 outlook): a crack along a self-affine rough weak interface
//! (`fem.interface_rough`), standard against hybrid model, on the small scene
//! `tiny-fem-rough-interface` (the full scene's box, laws and loading at h = 5 mm: a few seconds
//! for both runs). The claims of paper Section 4 that do not depend on the path's shape: the
//! hybrid model satisfies the contact (KKT) conditions and closes its energy balance, the
//! standard model violates them once the rough faces slide.

use compare::sinusoid::metrics::{SinusoidSummary, summarise};
use validation::{scene_text, with_overrides, worst_energy_residual};

// The bounds of the Section 4 test (fem_sinusoid), which do not depend on the path's shape, and
// are not tuned here. The hybrid model's contact is node-to-segment with its own penalty, so an
// open crack-face node carries no compressive traction and contact and traction zones coincide:
// at most 1 % of the crack-face nodes may do otherwise (measured 0 and 0.66 % at this size, 0 and
// 0.13 % on the 1 mm mesh of scenes/rough-interface.toml). The standard model's frozen facet
// pairs (paper eq. 4) push while open once the faces slide over the asperities: its violating
// share must reach 2 % and its zone mismatch 5 % (measured 9.2 % and 19.1 % at this size, 10.1 %
// and 15.1 % on the 1 mm mesh), so the comparison cannot pass with both models alike.
const MAX_HYBRID_KKT_SHARE: f64 = 0.01;
const MAX_HYBRID_ZONE_MISMATCH: f64 = 0.01;
const MIN_STANDARD_KKT_SHARE: f64 = 0.02;
const MIN_STANDARD_ZONE_MISMATCH: f64 = 0.05;
// Energy residual < 1 % of the boundary work, as for the centre crack and the sinusoid; not tuned
// (measured 0.45 % for the hybrid model; the standard model's frozen pairs create energy once
// slid, 424 % here, which is printed, not asserted: it is a finding, not a claim).
const TOL_BALANCE_REL: f64 = 0.01;

fn run(model: &str) -> (fem::Scene, fem::RunOutput, f64) {
    let text = with_overrides(
        &scene_text("tiny-fem-rough-interface"),
        &[("fem.model", Some(toml::Value::String(model.to_string())))],
    );
    let scene = fem::Scene::from_toml_str(&text).unwrap();
    let started = std::time::Instant::now();
    let out = fem::run(&scene).unwrap_or_else(|e| panic!("{model} run: {e}"));
    (scene, out, started.elapsed().as_secs_f64())
}

fn summary(model: &str) -> (SinusoidSummary, fem::RunOutput) {
    let (scene, out, wall) = run(model);
    let (a, h, t_end) = (scene.half_length(), scene.fem.element_size, scene.duration());
    let s = summarise(model, &out, a, h, t_end);
    let (worst, w_final) = worst_energy_residual(&out);
    println!(
        "{model:>8}: wall {wall:.1} s ({} steps); max KKT share {:.4}; max zone mismatch {:.4}; \
         max violating traction {:.3e} Pa; largest twin slip {:.2} h; onset t/T = {:.3}; weak branch cracked \
         t/T = {:.3}; final tip {:.3} a; worst |residual|/W_ext {worst:.2e} (W_ext {w_final:.3e} J/m)",
        out.steps,
        s.max_kkt_share,
        s.max_zone_mismatch_share,
        s.max_violating_traction,
        out.kkt.iter().map(|r| r.max_slip).fold(0.0, f64::max) / h,
        s.onset / t_end,
        s.t_weak_cracked / t_end,
        s.final_tip_right / a,
    );
    (s, out)
}

#[test]
fn on_a_rough_interface_the_hybrid_model_keeps_the_contact_conditions_and_the_standard_one_does_not() {
    let (std_s, std_out) = summary("standard");
    let (hyb_s, hyb_out) = summary("hybrid");
    // the scene does what the comparison needs: in both models the crack runs the whole weak
    // branch (past 2.4a; it ends at 2.48a) and the rough faces touch behind the tip
    for (s, out) in [(&std_s, &std_out), (&hyb_s, &hyb_out)] {
        assert!(
            s.t_weak_cracked.is_finite(),
            "{}: the weak branch did not crack",
            s.model
        );
        assert!(
            out.kkt.iter().any(|r| r.compressive_nodes > 0),
            "{}: faces never in contact",
            s.model
        );
    }
    let (worst, _) = worst_energy_residual(&hyb_out);
    assert!(
        worst < TOL_BALANCE_REL,
        "hybrid: energy residual {worst} of the boundary work"
    );
    assert!(
        hyb_s.max_kkt_share <= MAX_HYBRID_KKT_SHARE,
        "hybrid KKT-violation share {} > {MAX_HYBRID_KKT_SHARE}",
        hyb_s.max_kkt_share
    );
    assert!(
        std_s.max_kkt_share >= MIN_STANDARD_KKT_SHARE,
        "standard KKT-violation share {} < {MIN_STANDARD_KKT_SHARE}",
        std_s.max_kkt_share
    );
    assert!(
        hyb_s.max_zone_mismatch_share <= MAX_HYBRID_ZONE_MISMATCH,
        "hybrid contact/traction zone mismatch {} > {MAX_HYBRID_ZONE_MISMATCH}",
        hyb_s.max_zone_mismatch_share
    );
    assert!(
        std_s.max_zone_mismatch_share >= MIN_STANDARD_ZONE_MISMATCH,
        "standard contact/traction zone mismatch {} < {MIN_STANDARD_ZONE_MISMATCH}",
        std_s.max_zone_mismatch_share
    );
}
