//! `compare` checks the whole scene — both models, every `[compare]` key, every friction value
//! and model it lists, the budgets and the output folder — before its first time step, and
//! reports every problem at once with the key and the line of the user's file. "No step ran":
//! the output folder is never created and nothing is printed on stdout.

use preflight::testing::{Trial, line_containing as line_of, scene_text as scene_in};
use std::process::Command;

fn scene_text(name: &str) -> String {
    scene_in(env!("CARGO_MANIFEST_DIR"), name)
}

fn trial(name: &str, text: &str) -> Trial {
    Trial::new(
        env!("CARGO_TARGET_TMPDIR"),
        &format!("compare-bad-input-{name}"),
        text,
    )
}

/// Runs `compare [job] --scene <text> --out <trial out> [extra]`; asserts it was refused before
/// any step and returns its stderr.
fn refused(name: &str, job: &[&str], text: &str, extra: &[&str]) -> String {
    let t = trial(name, text);
    t.refused(
        Command::new(env!("CARGO_BIN_EXE_compare"))
            .args(job)
            .arg("--scene")
            .arg(&t.scene)
            .arg("--out")
            .arg(&t.out)
            .args(extra),
    )
}

#[test]
fn problems_of_both_models_and_of_compare_are_reported_together_with_their_lines() {
    let text = scene_text("center-crack")
        .replace("poisson_ratio = 0.35 ", "poisson_ratio = 0.0 ")
        .replace(
            "friction_coeffs = [0.0, 0.3] ",
            "friction_coeffs = [0.0, 100.0]\nsnapshot_t_over_t = 0.5 ",
        )
        .replace("grid_points = 4096 ", "grid_points = 4097 ")
        .replace(
            "fast_tolerance = 1e-5 ",
            "fast_tolerance = 1e-5\nfast_tolerence = 1e-6 ",
        );
    let e = refused("together", &[], &text, &[]);
    for (message, needle) in [
        // ν = 0 is valid for the FE model, not for the spectral kernels
        ("material.poisson_ratio = 0", "poisson_ratio = 0.0"),
        ("compare.friction_coeffs: 100 is refused", "friction_coeffs = ["),
        ("unknown key compare.snapshot_t_over_t", "snapshot_t_over_t"),
        ("spectral.grid_points = 4097", "grid_points = 4097"),
        ("unknown key spectral.fast_tolerence", "fast_tolerence"),
    ] {
        let expected = format!("line {}: {message}", line_of(&text, needle));
        assert!(e.contains(&expected), "{expected}\n{e}");
    }
}

#[test]
fn values_of_the_wrong_type_and_unknown_models_are_named_on_their_line() {
    let text =
        scene_text("center-crack").replace("friction_coeffs = [0.0, 0.3] ", "friction_coeffs = \"0.3\" ");
    let e = refused("type", &[], &text, &[]);
    assert!(
        e.contains(&format!("line {}", line_of(&text, "friction_coeffs = \""))),
        "{e}"
    );
    assert!(
        !e.contains("missing"),
        "a value of the wrong type is not a missing key: {e}"
    );
    let text = scene_text("sinusoidal-interface").replace("\"hybrid\"]", "\"hybird\"]");
    let e = refused("model", &["sinusoid"], &text, &[]);
    assert!(
        e.contains("hybird") && e.contains(&format!("line {}", line_of(&text, "hybird"))),
        "{e}"
    );
    let text =
        scene_text("sinusoidal-interface").replace("\"standard\", \"hybrid\"]", "\"hybrid\", \"hybrid\"]");
    let e = refused("duplicate", &["sinusoid"], &text, &[]);
    assert!(e.contains("compare.models") && e.contains("twice"), "{e}");
}

#[test]
fn a_spectral_grid_that_cannot_hold_the_crack_is_refused() {
    let text = scene_text("center-crack")
        .replace("length = 3.75 ", "length = 0.4 ")
        .replace("grid_points = 4096 ", "grid_points = 512 ");
    let e = refused("geometry", &[], &text, &[]);
    assert!(
        e.contains("spectral.length") && e.contains(&format!("line {}", line_of(&text, "length = 0.4"))),
        "{e}"
    );
}

