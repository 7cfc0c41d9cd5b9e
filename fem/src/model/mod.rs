//! Scene -> Model + State + Workspace, and the model's kernels (bulk, cohesive, insertion, loading).

pub mod build;
pub(crate) mod bulk;
pub mod cohesive;
pub(crate) mod face_stress;
pub(crate) mod insertion;
pub(crate) mod layers;
pub(crate) mod loading;
pub(crate) mod mapped;
pub(crate) mod reduce;
pub mod state;
pub(crate) mod stencil;
pub(crate) mod stress;
pub mod unstructured;
