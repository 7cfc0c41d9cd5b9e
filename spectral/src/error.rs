//! Typed errors of the spectral solver (thiserror); each names the field, the value and the
//! allowed range.

use crate::output::RunOutput;

/// A scene that cannot be parsed or is out of range.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The TOML text does not parse or has unknown/missing keys.
    #[error("scene TOML: {0}")]
    Toml(#[from] toml::de::Error),
    /// A value outside its allowed range.
    #[error("{field} = {value} out of range; allowed {allowed}")]
    OutOfRange {
        /// Dotted key of the offending field.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// Mutually exclusive or jointly required keys.
    #[error("{0}")]
    Inconsistent(String),
}

/// A failure while building the model from a valid scene.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The sum-of-exponentials fit of a kernel did not reach the requested accuracy.
    #[error("fast convolution: fit of {kernel} reached max error {achieved:e} > requested {requested:e}")]
    FitFailed {
        /// Kernel name (H11, H22, K12).
        kernel: &'static str,
        /// Achieved max error on [0, kernel_cutoff] [-].
        achieved: f64,
        /// Requested tolerance [-].
        requested: f64,
    },
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
}
