//! Raising the stop flag (what Ctrl-C and SIGTERM do in the command) ends a run at its next step
//! with `RunError::Interrupted` and every record up to there.

use spectral::{RunError, Scene};
use std::sync::atomic::{AtomicBool, Ordering};

#[test]
fn a_stopped_run_returns_its_records_up_to_the_stop() {
    let scene = Scene::from_toml_str(include_str!("../../scenes/tiny-spectral-andrews.toml")).unwrap();
    let stop = AtomicBool::new(false);
    let mut raise = |done: u64, total: u64| {
        if done >= total / 4 {
            stop.store(true, Ordering::Relaxed);
        }
    };
    let result = spectral::run_with_progress(&scene, &mut raise, &stop);
    let Err(RunError::Interrupted {
        step,
        time_s,
        partial,
    }) = result
    else {
        panic!("the run did not stop: {result:?}");
    };
    let total = scene.last_step() + 1;
    assert!(step > 0 && step < total / 2, "stopped at step {step} of {total}");
    assert_eq!(
        partial.tips.len() as u64,
        step + 1,
        "one tip record per step computed"
    );
    assert!((partial.tips.last().unwrap().t - time_s).abs() < 1e-9 * scene.duration());
    assert!(time_s < scene.duration());
    // stats.csv says the run is partial, and its last step
    assert_eq!(partial.stats.status, preflight::Status::Interrupted);
    assert_eq!(partial.stats.last_step, step);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("spectral-interrupt");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    spectral::write_csv(&partial, &dir).unwrap();
    let stats = std::fs::read_to_string(dir.join("stats.csv")).unwrap();
    let (header, row) = stats.split_once('\n').unwrap();
    assert!(header.ends_with(",status,last_step"), "{header}");
    assert!(row.trim_end().ends_with(&format!(",interrupted,{step}")), "{row}");
}
