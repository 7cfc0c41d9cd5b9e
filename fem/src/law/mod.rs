//! Pure constitutive laws: (params, inputs, old state) -> (output, new state).

pub mod cohesive;
pub mod elastic;
pub(crate) mod friction;
pub(crate) mod penalty;
