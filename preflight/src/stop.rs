//! Ctrl-C (SIGINT) and SIGTERM stop a run at its next time step: the handler only raises a flag
//! the time loop reads, so the run returns what it has and the command writes it. A second
//! signal ends the process at once, but only [`GRACE`] or more after the first: GNU `timeout`,
//! and any wrapper that signals the whole process group, delivers two signals at once, and that
//! is one request to stop, whose partial output is written.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

static STOP: AtomicBool = AtomicBool::new(false);

/// Time of the first signal, in milliseconds after [`on_signal`] was called.
static FIRST_MS: AtomicU64 = AtomicU64::new(0);

/// How long after the first signal a second one still counts as the same request.
pub const GRACE: Duration = Duration::from_secs(1);

/// Whether a signal `since_first` after the first one means "quit now".
pub fn quits_now(since_first: Duration) -> bool {
    since_first >= GRACE
}

/// Installs the handler (once per process) and returns the flag it raises.
pub fn on_signal() -> Result<&'static AtomicBool, String> {
    let start = Instant::now();
    ctrlc::set_handler(move || {
        let now_ms = start.elapsed().as_millis() as u64;
        if STOP.swap(true, Ordering::SeqCst) {
            let since = Duration::from_millis(now_ms.saturating_sub(FIRST_MS.load(Ordering::SeqCst)));
            if quits_now(since) {
                // the user does not want to wait for the output to be written
                eprintln!("\nquitting now; the output of this run is not written");
                std::process::exit(130);
            }
            return;
        }
        FIRST_MS.store(now_ms, Ordering::SeqCst);
        eprintln!(
            "\nstopping at the next time step; the output so far will be written (again, a second \
             or more later, to quit now)"
        );
    })
    .map_err(|e| format!("installing the Ctrl-C handler: {e}"))?;
    Ok(&STOP)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two signals at once are one request; a second one later is "quit now".
    #[test]
    fn a_second_signal_quits_only_after_the_grace_period() {
        assert!(!quits_now(Duration::ZERO));
        assert!(!quits_now(Duration::from_millis(999)));
        assert!(quits_now(GRACE));
    }
}
