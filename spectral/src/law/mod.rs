//! Per-point interface laws (docs/spectral-model.md §5): pure functions of (params, inputs, old state).
//!
//! Sign conventions (stated once, pinned by tests): opening δ_n = u^+_2 − u^-_2 (> 0 open, < 0
//! interpenetration); slip δ_t = u^+_1 − u^-_1; traction T_i = σ_i2 on y = 0 (T_2 > 0 tension);
//! if the top face slides in +x relative to the bottom, the resisting T_1 is positive.
//! S^± = T^0 + f^± is the "dynamic stress" of each face: T^± = S^± ∓ Z v^±.

pub mod cohesive;
pub mod contact;
pub mod friction;
pub mod point;

/// State of an interface point (cRacklet's `ind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[repr(u8)]
pub enum PointState {
    /// Untouched: full strength.
    Intact = 0,
    /// In the process zone: 0 < a < 1.
    Cohesive = 1,
    /// Fully broken (a ≥ 1 at some time, or pre-cut).
    Broken = 2,
    /// Broken and in contact this step.
    Contact = 3,
}

impl PointState {
    /// Fully broken (ind ∈ {2, 3}).
    pub fn is_broken(self) -> bool {
        self >= PointState::Broken
    }
}
