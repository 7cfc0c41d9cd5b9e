//! Structured Q4 meshes with a twinned interface row.

pub(crate) mod interfaces;
pub(crate) mod structured;
