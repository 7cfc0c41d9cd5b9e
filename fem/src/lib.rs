//! Hybrid cohesive-contact explicit dynamic finite-element model (Pundir & Anciaux 2020).
//!
//! Plane-strain Q4 (structured grid) or T3/Q4 (Gmsh mesh) bulk, extrinsic cohesive elements
//! inserted on the fly on declared interfaces, node-to-segment penalty contact with regularised
//! Coulomb friction between crack faces (hybrid model) or contact through the cohesive law
//! (standard model, paper eq. 4), explicit central differences.
//!
//! # Plan
//! One run goes scene → validated [`Scene`] → [`Model`] + [`State`] + [`Workspace`] → step loop →
//! records ([`RunOutput`]) → files (docs/architecture.md). Modules import only from the ones
//! listed before them:
//! - [`law`] (pure constitutive laws), [`records`] (plain record types), [`profile`] (wall time
//!   per phase);
//! - `contact` (node-to-segment detection and resolution) and `mesh` (the grid, Gmsh meshes,
//!   interface rows);
//! - [`error`] (every typed error);
//! - [`scene`] (TOML → validated `Scene`; no physics);
//! - [`model`] (`Scene` → `Model` + `State` + `Workspace`, and the model's kernels);
//! - [`diag`] and [`probe`] (read-only observers of the state);
//! - [`solver`] (the step and the one time loop);
//! - [`output`] (CSV and ParaView files; the only module that writes files).
//!
//! # Public surface
//! - running a scene: [`Scene`], [`estimate`], [`runs_best_on_two_cores`], [`run`],
//!   [`run_with_progress`], [`run_with_fields`], and [`ended`] (how a run ended, as
//!   `preflight::RunEnded`);
//! - stepping by hand: [`build`], [`build_with_row_map`], [`step`], [`Model`], [`State`],
//!   [`Workspace`];
//! - results: [`RunOutput`] and its records, [`write_csv`], [`ParaviewWriter`] (a
//!   [`FieldSink`] of [`FieldSnapshot`]s);
//! - meshes: [`gmsh`] (the reader), [`prepared`] (a scene's mesh with its roles),
//!   [`grid_as_msh`];
//! - errors: [`SceneError`], [`BuildError`], [`RunError`].
//!
//! `law`, `model::cohesive`, `model::unstructured` and `probe` are public for the validation
//! tests and the benchmarks.
#![warn(missing_docs)]

pub(crate) mod contact;
pub mod diag;
pub mod error;
mod hint;
pub mod law;
pub(crate) mod mesh;
pub mod model;
pub mod output;
pub mod probe;
pub mod profile;
pub mod records;
pub mod scene;
pub mod solver;
#[cfg(test)]
mod test_scenes;

pub use error::{BuildError, RunError, SceneError};
pub use law::elastic::WaveSpeeds;
pub use mesh::gmsh;
pub use mesh::prepared;
pub use model::build::{build, build_with_row_map};
pub use model::state::{Model, State, Workspace};
/// Re-export of the vector type used at the API (`Vector2<f64>`), so callers need not depend on nalgebra.
pub use nalgebra;
pub use output::paraview::ParaviewWriter;
pub use output::write_csv;
pub use records::fields::{FieldSink, FieldSnapshot};
pub use records::{
    ArrivalRecord, BoundaryRecord, ContactMeanRecord, CrackRecord, CrackTipRecord, EnergyRecord, FaceRecord,
    FieldRecord, FrictionRecord, InterfaceRecord, KktRecord, ProbeRecord, ProfileRecord,
    ResidualStressRecord, RunOutput, RunRecord, TipRecord,
};
pub use scene::Scene;
pub use scene::write_msh::grid_as_msh;
pub use solver::central_difference::step;
pub use solver::estimate::{estimate, runs_best_on_two_cores};
pub use solver::run::{ended, run, run_checkpointed, run_with_fields, run_with_progress};
