//! Pure constitutive laws: (params, inputs, old state) -> (output, new state).

pub(crate) mod friction;
pub(crate) mod penalty;
