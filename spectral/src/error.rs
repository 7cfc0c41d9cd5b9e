//! Typed errors of the spectral solver (thiserror); each names the scene key, the value and what
//! is allowed.

use crate::output::RunOutput;
pub use preflight::Problem;

/// A scene that cannot be parsed or holds values outside their allowed ranges.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The TOML text does not parse or a value has the wrong type (the message has the line).
    #[error("scene does not parse: {0}")]
    Parse(String),
    /// A value outside its allowed range.
    #[error("{field} = {value} out of range; allowed {allowed}")]
    OutOfRange {
        /// Dotted key of the offending field.
        field: String,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// Keys that do not fit together; `key` is the one to change.
    #[error("{key}: {message}")]
    Inconsistent {
        /// Dotted scene key.
        key: String,
        /// What does not fit.
        message: String,
    },
    /// Every problem of a scene, each with its key and the line of the user's file.
    #[error("{}", preflight::problems_text(problems))]
    Invalid {
        /// The problems, in the order of the file.
        problems: Vec<Problem>,
    },
}

impl SceneError {
    /// The dotted key the error is about (`None` for a file that does not parse or a list).
    pub fn key(&self) -> Option<&str> {
        match self {
            SceneError::Parse(_) | SceneError::Invalid { .. } => None,
            SceneError::OutOfRange { field, .. } => Some(field),
            SceneError::Inconsistent { key, .. } => Some(key),
        }
    }

    /// The problems this error stands for (one, or the list of `Invalid`).
    pub fn problems(&self) -> Vec<Problem> {
        preflight::SceneErrorKind::problems(self)
    }
}

/// Its problems and the conversion from a refused file are preflight's, shared by every model.
impl preflight::SceneErrorKind for SceneError {
    fn parse(message: String) -> SceneError {
        SceneError::Parse(message)
    }

    fn invalid(problems: Vec<Problem>) -> SceneError {
        SceneError::Invalid { problems }
    }

    fn listed(&self) -> Option<&[Problem]> {
        match self {
            SceneError::Invalid { problems } => Some(problems),
            _ => None,
        }
    }

    fn key(&self) -> Option<&str> {
        SceneError::key(self)
    }
}

impl From<preflight::Refused> for SceneError {
    fn from(r: preflight::Refused) -> SceneError {
        preflight::SceneErrorKind::refused(r)
    }
}

/// A failure while building the model from a valid scene.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The sum-of-exponentials fit of the kernels did not reach the requested accuracy.
    #[error(
        "spectral.fast_tolerance = {requested:e}: the sum-of-exponentials fit of the kernels \
         ({kernel}) {} on [0, spectral.kernel_cutoff] for material.poisson_ratio = \
         {poisson_ratio}; raise spectral.fast_tolerance, raise spectral.kernel_cutoff, or use \
         spectral.convolution = \"direct\"",
        reached(*.achieved)
    )]
    FitFailed {
        /// Kernel names (H11, H22, K12).
        kernel: &'static str,
        /// Achieved max error on [0, kernel_cutoff] [-].
        achieved: f64,
        /// Requested tolerance [-].
        requested: f64,
        /// Poisson ratio of the kernels [-].
        poisson_ratio: f64,
    },
}

/// What the best fit reached, in words.
fn reached(achieved: f64) -> String {
    if achieved.is_finite() {
        format!("reaches only {achieved:.3e}")
    } else {
        "cannot be computed (too few kernel samples)".to_string()
    }
}

/// A failure during the time loop.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// Building the model failed.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// A non-finite value appeared; `partial` holds everything recorded up to the previous step.
    #[error("run went unstable at step {step} (t = {time_s:e} s) at {location}")]
    Unstable {
        /// Step index n (t = n dt).
        step: u64,
        /// Time of the step [s].
        time_s: f64,
        /// Where: grid point index and x [m].
        location: String,
        /// Output computed so far.
        partial: Box<RunOutput>,
    },
    /// A checkpoint (`--checkpoint-every`) could not be written: the run stopped there, as with
    /// any output that fails; `partial` holds everything recorded so far.
    #[error("run stopped at step {step} (t = {time_s:e} s): {message}")]
    OutputFailed {
        /// Last step computed.
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// What failed, naming the file.
        message: String,
        /// Output computed so far.
        partial: Box<RunOutput>,
    },
    /// The checkpoint to resume from cannot be read or does not fit the model the scene builds;
    /// no step ran.
    #[error("{message}")]
    Resume {
        /// Why, naming the checkpoint file.
        message: String,
    },
    /// Stopped on request (Ctrl-C, SIGTERM) before T; `partial` holds everything recorded so far.
    #[error("run stopped on request at step {step} (t = {time_s:e} s)")]
    Interrupted {
        /// Last step computed.
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// Output computed so far.
        partial: Box<RunOutput>,
    },
}
