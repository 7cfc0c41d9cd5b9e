//! Helpers of the command-line tests and the benchmarks (feature `testing`, for dev-dependencies
//! only): a scratch folder with the scene written into it, the check that a command refused its
//! input before any time step — non-zero exit, nothing on stdout (every command prints its plan
//! only once its checks have passed), no output folder — and a clock for benchmarks that runs
//! the models' parallel code where their runs do, on a thread of rayon's pool
//! ([`time_on_pool`], [`time_on_awake_pool`]).

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

/// The time `iters` calls of `routine` take on a thread of rayon's global pool, for criterion's
/// `iter_custom`, as the spectral model's runs call their steps. Both models run their time steps
/// on a pool thread, so that each parallel loop of a step splits its work through the worker's
/// own queue; called from any other thread (criterion's), every such loop would instead be handed
/// to the pool while the caller sleeps until it ends, a cost the runs never pay. The results are
/// black-boxed, as criterion's `iter` does.
pub fn time_on_pool<R>(iters: u64, routine: impl FnMut() -> R + Send) -> Duration {
    rayon::scope(|_| timed(iters, routine))
}

/// [`time_on_pool`] as the FE model's runs call their steps: on a pool of their own whose other
/// workers are kept awake ([`crate::pool::Steps`]), one pool for the whole process.
pub fn time_on_awake_pool<R>(iters: u64, routine: impl FnMut() -> R + Send) -> Duration {
    static STEPS: std::sync::OnceLock<crate::pool::Steps> = std::sync::OnceLock::new();
    STEPS
        .get_or_init(crate::pool::Steps::new)
        .run(|| timed(iters, routine))
}

/// The time of `iters` calls of `routine`, their results black-boxed.
fn timed<R>(iters: u64, mut routine: impl FnMut() -> R) -> Duration {
    let start = Instant::now();
    for _ in 0..iters {
        std::hint::black_box(routine());
    }
    start.elapsed()
}

/// The text of `scenes/<name>.toml` of the workspace whose member lives at `manifest_dir`.
pub fn scene_text(manifest_dir: &str, name: &str) -> String {
    let path = Path::new(manifest_dir).join(format!("../scenes/{name}.toml"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Line (1-based) of the first line of `text` that contains `needle`.
pub fn line_containing(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle} not in the scene"))
        + 1
}

/// One trial of a command: a fresh folder holding `scene.toml`; `out` is the output folder to
/// pass (not created).
pub struct Trial {
    /// The folder of the trial.
    pub dir: PathBuf,
    /// The scene file.
    pub scene: PathBuf,
    /// The output folder to give the command.
    pub out: PathBuf,
}

impl Trial {
    /// A trial named `name` under `root` (the test's `CARGO_TARGET_TMPDIR`) with scene `text`.
    pub fn new(root: &str, name: &str, text: &str) -> Trial {
        let dir = Path::new(root).join(name);
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, text).unwrap();
        Trial {
            out: dir.join("out"),
            scene,
            dir,
        }
    }

    /// Runs `cmd`, asserts it was refused before any step and returns its stderr.
    pub fn refused(&self, cmd: &mut Command) -> String {
        let o = cmd.output().unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(!o.status.success(), "accepted: {stderr}");
        assert!(
            o.stdout.is_empty(),
            "started: {}",
            String::from_utf8_lossy(&o.stdout)
        );
        assert!(!self.out.exists(), "the output folder was created: {stderr}");
        stderr
    }
}

/// `cmd` started with stdout and stderr piped, once it has printed its first line on stdout (its
/// plan: every command prints it when all its checks have passed, just before its first step);
/// the running child and that line.
pub fn started(cmd: &mut Command) -> (Child, String) {
    let mut child = cmd.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.as_mut().unwrap())
        .read_line(&mut line)
        .unwrap();
    (child, line)
}

/// Sends `signals` (`libc::SIGTERM`, `libc::SIGINT`, ...) to `child`, one right after the other,
/// and waits for its output.
pub fn signalled(child: Child, signals: &[libc::c_int]) -> Output {
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    for &signal in signals {
        // SAFETY: kill(2) with a valid signal number on our own child's pid has no memory effects.
        assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
    }
    child.wait_with_output().unwrap()
}

#[cfg(test)]
mod tests {
    use super::time_on_pool;

    #[test]
    fn time_on_pool_runs_the_routine_iters_times_on_a_pool_thread() {
        let (mut calls, mut off_pool) = (0, 0);
        time_on_pool(5, || {
            calls += 1;
            off_pool += usize::from(rayon::current_thread_index().is_none());
        });
        assert_eq!((calls, off_pool), (5, 0));
    }
}
