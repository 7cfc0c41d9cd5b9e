//! Hybrid cohesive-contact explicit dynamic finite-element model (Pundir & Anciaux 2020).
//!
//! Plane-strain Q4 bulk, extrinsic cohesive elements inserted on the fly on a declared interface
//! row, node-to-segment penalty contact with regularised Coulomb friction between crack faces
//! (hybrid model) or contact through the cohesive law (standard model, paper eq. 4), explicit
//! central differences. Public surface: [`Scene`], [`build`], [`step`], [`run`], [`RunOutput`].
#![warn(missing_docs)]

pub(crate) mod contact;
pub mod diag;
pub mod error;
pub mod law;
pub(crate) mod mesh;
pub mod model;
pub mod output;
pub mod probe;
pub mod scene;
pub mod solver;
#[cfg(test)]
mod test_scenes;

pub use error::{BuildError, RunError, SceneError};
pub use law::elastic::WaveSpeeds;
pub use mesh::gmsh;
pub use mesh::prepared;
pub use mesh::write_msh::grid_as_msh;
pub use model::build::{build, build_with_row_map};
pub use model::state::{Model, State, Workspace};
/// Re-export of the vector type used at the API (`Vector2<f64>`), so callers need not depend on nalgebra.
pub use nalgebra;
pub use output::paraview::{FieldSink, FieldSnapshot, ParaviewWriter};
pub use output::{
    ArrivalRecord, BoundaryRecord, ContactMeanRecord, CrackRecord, CrackTipRecord, EnergyRecord, FaceRecord,
    FieldRecord, FrictionRecord, InterfaceRecord, KktRecord, ProbeRecord, ProfileRecord,
    ResidualStressRecord, RunOutput, RunRecord, TipRecord, write_csv,
};
pub use scene::Scene;
pub use solver::central_difference::step;
pub use solver::estimate::estimate;
pub use solver::run::{ended, run, run_with_fields, run_with_progress};
