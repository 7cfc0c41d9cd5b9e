//! The `fem` command refuses bad input before any time step: every problem of a scene at once,
//! each with its key and its line; runs beyond the budget; an empty, unwritable or foreign output
//! folder. "No step ran": nothing on stdout (the command prints its plan only once everything is
//! checked) and no output folder.

use preflight::testing::{Trial, line_containing, scene_text};
use std::process::Command;

fn text(name: &str) -> String {
    scene_text(env!("CARGO_MANIFEST_DIR"), name)
}

/// `fem <trial scene> --out <trial out> [extra]`.
fn fem(t: &Trial, extra: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fem"));
    c.arg(&t.scene).arg("--out").arg(&t.out).args(extra);
    c
}

fn trial(name: &str, text: &str) -> Trial {
    Trial::new(
        env!("CARGO_TARGET_TMPDIR"),
        &format!("fem-bad-input-{name}"),
        text,
    )
}

#[test]
fn a_bad_value_and_a_late_typo_are_reported_together_with_their_lines() {
    let s = text("center-crack")
        .replace("poisson_ratio = 0.35 ", "poisson_ratio = 0.6 ")
        .replace("max_gap = 1e-3 ", "max_gapp = 1e-3 ");
    let t = trial("together", &s);
    let e = t.refused(&mut fem(&t, &[]));
    let nu = format!(
        "line {}: material.poisson_ratio = 0.6",
        line_containing(&s, "poisson_ratio")
    );
    let typo = format!(
        "line {}: unknown key fem.max_gapp",
        line_containing(&s, "max_gapp")
    );
    assert!(e.contains(&nu) && e.contains(&typo), "{e}");
}

#[test]
fn a_ramp_after_the_end_and_two_step_keys_are_refused() {
    let s = text("center-crack")
        .replace(
            "ramp_start = 0.0, ramp_end = 0.004 }",
            "ramp_start = 0.03, ramp_end = 0.04 }",
        )
        .replace(
            "time_step_safety = 0.5 ",
            "time_step = 1e-6\ntime_step_safety = 0.5 ",
        );
    let t = trial("ramp", &s);
    let e = t.refused(&mut fem(&t, &[]));
    assert!(
        e.contains("loading.normal.ramp_start = 0.03") && e.contains("fem.time_step"),
        "{e}"
    );
}

#[test]
fn a_run_beyond_the_budget_is_refused_with_the_key_to_change() {
    let t = trial(
        "memory",
        &text("center-crack").replace("element_size = 1e-3", "element_size = 1e-5"),
    );
    let e = t.refused(&mut fem(&t, &[]));
    assert!(e.contains("budget") && e.contains("fem.element_size"), "{e}");
    // the budget is the user's to raise; a small step budget refuses the case itself
    let t = trial("steps", &text("center-crack"));
    let e = t.refused(&mut fem(&t, &["--max-steps", "1000"]));
    assert!(e.contains("--max-steps") && e.contains("loading.duration"), "{e}");
}

#[test]
fn an_empty_unwritable_or_foreign_output_folder_is_refused_before_any_step() {
    let t = trial("empty-out", &text("center-crack"));
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&t.scene)
            .args(["--out", ""]),
    );
    assert!(e.contains("--out"), "{e}");
    // a folder below a file cannot be created
    let t = trial("unwritable", &text("center-crack"));
    std::fs::write(t.dir.join("a-file"), "").unwrap();
    let below_a_file = t.dir.join("a-file").join("out");
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&t.scene)
            .arg("--out")
            .arg(&below_a_file),
    );
    assert!(e.contains("output folder"), "{e}");
    // a folder the spectral model writes to
    let t = trial("owner", &text("tiny-fem-center-crack"));
    let theirs = t.dir.join("theirs");
    std::fs::create_dir_all(&theirs).unwrap();
    std::fs::write(theirs.join(preflight::paths::MARKER), "spectral\n").unwrap();
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&t.scene)
            .arg("--out")
            .arg(&theirs),
    );
    assert!(e.contains("spectral model"), "{e}");
}

