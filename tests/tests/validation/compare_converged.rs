//! The FE–spectral onset agreement once the FE model has converged (docs/cases.md, decisions
//! after measurement): the comparison of `compare converged`, FE at h = 0.5 mm (1000 × 500
//! elements), spectral on N = 8192 points at the FE step, both friction values, the paper's hybrid
//! friction rule in both models. The onsets must agree within 0.01 T (at the paper's h = 1 mm the
//! gate allows 0.015 T: the FE onset is still 0.005 T from converged there); the other metrics
//! keep the gate's tolerances, except the one whose decision is open (below).

use compare::converged::{ConvergedRow, run_converged};
use compare::runner::Silent;
use compare::study::Study;
use validation::{reference_rows, repo_root};

// The metrics that fail and whose decision is open (docs/cases.md, decision 5): with the paper's
// hybrid friction rule in both models the μ = 0.3 tip positions drift 0.056a apart from a common
// origin (limit 0.05a). CI runs the comparison with the same list (`--open`). Every other metric
// must pass, and these must still fail: a change that makes one pass removes it from both lists.
const OPEN: [&str; 1] = ["tip_position_rms_over_a@0.3"];

// The committed result (reference/center-crack-converged.csv) must be what this code produces:
// onsets and mean speeds equal to 1e-6 relative (a summation-order change moves them by ~1e-12;
// a change of the physics, by far more). Not tuned.
const TOL_REPRODUCED_REL: f64 = 1e-6;

#[test]
fn onsets_agree_within_a_hundredth_of_t_once_the_fe_model_has_converged() {
    let study = Study::load(&repo_root().join("scenes/center-crack.toml")).unwrap();
    let dir = std::env::temp_dir().join(format!("validation-converged-{}", std::process::id()));
    let report = run_converged(&study, &dir, &Silent).unwrap();
    for v in &report.gate.verdicts {
        println!(
            "{:<38} mu = {:<6} {:.5} ({}) {}",
            v.metric,
            v.mu,
            v.value,
            v.tolerance,
            if v.pass { "pass" } else { "FAIL" }
        );
    }
    let committed: Vec<ConvergedRow> = reference_rows("center-crack-converged.csv");
    for r in &report.rows {
        println!(
            "mu = {}: FE onset {:.6} s, spectral onset {:.6} s, difference {:.5} T; mean speeds {:.2} / {:.2} m/s",
            r.mu,
            r.fem_onset,
            r.spectral_onset,
            r.onset_difference_over_t,
            r.fem_mean_speed,
            r.spectral_mean_speed
        );
        let c = committed
            .iter()
            .find(|c| c.mu == r.mu)
            .expect("the reference has every μ");
        for (new, old) in [
            (r.fem_onset, c.fem_onset),
            (r.spectral_onset, c.spectral_onset),
            (r.fem_mean_speed, c.fem_mean_speed),
            (r.spectral_mean_speed, c.spectral_mean_speed),
        ] {
            assert!(
                (new - old).abs() <= TOL_REPRODUCED_REL * old.abs(),
                "mu = {}: {new} against the committed {old}; regenerate the reference with \
                 `compare converged` if the physics changed on purpose",
                r.mu
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    let failing: Vec<String> = report
        .gate
        .verdicts
        .iter()
        .filter(|v| !v.pass)
        .map(|v| format!("{}@{}", v.metric, v.mu))
        .collect();
    assert_eq!(
        failing, OPEN,
        "the failing metrics at h = 0.5 mm are not the open ones"
    );
}
