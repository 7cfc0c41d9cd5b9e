//! Structured Q4 meshes with a twinned interface row, and the reader of Gmsh meshes (not yet used
//! by the solver).

pub mod gmsh;

pub(crate) mod interfaces;
pub(crate) mod structured;
