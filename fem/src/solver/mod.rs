//! Explicit central-difference integration and the run loop, on the structured grid and on Gmsh
//! meshes alike.

pub(crate) mod absorbing;
pub mod central_difference;
pub(crate) mod checkpoint;
pub(crate) mod contact_step;
pub mod estimate;
pub(crate) mod node;
pub mod run;
pub(crate) mod sweep;
