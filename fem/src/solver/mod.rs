//! Explicit central-difference integration and the run loop (structured grid), and the bulk-only
//! time loop on unstructured meshes ([`unstructured`]).

pub mod central_difference;
pub(crate) mod contact_step;
pub mod estimate;
pub(crate) mod node;
pub mod profile;
pub mod run;
pub(crate) mod sweep;
pub mod unstructured;
