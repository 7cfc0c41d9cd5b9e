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
}

impl RunOptions {
    /// `--out` if given (refused when empty), else `out/<model>-<scene file name>` with the name
    /// made safe ([`crate::paths::folder_name`]).
    pub fn out_dir(&self, model: &str, scene: &Path) -> Result<PathBuf, String> {
        match &self.out {
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
