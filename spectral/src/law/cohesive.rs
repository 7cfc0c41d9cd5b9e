//! Strength update of the linear coupled cohesive law, irreversible (docs/spectral-model.md §5.1;
//! cRacklet `CohesiveLaw::updateCohesiveLaw`).
//!
//! a = sqrt((δ_n/δ_cn)² + (δ_t/δ_ct)²); σ_s = σ_max − (σ_max − σ_res) a, τ_s = τ_max − (τ_max − τ_res) a.
//! Mapping from paper eqs. (2)–(3), where δ = sqrt((β²/κ²) δ_t² + δ_n²): σ_max = σ_c, δ_cn = δ_c,
//! τ_max = β σ_c, δ_ct = κ δ_c/β, so that a = δ/δ_c and, for δ_n = 0, |T_1| = β σ_c (1 − β|δ_t|/(κ δ_c))
//! as eq. (2) gives: peak shear β σ_c and mode-II fracture energy G_II = ½ τ_max δ_ct = κ G_c (the
//! paper's κ = G_II/G_I), the same convention as the FE law.
//!
//! # Deviation
//! In mixed-mode opening the paper scales the two components by δ_n/δ and β δ_t/δ (circular
//! envelope) while this law bounds σ and τ separately (box envelope, cRacklet). Both agree for pure
//! mode II under compression (the centre-crack case). Damage is irreversible through the strength
//! history (strength only decreases), equivalent to the paper's δ_max history under monotonic loading.

use super::PointState;

/// Parameters of the linear coupled law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveParams {
    /// Peak normal strength σ_max [Pa].
    pub sigma_max: f64,
    /// Peak shear strength τ_max [Pa].
    pub tau_max: f64,
    /// Critical normal opening δ_cn [m].
    pub delta_cn: f64,
    /// Critical slip δ_ct [m].
    pub delta_ct: f64,
    /// Residual normal strength σ_res [Pa].
    pub sigma_res: f64,
    /// Residual shear strength τ_res [Pa].
    pub tau_res: f64,
}

impl CohesiveParams {
    /// From the paper's TSL parameters (eq. 2–3): σ_c [Pa], δ_c [m], β [-], κ [-]; residuals 0.
    pub fn from_paper(sigma_c: f64, delta_c: f64, beta: f64, kappa: f64) -> CohesiveParams {
        CohesiveParams {
            sigma_max: sigma_c,
            tau_max: beta * sigma_c,
            delta_cn: delta_c,
            delta_ct: kappa * delta_c / beta,
            sigma_res: 0.0,
            tau_res: 0.0,
        }
    }
}

/// Current strengths and state of one point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Strength {
    /// Normal strength σ_s [Pa].
    pub sigma: f64,
    /// Shear strength τ_s [Pa].
    pub tau: f64,
    /// Point state.
    pub state: PointState,
}

impl Strength {
    /// Untouched point.
    pub fn intact(p: &CohesiveParams) -> Strength {
        Strength {
            sigma: p.sigma_max,
            tau: p.tau_max,
            state: PointState::Intact,
        }
    }
    /// Pre-cut point: residual strengths, broken.
    pub fn precut(p: &CohesiveParams) -> Strength {
        Strength {
            sigma: p.sigma_res,
            tau: p.tau_res,
            state: PointState::Broken,
        }
    }
}

/// Damage indicator a = sqrt((δ_n/δ_cn)² + (δ_t/δ_ct)²) [-].
pub fn damage_ratio(p: &CohesiveParams, opening: f64, slip: f64) -> f64 {
    ((opening / p.delta_cn).powi(2) + (slip / p.delta_ct).powi(2)).sqrt()
}

/// Strength update from the current jumps (§5.1). Exact equality tests are part of the logic.
pub fn update(p: &CohesiveParams, opening: f64, slip: f64, s: Strength) -> Strength {
    if opening == 0.0 && slip == 0.0 && !s.state.is_broken() {
        return s;
    }
    let a = damage_ratio(p, opening, slip);
    if a >= 1.0 || s.sigma == p.sigma_res || s.tau == p.tau_res {
        if s.sigma == p.sigma_res && opening < -f64::EPSILON {
            return s;
        }
        return Strength {
            sigma: p.sigma_res,
            tau: p.tau_res,
            state: PointState::Broken,
        };
    }
    let sigma = p.sigma_max - (p.sigma_max - p.sigma_res) * a;
    let tau = p.tau_max - (p.tau_max - p.tau_res) * a;
    // Irreversible: strength never recovers (§5.1 "only the strength decreases").
    Strength {
        sigma: sigma.min(s.sigma),
        tau: tau.min(s.tau),
        state: PointState::Cohesive,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> CohesiveParams {
        CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0)
    }

    #[test]
    fn untouched_point_keeps_peak_strength() {
        let s = update(&p(), 0.0, 0.0, Strength::intact(&p()));
        assert_eq!(s, Strength::intact(&p()));
    }

    #[test]
    fn linear_softening_in_pure_shear_matches_paper_eq3() {
        let s = update(&p(), 0.0, 0.25e-4, Strength::intact(&p()));
        assert!((s.tau - 0.3e6).abs() < 1e-6 && s.state == PointState::Cohesive);
    }

    #[test]
    fn strength_is_irreversible_on_unloading() {
        let s1 = update(&p(), 0.0, 0.5e-4, Strength::intact(&p()));
        let s2 = update(&p(), 0.0, 0.2e-4, s1);
        assert_eq!(s2.tau, s1.tau);
    }

    #[test]
    fn failure_and_precut_are_broken_with_zero_strength() {
        let s = update(&p(), 0.6e-4, 0.9e-4, Strength::intact(&p()));
        assert_eq!((s.sigma, s.tau, s.state), (0.0, 0.0, PointState::Broken));
        let s = update(&p(), 0.0, 0.0, Strength::precut(&p()));
        assert_eq!(s.state, PointState::Broken);
    }

    /// Paper eq. (2) at β = 0.5, κ = 2 in pure shear: peak strength β σ_c and
    /// G_II = ∫ τ dδ_t = κ G_c = κ σ_c δ_c/2, the analytic values (the FE law's test checks the
    /// same numbers).
    #[test]
    fn kappa_and_beta_give_peak_shear_beta_sigma_c_and_g_ii_kappa_g_c() {
        let (sigma_c, delta_c, beta, kappa) = (0.4e6, 1e-4, 0.5, 2.0);
        let q = CohesiveParams::from_paper(sigma_c, delta_c, beta, kappa);
        let mut s = Strength::intact(&q);
        assert!((s.tau - beta * sigma_c).abs() < 1e-9, "peak shear {}", s.tau);
        // integrate the shear strength over a monotone slip ramp to failure (midpoint rule)
        let (n, end) = (200_000, 1.2 * kappa * delta_c / beta);
        let mut g = 0.0;
        for k in 0..n {
            let slip = (k as f64 + 0.5) * end / n as f64;
            s = update(&q, 0.0, slip, s);
            g += s.tau * end / n as f64;
        }
        assert_eq!(s.state, PointState::Broken);
        let g_ii = kappa * 0.5 * sigma_c * delta_c;
        assert!((g / g_ii - 1.0).abs() < 1e-4, "G_II {g} against κ G_c {g_ii}");
    }
}
