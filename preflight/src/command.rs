//! What the two models' command lines share around their run: the scene read and checked, the
//! output folder claimed and emptied of an earlier run's files before the run, and the last line
//! of a run that stopped before T.

use crate::Estimate;
use crate::options::RunOptions;
use std::error::Error;
use std::fmt;
use std::path::{Path, PathBuf};

/// A scene ready to run: read, within its budget, its output folder claimed and emptied.
#[derive(Debug)]
pub struct Prepared<S> {
    /// The validated scene.
    pub scene: S,
    /// Its steps, memory and time.
    pub estimate: Estimate,
    /// The output folder.
    pub out_dir: PathBuf,
    /// How many files of an earlier run were removed from it.
    pub removed: usize,
    /// The folder, held for this run: keep it until the output is written.
    pub claim: crate::paths::Claim,
    /// The checkpoint this run continues from (`--resume`), checked against the scene.
    pub resumed: Option<crate::checkpoint::Resumed>,
    /// The writer of this run's checkpoints (`--checkpoint-every`, or the interval of the run a
    /// resumed run continues).
    pub checkpoints: Option<crate::checkpoint::Writer>,
}

impl<S> Prepared<S> {
    /// The line before the run: the scene file, the estimate, the time step `time_step` [s], the
    /// output folder and how many files of an earlier run were removed from it.
    pub fn announce(&self, scene_path: &Path, time_step: f64) {
        println!(
            "{}: {} (dt = {:.4e} s); output in {}{}",
            scene_path.display(),
            self.estimate.summary(),
            time_step,
            self.out_dir.display(),
            crate::paths::removed_note(self.removed)
        );
        match &self.resumed {
            Some(r) => println!("{}", r.summary()),
            None => {
                if let Some(note) = self.claim.taken_over() {
                    eprintln!("warning: {note}");
                }
            }
        }
        if let Some(w) = &self.checkpoints {
            println!("{}", w.plan());
        }
    }
}

/// Why a command stops before its run; each names the file or folder and what to change.
#[derive(Debug)]
pub enum SetUpError {
    /// The scene file cannot be read.
    Read {
        /// The scene file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The scene is invalid (or its model cannot be estimated).
    Scene {
        /// The scene file.
        path: PathBuf,
        /// The model's error.
        source: Box<dyn Error + Send + Sync>,
    },
    /// The run is above its budget.
    Budget {
        /// The scene file.
        path: PathBuf,
        /// What is above the budget and the key or option to change.
        message: String,
    },
    /// The output folder or the Ctrl-C handler is refused.
    Refused(String),
    /// A file the scene reads (a mesh) cannot be read for the checkpoint's record of it.
    Input(std::io::Error),
    /// An earlier run's files cannot be removed from the output folder.
    Clear {
        /// The output folder.
        dir: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl fmt::Display for SetUpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SetUpError::Read { path, .. } => write!(f, "reading {}", path.display()),
            SetUpError::Scene { path, .. } => write!(f, "scene {}", path.display()),
            SetUpError::Budget { path, message } => write!(f, "scene {}: {message}", path.display()),
            SetUpError::Refused(m) => write!(f, "{m}"),
            SetUpError::Input(e) => write!(f, "{e}"),
            SetUpError::Clear { dir, .. } => write!(
                f,
                "output folder {}: removing the previous run's files",
                dir.display()
            ),
        }
    }
}

impl Error for SetUpError {
    fn source(&self) -> Option<&(dyn Error + 'static)> {
        match self {
            SetUpError::Read { source, .. } | SetUpError::Clear { source, .. } => Some(source),
            SetUpError::Scene { source, .. } => Some(&**source),
            SetUpError::Budget { .. } | SetUpError::Refused(_) | SetUpError::Input(_) => None,
        }
    }
}

/// A model's own steps in [`prepare`].
pub struct ModelSteps<Read, Inputs, Est, Clear> {
    /// Reads the scene from its text and the scene file's folder (where relative paths in it
    /// start).
    pub read: Read,
    /// The files the scene reads besides itself (a mesh), which a checkpoint records.
    pub inputs: Inputs,
    /// Estimates the run.
    pub estimate: Est,
    /// Removes an earlier run's files from a folder and says how many.
    pub clear_previous: Clear,
}