/// Every bad value of every table in one message: two or more per table, in the shared tables and
/// in `[fem]`, with a refused `[crack]` (whose problems used to hide all of `[fem]`'s) and several
/// keys of one table (of which only the first used to be reported).
#[test]
fn every_bad_value_of_every_table_is_reported_at_once() {
    let bad = [
        (
            "youngs_modulus = 70e6 ",
            "youngs_modulus = -70e6 ",
            "material.youngs_modulus",
        ),
        ("density = 1230.0 ", "density = -1.0 ", "material.density"),
        ("sigma_c = 0.4e6 ", "sigma_c = 0.0 ", "interface.sigma_c"),
        ("delta_c = 1e-4 ", "delta_c = -1e-4 ", "interface.delta_c"),
        ("kappa = 1.0 ", "kappa = 0.0 ", "interface.kappa"),
        (
            "half_length = 0.125 ",
            "half_length = -0.125 ",
            "crack.half_length",
        ),
        (
            "friction_coeff = 0.3 ",
            "friction_coeff = -0.3 ",
            "friction.friction_coeff",
        ),
        (
            "initial = 0.0, final = -0.05e6",
            "initial = nan, final = -0.05e6",
            "loading.normal.initial",
        ),
        (
            "ramp_start = 0.0, ramp_end = 0.02",
            "ramp_start = 0.0, ramp_end = -1.0",
            "loading.shear.ramp_end",
        ),
        (
            "element_size = 1e-3 ",
            "element_size = -1e-3 ",
            "fem.element_size",
        ),
        ("model = \"hybrid\" ", "model = \"hybird\" ", "fem.model"),
        (
            "insertion_rule = \"max\" ",
            "insertion_rule = \"maximum\" ",
            "fem.insertion_rule",
        ),
        ("eps_n = 2.1e10 ", "eps_n = -2.1e10 ", "fem.eps_n"),
        ("eps_t = 2.1e10 ", "eps_t = -2.1e10 ", "fem.eps_t"),
        (
            "output_interval = 2e-5 ",
            "output_interval = -2e-5 ",
            "fem.output_interval",
        ),
        ("max_gap = 1e-3 ", "max_gap = -1e-3 ", "fem.max_gap"),
        (
            "projection_tolerance = 1e-3 ",
            "projection_tolerance = 0.7 ",
            "fem.projection_tolerance",
        ),
    ];
    let mut s = text("center-crack");
    for (from, to, _) in bad {
        assert!(s.contains(from), "{from}");
        s = s.replacen(from, to, 1);
    }
    let t = trial("all-at-once", &s);
    let e = t.refused(&mut fem(&t, &[]));
    let missing: Vec<&str> = bad.iter().map(|b| b.2).filter(|k| !e.contains(k)).collect();
    assert!(missing.is_empty(), "not reported: {missing:?}\n{e}");
    assert!(e.contains(&format!("{} problems in the scene", bad.len())), "{e}");
}

/// A penalty so stiff that the stable step vanishes (Δt = 0 at ε_n = 1e300) is refused naming
/// the penalty, not passed on to the budget, whose advice (raise --max-steps to 2^64 − 1) would
/// run NaN steps; a step count is never printed saturated.
#[test]
fn a_penalty_that_makes_the_step_vanish_is_refused_naming_it() {
    let s = text("center-crack").replace("eps_n = 2.1e10 ", "eps_n = 1e300 ");
    let t = trial("vanishing-step", &s);
    let e = t.refused(&mut fem(&t, &[]));
    assert!(
        e.contains("fem.eps_n") && e.contains("the time step would be 0e0 s"),
        "{e}"
    );
    assert!(
        !e.contains("18446744073709551615") && !e.contains("--max-steps"),
        "{e}"
    );
}

/// An output interval below the time step silently sampled every step: the run now says so
/// before it starts (a warning: "every step" is a legitimate wish).
#[test]
fn an_output_interval_below_the_step_is_said_to_mean_every_step() {
    let s = text("tiny-fem-center-crack").replace("output_interval = 1e-5 ", "output_interval = 1e-300 ");
    let t = trial("tiny-interval", &s);
    let out = fem(&t, &[]).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: fem.output_interval = 1e-300 s is below the time step")
            && err.contains("every step is recorded"),
        "{err}"
    );
}

/// A sine whose half-period equals h puts every node column on one of its zeros: the row would
/// be flat, which is not the interface asked for.
#[test]
fn a_sine_sampled_only_at_its_zeros_is_refused() {
    // h = 1 mm; `from` = 0.125 m lies on a node
    let s = text("sinusoidal-interface").replace("half_period = 0.0625", "half_period = 0.001");
    assert!(s.contains("element_size = 1e-3 "), "the test needs h = 1 mm");
    let t = trial("flat-sine", &s);
    let e = t.refused(&mut fem(&t, &[]));
    assert!(
        e.contains("fem.interface_sine.half_period") && e.contains("every node column falls on a zero"),
        "{e}"
    );
}

/// The output of `cmd`, killed (and the test failed) if it has not ended within 60 s: a file
/// without a size must be refused by the cap, not read until the memory runs out.
fn within_a_minute(cmd: &mut Command) -> std::process::Output {
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > std::time::Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("still reading after 60 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    child.wait_with_output().unwrap()
}

#[test]
fn dev_zero_as_the_scene_or_the_mesh_is_refused_by_the_size_cap() {
    let t = trial("dev-zero", "");
    let out = within_a_minute(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg("/dev/zero")
            .arg("--out")
            .arg(&t.out),
    );
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && out.stdout.is_empty(), "{e}");
    assert!(
        e.contains("/dev/zero")
            && e.contains("above the cap of 16777216 bytes")
            && e.contains("COHESIVE_MAX_SCENE_BYTES"),
        "{e}"
    );

    let s = text("tiny-fem-plate-tri");
    assert!(s.contains("file = "), "the scene reads a mesh file");
    let s = s
        .lines()
        .map(|l| {
            if l.trim_start().starts_with("file = ") {
                "file = \"/dev/zero\""
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let t = trial("dev-zero-mesh", &s);
    let out = within_a_minute(fem(&t, &[]).env("COHESIVE_MAX_MESH_BYTES", "1000000"));
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && out.stdout.is_empty(), "{e}");
    assert!(
        e.contains("fem.mesh.file") && e.contains("/dev/zero") && e.contains("more than 1000000 bytes"),
        "{e}"
    );
}
