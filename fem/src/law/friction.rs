//! Regularised Coulomb friction, paper eq. (8): explicit return map (stick/slip); pure.
