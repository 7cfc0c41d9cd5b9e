//! Typed errors of the library: scene validation, model building and the time loop.

use crate::output::RunOutput;
use thiserror::Error;

/// A scene that cannot be parsed or holds a value outside its allowed range.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The TOML text does not parse or does not match the scene format (unknown key, wrong type).
    #[error("scene does not parse: {0}")]
    Parse(String),
    /// A number outside its allowed range.
    #[error("{field} = {value} out of range; allowed {allowed}")]
    OutOfRange {
        /// Dotted scene key, e.g. `fem.element_size`.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// Human-readable allowed range.
        allowed: String,
    },
    /// A string option with an unknown value.
    #[error("{field} = \"{value}\" is not allowed; allowed {allowed}")]
    BadOption {
        /// Dotted scene key.
        field: &'static str,
        /// The offending value.
        value: String,
        /// The allowed values.
        allowed: &'static str,
    },
    /// A requested time step above the stable limit.
    #[error(
        "fem.time_step = {dt_s} s exceeds the stable limit {limit_s} s (docs/fem-model.md §2, paper eq. 12, alpha <= 0.95)"
    )]
    UnstableTimeStep {
        /// Requested step [s].
        dt_s: f64,
        /// Stable limit [s].
        limit_s: f64,
    },
    /// The mesh does not fit the geometry (domain not a multiple of h, crack tip not on a node, ...).
    #[error("mesh does not fit the geometry: {0}")]
    Geometry(String),
}

/// The model cannot be built from a valid scene (degenerate element, ...).
#[derive(Debug, Error)]
pub enum BuildError {
    /// An element with det J <= 0 at a Gauss point.
    #[error("element {element} has det J = {det_j} <= 0 at a Gauss point (inverted or degenerate quad)")]
    InvertedElement {
        /// Element index.
        element: usize,
        /// The Jacobian determinant [m^2].
        det_j: f64,
    },
}

/// The time loop stopped.
#[derive(Debug, Error)]
pub enum RunError {
    /// The scene is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The model could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// Non-finite or runaway velocity (|v| > 10 c_d). `partial` holds what was computed so far.
    #[error("run unstable at step {step}, t = {time_s} s: {location}")]
    Unstable {
        /// Step index at which the guard fired.
        step: u64,
        /// Time [s].
        time_s: f64,
        /// Where: node id, position and velocity.
        location: String,
        /// Output recorded up to the failure.
        partial: Box<RunOutput>,
    },
}
