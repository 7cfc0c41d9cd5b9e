//! The `spectral` command refuses bad input before any time step: every problem of a scene at
//! once with its key and line, a geometry the periodic grid cannot hold, a kernel fit that cannot
//! reach its tolerance, runs beyond the budget. "No step ran": no output folder, nothing on
//! stdout (the command prints its plan only once everything is checked).

use std::path::{Path, PathBuf};
use std::process::Command;

fn scene_text(name: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml")))
        .unwrap()
}

fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("spectral-bad-input-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `spectral` on `text`; asserts it failed before any step and returns its stderr.
fn refused(test: &str, text: &str, extra: &[&str]) -> String {
    let dir = scratch(test);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let o = Command::new(env!("CARGO_BIN_EXE_spectral"))
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .args(extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!o.status.success(), "accepted: {stderr}");
    assert!(
        o.stdout.is_empty(),
        "started: {}",
        String::from_utf8_lossy(&o.stdout)
    );
    assert!(!out.exists(), "the output folder was created");
    stderr
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn every_problem_is_reported_at_once_with_its_line() {
    let text = scene_text("center-crack")
        .replace("friction_coeff = 0.3 ", "friction_coeff = 1e6 ")
        .replace("grid_points = 4096 ", "grid_points = 4095 ")
        .replace("t_star = 2e-5 ", "t_star = 2e-5\nt_starr = 1.0 ");
    let e = refused("together", &text, &[]);
    for (key, needle) in [
        ("friction.friction_coeff = 1000000", "friction_coeff = 1e6"),
        ("spectral.grid_points = 4095", "grid_points = 4095"),
        ("unknown key spectral.t_starr", "t_starr"),
    ] {
        assert!(
            e.contains(&format!("line {}: {key}", line_of(&text, needle))),
            "{key}: {e}"
        );
    }
}

#[test]
fn a_crack_the_periodic_grid_cannot_hold_is_refused() {
    // 2a = 0.25 m in a periodic length of 0.4 m: the images are closer than the crack is long
    let text = scene_text("center-crack")
        .replace("length = 3.75 ", "length = 0.4 ")
        .replace("grid_points = 4096 ", "grid_points = 512 ");
    let e = refused("geometry", &text, &[]);
    assert!(
        e.contains("spectral.length") && e.contains("periodic images"),
        "{e}"
    );
    // four points over 3.75 m: the process zone (8.75 mm) falls between them
    let text = scene_text("center-crack").replace("grid_points = 4096 ", "grid_points = 4 ");
    let e = refused("resolution", &text, &[]);
    assert!(
        e.contains("spectral.grid_points") && e.contains("process zone"),
        "{e}"
    );
}

#[test]
fn a_kernel_fit_that_cannot_reach_its_tolerance_names_the_keys_to_change() {
    let text = scene_text("center-crack").replace("poisson_ratio = 0.35 ", "poisson_ratio = 0.499 ");
    let e = refused("fit", &text, &[]);
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
    let text =
        scene_text("center-crack").replace("field_output_interval = 1e-3 ", "field_output_interval = 1e-7 ");
    let e = refused("memory", &text, &[]);
    assert!(
        e.contains("spectral.field_output_interval") && e.contains("--max-memory"),
        "{e}"
    );
    let e = refused("steps", &scene_text("center-crack"), &["--max-steps", "100"]);
    assert!(e.contains("--max-steps") && e.contains("loading.duration"), "{e}");
}

#[test]
fn an_empty_output_folder_is_refused() {
    let dir = scratch("empty-out");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, scene_text("tiny-spectral-andrews")).unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_spectral"))
        .arg(&scene)
        .args(["--out", ""])
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && e.contains("--out") && o.stdout.is_empty(),
        "{e}"
    );
}
