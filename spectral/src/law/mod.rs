//! Per-point interface laws (docs/spectral-model.md §5): pure functions of (params, inputs, old state).
//!
//! Sign conventions (stated once, pinned by tests): opening δ_n = u^+_2 − u^-_2 (> 0 open, < 0
//! interpenetration); slip δ_t = u^+_1 − u^-_1; traction T_i = σ_i2 on y = 0 (T_2 > 0 tension);
//! if the top face slides in +x relative to the bottom, the resisting T_1 is positive.
//! S^± = T^0 + f^± is the "dynamic stress" of each face: T^± = S^± ∓ Z^± v^±, with each face's
//! own impedance Z^± (equal for identical half-spaces; docs/spectral-model.md §5.2).

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
pub mod cohesive;
pub mod contact;
pub mod friction;
pub mod point;

/// How the solver runs the law over the grid points, chosen once at run time. Both give every
/// point the same bits ([`avx2`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LawBuild {
    /// Four points at once in AVX2 registers, the rest of a run of points one at a time.
    Avx2,
    /// One point at a time, [`point::step`].
    Scalar,
}

impl LawBuild {
    /// AVX2 where the CPU reports it, else the scalar law.
    pub(crate) fn detect() -> LawBuild {
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                return LawBuild::Avx2;
            }
        }
        LawBuild::Scalar
    }
}

/// The impedances of the two faces in one direction [Pa s/m]: ρc_s of each half-space in shear,
/// ρc_d in the normal direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedances {
    /// Z^+ of the top half-space [Pa s/m].
    pub top: f64,
    /// Z^- of the bottom half-space [Pa s/m].
    pub bottom: f64,
}

impl Impedances {
    /// The same impedance Z [Pa s/m] on both faces (identical half-spaces).
    pub fn equal(z: f64) -> Impedances {
        Impedances { top: z, bottom: z }
    }

    /// Z^+ + Z^- [Pa s/m].
    pub fn sum(&self) -> f64 {
        self.top + self.bottom
    }

    /// The traction both faces carry when they move together (stick), T = (Z^- S^+ + Z^+ S^-)/(Z^+ + Z^-)
    /// [Pa], from S^+ − Z^+ v = S^- + Z^- v. With equal impedances the weights are exactly 1/2, so
    /// this is (S^+ + S^-)/2 to the bit.
    pub fn stick_traction(&self, s_top: f64, s_bottom: f64) -> f64 {
        let sum = self.sum();
        (self.bottom / sum) * s_top + (self.top / sum) * s_bottom
    }

    /// The common velocity of two stuck faces, v = (S^+ − S^-)/(Z^+ + Z^-) [m/s].
    pub fn stick_velocity(&self, s_top: f64, s_bottom: f64) -> f64 {
        (s_top - s_bottom) / self.sum()
    }
}

/// State of an interface point (cRacklet's `ind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
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
