//! The options every command takes: where the output goes and the budget of a run.

use crate::Budget;
use crate::budget::{DEFAULT_MAX_BYTES, DEFAULT_MAX_STEPS};
use std::path::{Path, PathBuf};

/// The budget of each run (`--max-memory`, `--max-steps`).
#[derive(Debug, Clone, clap::Args)]
pub struct BudgetOptions {
    /// Memory budget of a run [GiB]: a run estimated above it is refused before it starts.
    #[arg(long, global = true, value_name = "GIB", default_value_t = (DEFAULT_MAX_BYTES >> 30) as f64,
          allow_negative_numbers = true, value_parser = parse_gib)]
    pub max_memory: f64,
    /// Time-step budget of a run: a run needing more steps is refused before it starts.
    #[arg(long, global = true, value_name = "N", default_value_t = DEFAULT_MAX_STEPS,
          allow_negative_numbers = true)]
    pub max_steps: u64,
}

/// `--max-memory`: a finite number of GiB > 0 (NaN would become a 0-byte budget, inf no budget).
fn parse_gib(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(g) if g.is_finite() && g > 0.0 => Ok(g),
        Ok(g) => Err(format!("{g} GiB: give a finite number > 0")),
        Err(e) => Err(format!("{s:?}: {e}")),
    }
}

impl BudgetOptions {
    /// The budget these options give.
    pub fn budget(&self) -> Budget {
        Budget::new(self.max_memory, self.max_steps)
    }
}

/// The options of a command that runs one model on one scene.
#[derive(Debug, Clone, clap::Args)]
pub struct RunOptions {
    /// Output folder (default: out/<model>-<scene file name>/).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// The budget of the run.
    #[command(flatten)]
    pub budget: BudgetOptions,
    /// Writes the run's complete state to checkpoint.bin in its output folder every SECONDS of
    /// wall time (atomically), and when it is stopped (Ctrl-C, SIGTERM), so that `--resume`
    /// continues it after a kill. A run that reaches its end removes it.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true, value_parser = parse_seconds)]
    pub checkpoint_every: Option<f64>,
    /// Continues the run whose output folder is DIR from its checkpoint, with the scene it was
    /// started with; its output is the same, byte for byte, as if it had never stopped.
    /// Checkpoints go on at the interval of the first run unless --checkpoint-every is given.
    #[arg(long, value_name = "DIR", conflicts_with = "out")]
    pub resume: Option<PathBuf>,
}

/// `--checkpoint-every`: a finite number of seconds > 0.
fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        Ok(t) => Err(format!("{t} s: give a finite number of seconds > 0")),
        Err(e) => Err(format!("{s:?}: {e}")),
    }
}

impl RunOptions {
    /// `--resume` if given, else `--out` if given (refused when empty), else `out/<model>-<scene file name>` with the name
    /// made safe ([`crate::paths::folder_name`]).
    pub fn out_dir(&self, model: &str, scene: &Path) -> Result<PathBuf, String> {
        match self.resume.as_ref().or(self.out.as_ref()) {
            Some(dir) => crate::paths::explicit(dir).map(Path::to_path_buf),
            None => {
                let stem = scene
                    .file_stem()
                    .map_or(String::new(), |s| s.to_string_lossy().into_owned());
                Ok(PathBuf::from("out").join(format!("{model}-{}", crate::paths::folder_name(&stem))))
            }
        }
    }
}
