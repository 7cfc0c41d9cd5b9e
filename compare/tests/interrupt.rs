//! A study stopped on request (Ctrl-C, SIGTERM raise the reporter's stop flag) ends at the next
//! step of its current run: that run's output up to there is written, the study returns an error
//! saying where, and no later run starts.

use compare::runner::Reporter;
use compare::study::Study;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Raises the stop flag at the first progress report of the FE run at μ = 0. Only that run
/// raises it: runs go side by side, and a flag raised by its neighbour could stop it before its
/// first record.
struct StopSoon(AtomicBool);

impl Reporter for StopSoon {
    fn run_started(&self, label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_> {
        let raises = label.starts_with("FE") && label.ends_with("μ = 0");
        Box::new(move |done, _| {
            if raises && done > 0 {
                self.0.store(true, Ordering::Relaxed);
            }
        })
    }

    fn stop(&self) -> &AtomicBool {
        &self.0
    }
}

#[test]
fn a_stopped_study_keeps_the_output_of_its_current_run() {
    let study =
        Study::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml")).unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("compare-interrupt");
    let _ = std::fs::remove_dir_all(&dir);
    let e = compare::gate::run_gate(
        &study,
        &compare::gate::metrics::PAPER_RESOLUTION,
        &dir,
        &StopSoon(AtomicBool::new(false)),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("stopped on request") && e.contains("fem_mu0"), "{e}");
    // runs side by side all stop: the error names every partial output, not the first only
    if rayon::current_num_threads() > 1 {
        assert!(e.matches("stopped on request").count() >= 2, "{e}");
    }
    let tips = std::fs::read_to_string(dir.join("fem_mu0").join("tips.csv")).unwrap();
    assert!(tips.lines().count() > 2, "{tips}");
    assert!(!dir.join("spectral_mu0").exists(), "a run started after the stop");
}

/// SIGTERM to `compare sweep` alone (as `kill` sends it), not to its point processes: the sweep
/// forwards it to the point running, which writes its output up to there; the sweep names it
/// and exits non-zero instead of running every point to the end.
#[test]
fn a_terminated_sweep_stops_its_point_and_says_where_its_output_went() {
    use preflight::testing::{signalled, started};
    use std::process::Command;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("compare-interrupt-sweep");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
    let (child, plan) = started(
        Command::new(env!("CARGO_BIN_EXE_compare"))
            .args(["sweep", "--sizes", "1e-3", "--scene"])
            .arg(&scene)
            .arg("--out")
            .arg(&dir),
    );
    // the plan line comes once every check has passed, just before the first point starts
    assert!(plan.contains("runs"), "{plan}");
    std::thread::sleep(std::time::Duration::from_millis(2000));
    let out = signalled(child, &[libc::SIGTERM]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "the sweep ran on: {stderr}");
    assert!(
        stderr.contains("sweep stopped on request") && stderr.contains("its output up to there is in"),
        "{stderr}"
    );
    let partial: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("tips.csv").exists())
        .collect();
    assert_eq!(partial.len(), 1, "{partial:?}");
    assert!(stderr.contains(&partial[0].display().to_string()), "{stderr}");
    assert!(!dir.join("sweep.csv").exists());
}
