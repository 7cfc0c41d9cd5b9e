//! The `spectral` command refuses bad input before any time step: every problem of a scene at
//! once with its key and line, a geometry the periodic grid cannot hold, a kernel fit that cannot
//! reach its tolerance, runs beyond the budget. "No step ran": no output folder, nothing on
//! stdout (the command prints its plan only once everything is checked).

use preflight::testing::{Trial, line_containing, scene_text};
use std::process::Command;

fn text(name: &str) -> String {
    scene_text(env!("CARGO_MANIFEST_DIR"), name)
}

/// Runs `spectral` on scene `s` with `extra` options; asserts it was refused before any step and
/// returns its stderr.
fn refused(name: &str, s: &str, extra: &[&str]) -> String {
    let t = Trial::new(
        env!("CARGO_TARGET_TMPDIR"),
        &format!("spectral-bad-input-{name}"),
        s,
    );
    t.refused(
        Command::new(env!("CARGO_BIN_EXE_spectral"))
            .arg(&t.scene)
            .arg("--out")
            .arg(&t.out)
            .args(extra),
    )
}

#[test]
fn every_problem_is_reported_at_once_with_its_line() {
    let s = text("center-crack")
        .replace("friction_coeff = 0.3 ", "friction_coeff = 1e6 ")
        .replace("grid_points = 4096 ", "grid_points = 4095 ")
        .replace("t_star = 2e-5 ", "t_star = 2e-5\nt_starr = 1.0 ");
    let e = refused("together", &s, &[]);
    for (key, needle) in [
        ("friction.friction_coeff = 1000000", "friction_coeff = 1e6"),
        ("spectral.grid_points = 4095", "grid_points = 4095"),
        ("unknown key spectral.t_starr", "t_starr"),
    ] {
        assert!(
            e.contains(&format!("line {}: {key}", line_containing(&s, needle))),
            "{key}: {e}"
        );
    }
}

#[test]
fn a_crack_the_periodic_grid_cannot_hold_is_refused() {
    // 2a = 0.25 m in a periodic length of 0.4 m: the images are closer than the crack is long
    let s = text("center-crack")
        .replace("length = 3.75 ", "length = 0.4 ")
        .replace("grid_points = 4096 ", "grid_points = 512 ");
    let e = refused("geometry", &s, &[]);
    assert!(
        e.contains("spectral.length") && e.contains("periodic images"),
        "{e}"
    );
    // four points over 3.75 m: the process zone (8.75 mm) falls between them
    let s = text("center-crack").replace("grid_points = 4096 ", "grid_points = 4 ");
    let e = refused("resolution", &s, &[]);
    assert!(
        e.contains("spectral.grid_points") && e.contains("process zone"),
        "{e}"
    );
}

#[test]
fn a_state_storage_that_is_not_one_or_does_not_apply_is_refused_with_its_key() {
    let with = |line: &str| {
        text("center-crack").replace(
            "fast_tolerance = 1e-5 ",
            &format!("fast_tolerance = 1e-5\n{line}\n"),
        )
    };
    let s = with("fast_storage = \"f16\"");
    let e = refused("storage-word", &s, &[]);
    assert!(
        e.contains("spectral.fast_storage") && e.contains("f32") && e.contains("f64"),
        "{e}"
    );
    let s = with("fast_storage = \"f32\"").replace("convolution = \"fast\"", "convolution = \"direct\"");
    let e = refused("storage-direct", &s, &[]);
    assert!(
        e.contains(&format!(
            "line {}: spectral.fast_storage",
            line_containing(&s, "fast_storage")
        )) && e.contains("direct"),
        "{e}"
    );
}

#[test]
fn a_kernel_fit_that_cannot_reach_its_tolerance_names_the_keys_to_change() {
    let s = text("center-crack").replace("poisson_ratio = 0.35 ", "poisson_ratio = 0.499 ");
    let e = refused("fit", &s, &[]);
    for key in [
        "spectral.fast_tolerance",
        "spectral.kernel_cutoff",
        "material.poisson_ratio = 0.499",
        "direct",
    ] {
        assert!(e.contains(key), "{key}: {e}");
    }
}

#[test]
fn runs_beyond_the_budget_are_refused_with_the_key_to_change() {
    let s = text("center-crack").replace("field_output_interval = 1e-3 ", "field_output_interval = 1e-7 ");
    let e = refused("memory", &s, &[]);
    assert!(
        e.contains("spectral.field_output_interval") && e.contains("--max-memory"),
        "{e}"
    );
    let e = refused("steps", &text("center-crack"), &["--max-steps", "100"]);
    assert!(e.contains("--max-steps") && e.contains("loading.duration"), "{e}");
}

#[test]
fn an_empty_output_folder_is_refused() {
    let t = Trial::new(
        env!("CARGO_TARGET_TMPDIR"),
        "spectral-bad-input-empty-out",
        &text("tiny-spectral-andrews"),
    );
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_spectral"))
            .arg(&t.scene)
            .args(["--out", ""]),
    );
    assert!(e.contains("--out"), "{e}");
}
