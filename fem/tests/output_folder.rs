//! An output folder takes one run at a time: a second run into a folder another run is writing
//! is refused before any work, naming the other run's process, and the first run's files are
//! its own.

use preflight::testing::{signalled, started};
use std::path::Path;
use std::process::Command;

#[test]
fn a_second_run_into_a_busy_folder_is_refused_naming_the_first() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fem-busy-folder");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
    let fem = || {
        let mut c = Command::new(env!("CARGO_BIN_EXE_fem"));
        c.arg(&scene).arg("--out").arg(&dir);
        c
    };
    let (first, line) = started(&mut fem());
    assert!(line.contains("steps"), "{line}");
    let second = fem().output().unwrap();
    let stderr = String::from_utf8_lossy(&second.stderr);
    assert!(!second.status.success(), "both ran: {stderr}");
    assert!(second.stdout.is_empty(), "the second started");
    assert!(
        stderr.contains("in use") && stderr.contains(&format!("process {}", first.id())),
        "{stderr}"
    );
    let out = signalled(first, &[libc::SIGTERM]);
    assert!(!out.status.success());
    // the lock is released with the run: the folder takes the next run
    assert_eq!(std::fs::read_to_string(dir.join(".run.lock")).unwrap(), "");
}
