//! Normal direction of the per-point velocity solve (docs/spectral-model.md §5.2 a–c): stick trial,
//! open trial with traction = strength, contact by matching normal displacements (gap closed
//! exactly at the end of the step, paper §3.2 "g = 0").

use super::Impedances;

/// Which branch the normal solve took.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalBranch {
    /// Faces move together (σ_s ≥ T*_2, σ_s ≠ 0).
    Stuck,
    /// Traction equals the normal strength; faces move independently.
    Open,
    /// Broken and closing: gap set to 0 at the end of the step; compressive traction.
    Contact,
}

/// Inputs of the normal solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalInput {
    /// Dynamic stress of the top face S^+_2 [Pa].
    pub s_top: f64,
    /// Dynamic stress of the bottom face S^-_2 [Pa].
    pub s_bottom: f64,
    /// Current normal strength σ_s [Pa].
    pub strength: f64,
    /// Current opening δ_n [m].
    pub opening: f64,
    /// Normal impedances Z_n^± = ρ^± c_d^± of the two faces [Pa s/m].
    pub impedance: Impedances,
    /// Time step Δt [s].
    pub dt: f64,
    /// Contact enabled.
    pub contact: bool,
}

/// Result of the normal solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalSolution {
    /// v^+_2 [m/s].
    pub v_top: f64,
    /// v^-_2 [m/s].
    pub v_bottom: f64,
    /// Interface traction T_2 [Pa] (> 0 tension).
    pub traction: f64,
    /// Branch taken.
    pub branch: NormalBranch,
}

/// §5.2 (a)–(c), with each face's impedance Z^± (equal for identical halves). Stick:
/// v = (S^+ − S^-)/(Z^+ + Z^-), T = (Z^- S^+ + Z^+ S^-)/(Z^+ + Z^-). Open: v^+ = (S^+ − σ_s)/Z^+,
/// v^- = (σ_s − S^-)/Z^-, T = σ_s. Contact (predicted gap < −ε): w = δ_n/Δt,
/// v^+ = (S^+ − S^- − Z^- w)/(Z^+ + Z^-), v^- = v^+ + w, T = S^+ − Z^+ v^+.
pub fn solve(i: &NormalInput) -> NormalSolution {
    let z = i.impedance;
    let t_star = z.stick_traction(i.s_top, i.s_bottom);
    if i.strength < t_star || i.strength == 0.0 {
        let v_top = (i.s_top - i.strength) / z.top;
        let v_bottom = (i.strength - i.s_bottom) / z.bottom;
        let gap = i.opening + i.dt * (v_top - v_bottom);
        if !(i.contact && gap < -f64::EPSILON) {
            return NormalSolution {
                v_top,
                v_bottom,
                traction: i.strength,
                branch: NormalBranch::Open,
            };
        }
        let w = i.opening / i.dt;
        let v_top = (i.s_top - i.s_bottom - z.bottom * w) / z.sum();
        return NormalSolution {
            v_top,
            v_bottom: v_top + w,
            traction: i.s_top - z.top * v_top,
            branch: NormalBranch::Contact,
        };
    }
    let v = z.stick_velocity(i.s_top, i.s_bottom);
    NormalSolution {
        v_top: v,
        v_bottom: v,
        traction: t_star,
        branch: NormalBranch::Stuck,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input(s_top: f64, s_bottom: f64, strength: f64, opening: f64) -> NormalInput {
        NormalInput {
            s_top,
            s_bottom,
            strength,
            opening,
            impedance: Impedances::equal(2.0),
            dt: 0.1,
            contact: true,
        }
    }

    #[test]
    fn compression_on_broken_point_closes_gap_exactly_with_compressive_traction() {
        let r = solve(&input(-1.0, -1.0, 0.0, 0.05));
        assert_eq!(r.branch, NormalBranch::Contact);
        assert!((0.05 + 0.1 * (r.v_top - r.v_bottom)).abs() < 1e-15);
        assert!(r.traction < 0.0);
    }

    #[test]
    fn tension_on_broken_point_opens_freely() {
        let r = solve(&input(1.0, 1.0, 0.0, 0.0));
        assert_eq!((r.branch, r.traction), (NormalBranch::Open, 0.0));
        assert!(r.v_top > 0.0 && r.v_bottom < 0.0);
    }

    #[test]
    fn intact_point_under_compression_sticks_with_identical_velocities() {
        let r = solve(&input(-1.0, -0.5, 1.0, 0.0));
        assert_eq!(r.branch, NormalBranch::Stuck);
        assert_eq!(r.v_top, r.v_bottom);
        assert_eq!(r.traction, -0.75);
    }
}