/// Everything a command checks before its run, in this order, stopping at the first refusal:
/// reads `scene_path`, validates it, chooses the output folder (`--resume`, `--out` or
/// `out/<model>-<scene name>`), checks the estimate against the budget, claims the folder for
/// `model` (locked against any other run until [`Prepared::claim`] is dropped), then either
/// reads the checkpoint to resume and checks it against the scene and its input files
/// (`--resume`), or removes an earlier run's files from the folder (one run per folder: they
/// would stand beside this one's), its checkpoint included. `steps` are the model's own.
pub fn prepare<S, ReadErr, EstimateErr>(
    model: &str,
    scene_path: &Path,
    options: &RunOptions,
    steps: ModelSteps<
        impl FnOnce(&str, &Path) -> Result<S, ReadErr>,
        impl FnOnce(&S) -> Vec<PathBuf>,
        impl FnOnce(&S) -> Result<Estimate, EstimateErr>,
        impl FnOnce(&Path) -> std::io::Result<usize>,
    >,
) -> Result<Prepared<S>, SetUpError>
where
    ReadErr: Error + Send + Sync + 'static,
    EstimateErr: Error + Send + Sync + 'static,
{
    let invalid = |e: Box<dyn Error + Send + Sync>| SetUpError::Scene {
        path: scene_path.to_path_buf(),
        source: e,
    };
    let text = crate::input::Cap::scene()
        .and_then(|cap| crate::input::read_text_capped(scene_path, cap))
        .map_err(|source| SetUpError::Read {
            path: scene_path.to_path_buf(),
            source,
        })?;
    let dir = scene_path.parent().unwrap_or(Path::new("."));
    let scene = (steps.read)(&text, dir).map_err(|e| invalid(Box::new(e)))?;
    let out_dir = options.out_dir(model, scene_path).map_err(SetUpError::Refused)?;
    let estimate = (steps.estimate)(&scene).map_err(|e| invalid(Box::new(e)))?;
    options
        .budget
        .budget()
        .check(&estimate)
        .map_err(|message| SetUpError::Budget {
            path: scene_path.to_path_buf(),
            message,
        })?;
    let claim = crate::paths::claim(&out_dir, model).map_err(SetUpError::Refused)?;
    let inputs = (steps.inputs)(&scene)
        .iter()
        .map(|p| crate::checkpoint::Input::of(p))
        .collect::<std::io::Result<Vec<_>>>()
        .map_err(SetUpError::Input)?;
    let header =
        crate::checkpoint::Header::new(model, env!("CARGO_PKG_VERSION"), &text, inputs, estimate.steps);
    let (removed, resumed) = match options.resume {
        Some(_) => {
            let resumed = crate::checkpoint::read(&out_dir, &header).map_err(SetUpError::Refused)?;
            (0, Some(resumed))
        }
        None => {
            let clear = |source| SetUpError::Clear {
                dir: out_dir.clone(),
                source,
            };
            let removed = (steps.clear_previous)(&out_dir).map_err(clear)?;
            let stale = crate::paths::remove_files([out_dir.join(crate::checkpoint::FILE)]).map_err(clear)?;
            (removed + stale, None)
        }
    };
    let every = options
        .checkpoint_every
        .or_else(|| resumed.as_ref().map(|r| r.header.every_s).filter(|&s| s > 0.0));
    let checkpoints = every.map(|s| crate::checkpoint::Writer::new(&out_dir, s, header));
    Ok(Prepared {
        scene,
        estimate,
        out_dir,
        removed,
        claim,
        resumed,
        checkpoints,
    })
}

/// A run that stopped before T, as the command's last word: why (in the model's words), and
/// where its output up to there went.
#[derive(Debug)]
pub struct StoppedEarly {
    /// Why, with when (and where, for an unstable run).
    pub why: String,
    /// The output folder.
    pub out_dir: PathBuf,
}

impl fmt::Display for StoppedEarly {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}; the output up to there is in {}",
            self.why,
            self.out_dir.display()
        )
    }
}

impl Error for StoppedEarly {}

/// The exit of a command: success, or the error with its causes on one line (`{:#}`) and exit
/// status 1; never a backtrace, whatever `RUST_BACKTRACE` says (it would bury the one line that
/// says what to change).
pub fn exit<E: fmt::Display>(result: Result<(), E>) -> std::process::ExitCode {
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(out: &Path) -> RunOptions {
        RunOptions {
            out: Some(out.to_path_buf()),
            budget: crate::options::BudgetOptions {
                max_memory: 1.0,
                max_steps: 10,
            },
            checkpoint_every: None,
            resume: None,
        }
    }

    fn costing(steps: u64) -> Estimate {
        Estimate {
            steps,
            steps_keys: "k",
            seconds: 1.0,
            parts: Vec::new(),
        }
    }

    /// A missing scene, an invalid one and one above the budget are each refused with the file
    /// named first, the cause after it.
    #[test]
    fn refusals_name_the_scene_then_the_cause() {
        let dir = std::env::temp_dir().join(format!("preflight-command-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.toml");
        let out = dir.join("out");
        let run = |n: u64| {
            prepare(
                "m",
                &scene,
                &options(&out),
                ModelSteps {
                    read: |t: &str, _: &Path| t.parse::<u64>(),
                    inputs: |_: &u64| Vec::new(),
                    estimate: move |_: &u64| Ok::<_, std::convert::Infallible>(costing(n)),
                    clear_previous: |_: &Path| Ok(2),
                },
            )
        };
        let missing = run(1).unwrap_err();
        assert!(missing.to_string().starts_with("reading "), "{missing}");
        assert!(missing.source().is_some());
        std::fs::write(&scene, "x").unwrap();
        let invalid = run(1).unwrap_err();
        assert_eq!(invalid.to_string(), format!("scene {}", scene.display()));
        assert_eq!(
            invalid.source().unwrap().to_string(),
            "invalid digit found in string"
        );
        std::fs::write(&scene, "7").unwrap();
        let above = run(11).unwrap_err();
        assert!(above.to_string().contains("above the budget of 10"), "{above}");
        let ready = run(10).unwrap();
        assert_eq!((ready.scene, ready.removed, ready.out_dir), (7, 2, out));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