#[test]
fn a_study_beyond_the_budget_is_refused_before_its_first_run() {
    let e = refused(
        "budget",
        &[],
        &scene_text("center-crack"),
        &["--max-memory", "0.01"],
    );
    assert!(
        e.contains("budget") && e.contains("μ = 0") && e.contains("--max-memory"),
        "{e}"
    );
    let e = refused(
        "penalty-budget",
        &["penalty"],
        &scene_text("center-crack"),
        &["--max-steps", "1000"],
    );
    assert!(e.contains("--max-steps") && e.contains("ε_n"), "{e}");
}

#[test]
fn empty_and_unwritable_output_folders_are_refused_before_any_step() {
    let t = trial("empty-out", &scene_text("center-crack"));
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_compare"))
            .arg("--scene")
            .arg(&t.scene)
            .args(["--out", ""]),
    );
    assert!(e.contains("--out"), "{e}");
    let t = trial("unwritable", &scene_text("center-crack"));
    std::fs::write(t.dir.join("a-file"), "").unwrap();
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_compare"))
            .arg("--scene")
            .arg(&t.scene)
            .arg("--out")
            .arg(t.dir.join("a-file").join("out")),
    );
    assert!(e.contains("output folder"), "{e}");
}

/// `--friction-rule` and `--open` belong to the comparison and `converged`; given to another job,
/// or `--open` with a name that is no metric, they are refused before any step.
#[test]
fn friction_rule_and_open_metrics_are_checked_before_any_step() {
    let text = scene_text("center-crack");
    let e = refused(
        "rule-job",
        &["penalty"],
        &text,
        &["--friction-rule", "failed_only"],
    );
    assert!(e.contains("--friction-rule: taken by the comparison"), "{e}");
    let e = refused(
        "open-job",
        &["boundary"],
        &text,
        &["--open", "tip_position_rms_over_a@0.3"],
    );
    assert!(e.contains("--open: taken by the comparison"), "{e}");
    let e = refused("open-name", &[], &text, &["--open", "tip_rms@0.3"]);
    assert!(
        e.contains("--open tip_rms@0.3") && e.contains("tip_position_rms_over_a"),
        "{e}"
    );
    let e = refused("rule-name", &[], &text, &["--friction-rule", "some"]);
    assert!(e.contains("all_faces") && e.contains("failed_only"), "{e}");
}

/// `suite` runs the scenes of scenes/suite as they are: a --scene, --open or --friction-rule
/// given to it is refused by name before any step, and a budget too small for its runs names the
/// run and the flag to raise.
#[test]
fn the_suite_takes_its_own_scenes_and_checks_its_budget() {
    let text = scene_text("center-crack");
    let e = refused("suite-scene", &["suite"], &text, &[]);
    assert!(e.contains("--scene: not taken by `suite`"), "{e}");
    let t = trial("suite-budget", &text);
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_compare"))
            .args(["suite", "--max-steps", "100", "--out"])
            .arg(&t.out),
    );
    assert!(
        e.contains("FE        freund-mode2") && e.contains("--max-steps"),
        "{e}"
    );
}

/// Negative numbers given to numeric options are read as values and refused with the range (they
/// were taken for unknown flags), and a memory budget that is not a finite positive number is
/// refused (`nan` became a 0-byte budget).
#[test]
fn negative_and_non_finite_option_values_are_refused_as_values() {
    let text = scene_text("center-crack");
    let e = refused("neg-factors", &["penalty"], &text, &["--factors", "-1"]);
    assert!(
        e.contains("'-1' for '--factors") && e.contains("-1 is not in 1.."),
        "{e}"
    );
    let e = refused("neg-boxes", &["boundary"], &text, &["--boxes", "2,-3"]);
    assert!(e.contains("'-3' for '--boxes") && e.contains("not in 1.."), "{e}");
    let e = refused("neg-runs", &[], &text, &["--concurrent-runs", "-2"]);
    assert!(e.contains("'-2' for '--concurrent-runs"), "{e}");
    for bad in ["nan", "inf", "-1", "0"] {
        let e = refused("nan-memory", &[], &text, &["--max-memory", bad]);
        assert!(
            e.contains("--max-memory <GIB>") && e.contains("give a finite number > 0"),
            "{bad}: {e}"
        );
    }
    let e = refused("neg-steps", &[], &text, &["--max-steps", "-5"]);
    assert!(e.contains("'-5' for '--max-steps"), "{e}");
}
