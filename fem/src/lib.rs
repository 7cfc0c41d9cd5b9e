//! Hybrid cohesive-contact explicit dynamic finite-element model (Pundir & Anciaux 2020).
#![warn(missing_docs)]

pub(crate) mod contact;
pub(crate) mod law;
