//! Normal penalty laws: node-to-segment pressure p_N = ε_n p (paper eq. 8, docs/fem-model.md §5.2), and the
//! compression penalty of the `standard` cohesive-contact model (paper eq. 4, docs/fem-model.md §3.4); pure.

use nalgebra::Vector2;

/// Node-to-segment normal pressure, paper eq. (8) left: p_N = ε_n p [Pa].
///
/// - `eps_n`: normal penalty ε_n [Pa/m] (traction per unit penetration, not a nodal spring).
/// - `penetration`: p = −g [m]; p ≤ 0 (separated or touching) gives no pressure.
///
/// Sign convention: p_N ≥ 0 is a compressive pressure; the force on the slave is A p_N n_e, along
/// the master's outward normal (docs/fem-model.md §10.7: eq. (8)'s T^n = ε_n g n is its negative).
pub(crate) fn normal_pressure(eps_n: f64, penetration: f64) -> f64 {
    eps_n * penetration.max(0.0)
}

/// Compression penalty of the `standard` model, paper eq. (4), docs/fem-model.md §3.4: the traction
/// added to the cohesive law's, ΔT = ε_n δ_n n [Pa] when δ_n < 0, and 0 otherwise.
///
/// - `eps_n`: ε_n [Pa/m]; `normal_opening`: δ_n = Δ·n [m] (opening + minus −, negative when the
///   faces interpenetrate); `normal`: the cohesive element's unit normal n (− → +) [-].
///
/// Sign convention: T·n > 0 pulls the faces together (docs/fem-model.md §3.2), so ε_n δ_n < 0 pushes
/// them apart. The caller decides when the penalty is active (its `pen` flag, §3.3) and may pass
/// any δ_n; a positive δ_n gives zero here.
pub(crate) fn compression_traction(eps_n: f64, normal_opening: f64, normal: Vector2<f64>) -> Vector2<f64> {
    normal * (eps_n * normal_opening.min(0.0))
}

// Provided for the standard model's energy output (docs/fem-model.md §8.3); fem-core's energy currently
// integrates the total cohesive traction instead.
#[cfg_attr(not(test), allow(dead_code))]
/// Stored energy of the compression penalty per unit length, ½ ε_n δ_n² [J/m²] for δ_n < 0
/// (docs/fem-model.md §3.4, §8.3), and 0 otherwise.
pub(crate) fn compression_energy(eps_n: f64, normal_opening: f64) -> f64 {
    let d = normal_opening.min(0.0);
    0.5 * eps_n * d * d
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS_N: f64 = 2.1e10; // Pa/m, 300 E per metre (docs/cases.md)

    #[test]
    fn pressure_is_eps_n_times_penetration_and_zero_when_separated() {
        assert_eq!(normal_pressure(EPS_N, 2e-6), EPS_N * 2e-6);
        assert_eq!(normal_pressure(EPS_N, -1e-6), 0.0);
        assert_eq!(normal_pressure(EPS_N, 0.0), 0.0);
    }

    #[test]
    fn compression_penalty_pushes_faces_apart_only_when_closing() {
        let n = Vector2::new(0.0, 1.0);
        // δ_n < 0 (interpenetration): T·n = ε_n δ_n < 0 pushes apart (T·n > 0 would pull together).
        let t = compression_traction(EPS_N, -1e-6, n);
        assert_eq!(t, Vector2::new(0.0, -EPS_N * 1e-6));
        assert!(t.dot(&n) < 0.0);
        assert_eq!(compression_traction(EPS_N, 1e-6, n), Vector2::zeros());
        assert!((compression_energy(EPS_N, -1e-6) - 0.5 * EPS_N * 1e-12).abs() < 1e-15);
        assert_eq!(compression_energy(EPS_N, 1e-6), 0.0);
    }

    #[test]
    fn compression_energy_is_the_integral_of_the_penalty_traction() {
        // d/dδ_n (½ ε_n δ_n²) = ε_n δ_n = ΔT·n: central difference of the energy.
        let (d, h, n) = (-3e-6, 1e-9, Vector2::new(0.6, 0.8));
        let de = (compression_energy(EPS_N, d + h) - compression_energy(EPS_N, d - h)) / (2.0 * h);
        let t = compression_traction(EPS_N, d, n).dot(&n);
        assert!((de - t).abs() < 1e-9 * t.abs());
    }
}
