//! SIGTERM (as Ctrl-C) stops a run at its next step: the command writes what it has computed,
//! says where, and exits non-zero; the records end before T and parse.

use preflight::testing::{signalled, started};
use std::path::Path;
use std::process::Command;

#[test]
fn a_terminated_run_keeps_parseable_output_and_says_so() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fem-interrupt");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
    let (child, first) = started(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&scene)
            .arg("--out")
            .arg(&dir),
    );
    // the plan line is printed once every check has passed, just before the first step
    assert!(first.contains("steps"), "{first}");
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let out = signalled(child, &[libc::SIGTERM]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("stopped on request") && stderr.contains("the output up to there is in"),
        "{stderr}"
    );
    let mut rd = csv::Reader::from_path(dir.join("tips.csv")).unwrap();
    let t: Vec<f64> = rd
        .records()
        .map(|r| r.unwrap()[0].parse::<f64>().unwrap())
        .collect();
    assert!(t.len() > 1, "{} rows", t.len());
    let last = *t.last().unwrap();
    assert!(
        last > 0.0 && last < 0.02,
        "the records end before T = 0.02 s: {last}"
    );
    assert!(t.windows(2).all(|w| w[1] > w[0]));
    // run.csv says the run is partial, and where it stopped
    let mut rd = csv::Reader::from_path(dir.join("run.csv")).unwrap();
    let header = rd.headers().unwrap().clone();
    let row = rd.records().next().unwrap().unwrap();
    let column = |name: &str| {
        &row[header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no {name}"))]
    };
    assert_eq!(column("status"), "interrupted");
    assert!(column("last_step").parse::<u64>().unwrap() > 0);
}

/// GNU `timeout`, and any wrapper that signals the whole process group, delivers two signals at
/// once: that is one request to stop, not "quit now"; the partial output is written.
#[test]
fn two_signals_at_once_stop_the_run_and_keep_its_output() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fem-interrupt-twice");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
    let (child, _) = started(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&scene)
            .arg("--out")
            .arg(&dir),
    );
    std::thread::sleep(std::time::Duration::from_millis(1000));
    let out = signalled(child, &[libc::SIGTERM, libc::SIGINT]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("stopped on request") && stderr.contains("the output up to there is in"),
        "{stderr}"
    );
    assert!(dir.join("tips.csv").exists());
}
