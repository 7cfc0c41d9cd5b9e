//! Typed errors of the library: scene validation, model building and the time loop.

use crate::records::RunOutput;
use thiserror::Error;

pub use preflight::Problem;
use preflight::problems_text;

/// A scene that cannot be parsed or holds a value outside its allowed range.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The TOML text does not parse or does not match the scene format (unknown key, wrong type).
    #[error("scene does not parse: {0}")]
    Parse(String),
    /// A number outside its allowed range.
    #[error("{field} = {} out of range; allowed {allowed}", number(*value))]
    OutOfRange {
        /// Dotted scene key, e.g. `fem.element_size`.
        field: String,
        /// The offending value.
        value: f64,
        /// Human-readable allowed range.
        allowed: String,
    },
    /// A string option with an unknown value.
    #[error("{field} = \"{value}\" is not allowed; allowed {allowed}")]
    BadOption {
        /// Dotted scene key.
        field: String,
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
    /// Keys that do not fit together (domain not a multiple of h, crack tip not on a node, two
    /// keys given where one is allowed, ...); `key` is the one to change.
    #[error("{key}: {message}")]
    Inconsistent {
        /// Dotted scene key, e.g. `fem.element_size`.
        key: String,
        /// What does not fit.
        message: String,
    },
    /// Every problem of a scene file, each with its key and the line of the user's file.
    #[error("{}", problems_text(problems))]
    Invalid {
        /// The problems, in the order of the file's sections.
        problems: Vec<Problem>,
    },
}

impl SceneError {
    /// The dotted key the error is about (`None` for a file that does not parse).
    pub fn key(&self) -> Option<&str> {
        match self {
            SceneError::Parse(_) | SceneError::Invalid { .. } => None,
            SceneError::OutOfRange { field, .. } | SceneError::BadOption { field, .. } => Some(field),
            SceneError::UnstableTimeStep { .. } => Some("fem.time_step"),
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
    /// A boundary condition holds a junction of interfaces.
    #[error(
        "a boundary condition holds the junction of interfaces at ({x}, {y}) m; a junction must not be \
         held (its copies are tied as a group that a support does not carry)"
    )]
    HeldJunction {
        /// x of the junction [m].
        x: f64,
        /// y of the junction [m].
        y: f64,
    },
    /// An absorbing boundary part runs through a junction of interfaces.
    #[error(
        "an absorbing boundary part (fem.boundary.NAME.absorbing) runs through the junction of interfaces at \
         ({x}, {y}) m; a junction's copies are tied as a group that a dashpot does not carry: end the \
         absorbing part before it"
    )]
    AbsorbingJunction {
        /// x of the junction [m].
        x: f64,
        /// y of the junction [m].
        y: f64,
    },
    /// The unstructured kernel cannot be built on the scene's Gmsh mesh.
    #[error("the mesh of fem.mesh.file: {0}")]
    Mesh(#[from] UnstructuredError),
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
    /// Stopped on request (Ctrl-C, SIGTERM) before T. `partial` holds what was computed so far.
    #[error("run stopped on request at step {step}, t = {time_s} s")]
    Interrupted {
        /// Last step computed.
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// Output recorded up to there: the samples taken before the stop.
        partial: Box<RunOutput>,
    },
    /// A ParaView snapshot or a checkpoint could not be written (disk full, folder removed, ...):
    /// the run stops at once. `partial` holds what was computed so far.
    #[error("output at step {step}, t = {time_s} s not written: {message}")]
    FieldOutput {
        /// Step of the output.
        step: u64,
        /// Its time [s].
        time_s: f64,
        /// What failed: `field snapshot: …` or `checkpoint: …`, naming the file.
        message: String,
        /// Output recorded up to there.
        partial: Box<RunOutput>,
    },
    /// The checkpoint to resume from does not fit this model (checked before the first step).
    #[error("resuming: {0}")]
    Resume(String),
}

/// A number for a message: as written for ordinary magnitudes (`0.25`, `70000000`), in scientific
/// notation beyond (`1e-300`, not three hundred zeros); the shortest form that reads back exactly.
pub fn number(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && a.is_finite() && !(1e-4..1e9).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod number_tests {
    use super::number;

    #[test]
    fn numbers_read_as_written_and_extremes_in_scientific_notation() {
        assert_eq!(number(0.25), "0.25");
        assert_eq!(number(70e6), "70000000");
        assert_eq!(number(1e-300), "1e-300");
        assert_eq!(number(-2.1665e-6), "-2.1665e-6");
        assert_eq!(number(1e300), "1e300");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::NAN), "NaN");
        assert_eq!(number(f64::INFINITY), "inf");
    }
}

/// A mesh the unstructured kernel cannot be built on.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum UnstructuredError {
    /// An element with a non-positive (or non-finite) Jacobian determinant at a quadrature point:
    /// inverted or degenerate. The mesh reader refuses such elements; this guards meshes built by
    /// hand.
    #[error("element {element} is inverted or degenerate (det J = {det_j} m²)")]
    InvertedElement {
        /// Element tag ([`crate::mesh::gmsh::BulkElement::tag`]).
        element: u64,
        /// The offending determinant (T3: twice the signed area) [m²].
        det_j: f64,
    },
    /// A density that is not finite and positive.
    #[error("density = {0} kg/m³ must be finite and positive")]
    BadDensity(f64),
    /// No material, more than 256, or an element material index out of range or missing.
    #[error("every element needs a material index into 1 to 256 materials")]
    BadMaterials,
    /// More nodes or edges than the 32-bit indices of the kernel hold.
    #[error("the mesh is too large for the kernel's 32-bit indices")]
    TooLarge,
}
