//! Shear direction of the per-point velocity solve (docs/spectral-model.md §5.2 d) and the simplified
//! Prakash regularisation of the friction normal stress (§5.3, paper eq. 14).
//!
//! # Deviation
//! The paper's eq. (14) reads dσ̃/dt = (σ̃ − σ)/t*; that sign is a typo (unstable). We integrate
//! dσ̃/dt = −(σ̃ − σ)/t* with backward Euler, r = Δt/t*, as cRacklet does, and drop cRacklet's special
//! case at its second step (σ̃ = T_2), which only matters for step loads on pre-compressed cracks.
//! Slip uses the momentum-conserving form T_1 = τ sgn(T*_1) (§5.2 d, preferred) rather than cRacklet's
//! per-face sgn(S^±_1); they coincide whenever S^+_1 and S^-_1 have the same sign.

use super::Impedances;

/// Result of the shear solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearSolution {
    /// v^+_1 [m/s].
    pub v_top: f64,
    /// v^-_1 [m/s].
    pub v_bottom: f64,
    /// Interface traction T_1 [Pa] (resists relative sliding: positive when the top slides in +x).
    pub traction: f64,
    /// True when the point slips (τ < |T*_1| or τ == 0).
    pub slipping: bool,
}

/// §5.2 (d) with shear strength τ ≥ 0 [Pa] and the faces' shear impedances Z^± = ρ^± c_s^± [Pa s/m]:
/// trial T* = (Z^- S^+ + Z^+ S^-)/(Z^+ + Z^-) (the stick traction; (S^+ + S^-)/2 for identical
/// halves); slip if τ < |T*| or τ == 0: T = τ sgn(T*), v^+ = (S^+ − T)/Z^+, v^- = (T − S^-)/Z^-;
/// else stick with v^± = (S^+ − S^-)/(Z^+ + Z^-), T = T*.
pub fn solve_shear(s_top: f64, s_bottom: f64, strength: f64, z: Impedances) -> ShearSolution {
    let t_trial = z.stick_traction(s_top, s_bottom);
    if strength < t_trial.abs() || strength == 0.0 {
        let traction = strength * t_trial.signum();
        return ShearSolution {
            v_top: (s_top - traction) / z.top,
            v_bottom: (traction - s_bottom) / z.bottom,
            traction,
            slipping: true,
        };
    }
    let v = z.stick_velocity(s_top, s_bottom);
    ShearSolution {
        v_top: v,
        v_bottom: v,
        traction: t_trial,
        slipping: false,
    }
}

/// Backward-Euler step of dσ̃/dt = −(σ̃ − σ)/t*: σ̃ ← (σ̃_prev + r σ)/(1 + r), r = Δt/t*, taken at
/// every step of every point (paper eq. 14). σ is the interface's compressive normal traction T_2
/// where the faces touch and 0 where they are apart, so out of contact σ̃ relaxes towards 0 over
/// t* instead of vanishing at once, and a point touching again starts from what is left of it.
/// `r = None` (t* = 0) gives plain Coulomb σ̃ = σ.
pub fn regularized_normal(prev: f64, normal_stress: f64, r: Option<f64>) -> f64 {
    match r {
        None => normal_stress,
        Some(r) => (prev + r * normal_stress) / (1.0 + r),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_traction_resists_relative_sliding() {
        // Top face driven in +x: T_1 = +τ and the top moves faster than the bottom.
        let r = solve_shear(3.0, 1.0, 1.0, Impedances::equal(2.0));
        assert!(r.slipping && r.traction == 1.0 && r.v_top > r.v_bottom);
    }

    #[test]
    fn stick_keeps_faces_together() {
        let r = solve_shear(0.5, 0.1, 1.0, Impedances::equal(2.0));
        assert!(!r.slipping);
        assert_eq!(r.v_top, r.v_bottom);
        assert_eq!(r.traction, 0.3);
    }

    #[test]
    fn slip_conserves_momentum() {
        let r = solve_shear(3.0, -0.5, 0.2, Impedances::equal(2.0));
        // traction continuity: S^+ − Z v^+ = S^- + Z v^-
        assert!(((3.0 - 2.0 * r.v_top) - (-0.5 + 2.0 * r.v_bottom)).abs() < 1e-15);
    }

    #[test]
    fn regularised_stress_relaxes_to_normal_traction() {
        let mut s = regularized_normal(0.0, -1.0, Some(0.1));
        assert!((s + 0.1 / 1.1).abs() < 1e-15);
        for _ in 0..400 {
            s = regularized_normal(s, -1.0, Some(0.1));
        }
        assert!((s + 1.0).abs() < 1e-12);
    }

    /// Eq. (14) out of contact: σ = 0, so σ̃ decays by 1/(1 + r) per step (backward Euler), to
    /// e^{-t/t*} as Δt → 0, instead of dropping to 0 at once; touching again continues from there.
    #[test]
    fn out_of_contact_the_regularised_stress_relaxes_instead_of_resetting() {
        let r = 0.05;
        let mut s = -1.0;
        for _ in 0..20 {
            s = regularized_normal(s, 0.0, Some(r));
        }
        let expected = -(1.0f64 + r).powi(-20);
        assert!((s - expected).abs() < 1e-15, "{s} against {expected}");
        assert!(s < -0.3, "after one t* a third of the stress is left, not 0");
        let back = regularized_normal(s, -1.0, Some(r));
        assert!((back - (s - r) / (1.0 + r)).abs() < 1e-15);
    }
}
