//! Ctrl-C (SIGINT) and SIGTERM stop a run at its next time step: the handler only raises a flag
//! the time loop reads, so the run returns what it has and the command writes it. A second signal
//! ends the process at once.

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

/// Installs the handler (once per process) and returns the flag it raises.
pub fn on_signal() -> Result<&'static AtomicBool, String> {
    ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            // second signal: the user does not want to wait for the output to be written
            std::process::exit(130);
        }
        eprintln!("\nstopping at the next time step; the output so far will be written (again to quit now)");
    })
    .map_err(|e| format!("installing the Ctrl-C handler: {e}"))?;
    Ok(&STOP)
}
