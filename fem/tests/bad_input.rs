//! The `fem` command refuses bad input before any time step: every problem of a scene at once,
//! each with its key and its line; runs beyond the budget; an empty or unwritable output folder.
//! "No step ran" is checked by the output folder (never created) and by stdout (the command
//! prints its plan only once everything is checked).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn scene_text(name: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml")))
        .unwrap()
}

/// A scratch folder of this test, emptied.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("fem-bad-input-{test}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn fem(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_fem"))
        .args(args)
        .output()
        .unwrap()
}

/// Runs `fem` on `text` written to `dir/scene.toml`, output into `dir/out`; returns (status ok,
/// stdout, stderr).
fn run(dir: &Path, text: &str, extra: &[&str]) -> (bool, String, String) {
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("out");
    let mut args: Vec<&std::ffi::OsStr> = vec![scene.as_os_str(), "--out".as_ref(), out.as_os_str()];
    args.extend(extra.iter().map(|a| std::ffi::OsStr::new(*a)));
    let o = fem(&args);
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

/// Nothing was run: no output folder, nothing on stdout.
fn assert_no_step(dir: &Path, stdout: &str) {
    assert!(!dir.join("out").exists(), "the output folder was created");
    assert!(stdout.is_empty(), "the command started: {stdout}");
}

#[test]
fn a_bad_value_and_a_late_typo_are_reported_together_with_their_lines() {
    let dir = scratch("together");
    let text = scene_text("center-crack")
        .replace("poisson_ratio = 0.35 ", "poisson_ratio = 0.6 ")
        .replace("max_gap = 1e-3 ", "max_gapp = 1e-3 ");
    let (ok, stdout, stderr) = run(&dir, &text, &[]);
    assert!(!ok);
    assert_no_step(&dir, &stdout);
    let nu = format!(
        "line {}: material.poisson_ratio = 0.6",
        line_of(&text, "poisson_ratio")
    );
    let typo = format!("line {}: unknown key fem.max_gapp", line_of(&text, "max_gapp"));
    assert!(stderr.contains(&nu) && stderr.contains(&typo), "{stderr}");
}

#[test]
fn a_ramp_after_the_end_and_two_step_keys_are_refused() {
    let dir = scratch("ramp");
    let text = scene_text("center-crack")
        .replace(
            "ramp_start = 0.0, ramp_end = 0.002 }",
            "ramp_start = 0.03, ramp_end = 0.04 }",
        )
        .replace(
            "time_step_safety = 0.5 ",
            "time_step = 1e-6\ntime_step_safety = 0.5 ",
        );
    let (ok, stdout, stderr) = run(&dir, &text, &[]);
    assert!(!ok);
    assert_no_step(&dir, &stdout);
    assert!(stderr.contains("loading.normal.ramp_start = 0.03"), "{stderr}");
    assert!(stderr.contains("fem.time_step"), "{stderr}");
}

#[test]
fn a_run_beyond_the_memory_budget_is_refused_with_the_key_to_change() {
    let dir = scratch("budget");
    let text = scene_text("center-crack").replace("element_size = 1e-3", "element_size = 1e-5");
    let (ok, stdout, stderr) = run(&dir, &text, &[]);
    assert!(!ok);
    assert_no_step(&dir, &stdout);
    assert!(
        stderr.contains("budget") && stderr.contains("fem.element_size"),
        "{stderr}"
    );
    // the budget is the user's to raise: the same scene with a tiny step budget is refused on steps
    let (ok, stdout, stderr) = run(&dir, &scene_text("center-crack"), &["--max-steps", "1000"]);
    assert!(!ok);
    assert_no_step(&dir, &stdout);
    assert!(
        stderr.contains("--max-steps") && stderr.contains("loading.duration"),
        "{stderr}"
    );
}

#[test]
fn an_empty_or_unwritable_output_folder_is_refused_before_any_step() {
    let dir = scratch("paths");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, scene_text("center-crack")).unwrap();
    let o = fem(&[scene.as_os_str(), "--out".as_ref(), "".as_ref()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && stderr.contains("--out"), "{stderr}");
    assert!(o.stdout.is_empty());
    // a folder below a file cannot be created
    let blocker = dir.join("a-file");
    std::fs::write(&blocker, "").unwrap();
    let out = blocker.join("out");
    let o = fem(&[scene.as_os_str(), "--out".as_ref(), out.as_os_str()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && stderr.contains("output folder"),
        "{stderr}"
    );
    assert!(o.stdout.is_empty(), "{}", String::from_utf8_lossy(&o.stdout));
}

#[test]
fn a_folder_of_the_spectral_model_is_not_overwritten() {
    let dir = scratch("owner");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join(preflight::paths::MARKER), "spectral\n").unwrap();
    let (ok, stdout, stderr) = run(&dir, &scene_text("tiny-fem-center-crack"), &[]);
    assert!(!ok && stdout.is_empty());
    assert!(stderr.contains("spectral model"), "{stderr}");
}
