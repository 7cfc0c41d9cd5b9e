//! Linear coupled traction–separation law, paper eqs. (2)–(3) (hybrid model) and eq. (4)
//! (standard model: compression penalty inside the law), docs/fem-model.md §3.3–3.4. Pure.
//!
//! Sign convention: the opening Δ = u⁺ − u⁻ [m]; n points from the − side into the + side;
//! δ_n = Δ·n > 0 is opening. The traction T [Pa] is what acts on the + face with a minus sign:
//! T·n > 0 means cohesion pulls the faces together.

use nalgebra::Vector2;

/// Numerical tolerance on δ_n/δ_c,eff deciding that a facet is closing (Akantu `cohesive_linear`).
const CLOSING_TOL: f64 = 1e-10;

/// An effective opening below this fraction of δ_c,eff leaves a facet in its insertion state
/// (d = 0, T = T_ins). Right after an insertion the two faces coincide and round-off leaves an
/// opening of ~1e-20 m in an arbitrary direction; taken as an opening, it would set the traction's
/// direction (a round-off closing normal turned T_ins = σ_c n into −σ_c n, tearing the facet
/// open). Physical openings of interest are many orders above 1e-9 δ_c (Akantu treats damages
/// below its float tolerance as zero for the same reason).
const UNOPENED_TOL: f64 = 1e-9;

/// Parameters of the linear coupled law (paper eq. 2, Table 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearCohesive {
    /// Critical strength σ_c [Pa].
    pub sigma_c: f64,
    /// Critical opening δ_c [m] (G_c = σ_c δ_c / 2).
    pub delta_c: f64,
    /// Shear weight β [-] of the effective opening and stress.
    pub beta: f64,
    /// Mode ratio κ = G_II/G_I [-].
    pub kappa: f64,
}

/// How closing (δ_n < 0) is treated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ClosingTreatment {
    /// Hybrid model (paper §2): no normal resistance from the law; node-to-segment contact carries compression.
    Hybrid,
    /// Standard model (paper eq. 4): penalty T += ε_n δ_n n while δ_n < 0, also after full failure.
    Standard {
        /// Compression penalty ε_n [Pa/m].
        eps_n: f64,
    },
}

/// State of one cohesive Gauss point.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct CohesiveState {
    /// Effective strength σ_c,eff [Pa] (the effective stress at insertion, App. A).
    pub sigma_c_eff: f64,
    /// Effective critical opening δ_c,eff = 2 G_c / σ_c,eff [m].
    pub delta_c_eff: f64,
    /// Largest effective opening reached δ_max [m] (irreversibility).
    pub delta_max: f64,
    /// Damage d = min(δ_max/δ_c,eff, 1) [-].
    pub damage: f64,
    /// Traction transmitted by the bulk at insertion T_ins [Pa] (docs/fem-model.md §4).
    pub t_ins: Vector2<f64>,
}

impl CohesiveState {
    /// State at insertion with effective stress σ_eff [Pa] and bulk traction t_ins [Pa]
    /// (docs/fem-model.md §4):
    /// σ_c,eff = σ_eff, δ_c,eff = δ_c σ_c/σ_eff (guard σ_eff < 1e-6 σ_c → σ_c, δ_c).
    pub fn inserted(p: &LinearCohesive, sigma_eff: f64, t_ins: Vector2<f64>) -> Self {
        let (sigma_c_eff, delta_c_eff) = if sigma_eff < 1e-6 * p.sigma_c {
            (p.sigma_c, p.delta_c)
        } else {
            (sigma_eff, p.delta_c * p.sigma_c / sigma_eff)
        };
        Self {
            sigma_c_eff,
            delta_c_eff,
            delta_max: 0.0,
            damage: 0.0,
            t_ins,
        }
    }
}

/// Traction of the linear coupled law, paper eqs. (2)–(3):
/// δ² = (β²/κ²) δ_t² + δ_n² (δ_n dropped while closing), d = min(δ_max/δ_c,eff, 1),
/// T = ((β²/κ) Δ_t + δ_n n) σ_c,eff (1 − d)/δ_max for 0 < d < 1, T_ins at d = 0 (openings below
/// 1e-9 δ_c,eff are round-off and leave d = 0), 0 at d = 1;
/// the standard variant adds ε_n δ_n n while closing (eq. 4). Returns (T [Pa], new state).
pub fn traction(
    p: &LinearCohesive,
    mode: ClosingTreatment,
    n: Vector2<f64>,
    opening: Vector2<f64>,
    s: CohesiveState,
) -> (Vector2<f64>, CohesiveState) {
    let (delta, closing, delta_n, dt_vec) = effective_opening(p, mode, n, opening, &s);
    let mut new = s;
    if delta > UNOPENED_TOL * s.delta_c_eff {
        new.delta_max = s.delta_max.max(delta);
    }
    new.damage = (new.delta_max / s.delta_c_eff).min(1.0);
    let normal_part = if closing { Vector2::zeros() } else { delta_n * n };
    let mut t = if new.damage >= 1.0 {
        Vector2::zeros()
    } else if new.damage <= 0.0 {
        if closing { Vector2::zeros() } else { s.t_ins }
    } else {
        (p.beta * p.beta / p.kappa * dt_vec + normal_part)
            * (s.sigma_c_eff * (1.0 - new.damage) / new.delta_max)
    };
    if let (ClosingTreatment::Standard { eps_n }, true) = (mode, closing) {
        t += crate::law::penalty::compression_traction(eps_n, delta_n, n);
    }
    (t, new)
}

/// Effective opening δ = √((β²/κ²) δ_t² + δ_n²) [m] (δ_n dropped while closing), with the
/// closing flag, δ_n [m] and the tangential opening vector Δ_t [m].
pub fn effective_opening(
    p: &LinearCohesive,
    mode: ClosingTreatment,
    n: Vector2<f64>,
    opening: Vector2<f64>,
    s: &CohesiveState,
) -> (f64, bool, f64, Vector2<f64>) {
    let delta_n = opening.dot(&n);
    let dt_vec = opening - delta_n * n;
    let contact_after_breaking = matches!(mode, ClosingTreatment::Standard { .. });
    let closing = (contact_after_breaking || s.damage < 1.0) && delta_n < -CLOSING_TOL * s.delta_c_eff;
    let ratio = p.beta / p.kappa;
    let delta_sq = ratio * ratio * dt_vec.norm_squared() + if closing { 0.0 } else { delta_n * delta_n };
    (delta_sq.sqrt(), closing, delta_n, dt_vec)
}

/// Reversible (elastic) energy density of the point, ½ T·Δ [J/m²].
pub fn reversible_energy_density(t: Vector2<f64>, opening: Vector2<f64>) -> f64 {
    0.5 * t.dot(&opening)
}

#[cfg(test)]
mod tests {
    use super::*;
    const P: LinearCohesive = LinearCohesive {
        sigma_c: 0.4e6,
        delta_c: 1e-4,
        beta: 1.0,
        kappa: 1.0,
    };
    const TOL: f64 = 1e-10; // the law matches paper eqs. (2)-(3) to 1e-10 relative

    fn fresh() -> CohesiveState {
        CohesiveState::inserted(&P, P.sigma_c, Vector2::new(0.0, P.sigma_c))
    }
    fn n() -> Vector2<f64> {
        Vector2::new(0.0, 1.0)
    }

    /// eq. (2) on loading: T_n = σ_c (1 − δ/δ_c).
    fn eq2(delta: f64) -> f64 {
        P.sigma_c * (1.0 - delta / P.delta_c)
    }

    #[test]
    fn mode_one_load_unload_reload() {
        let mut s = fresh();
        let (t0, s0) = traction(&P, ClosingTreatment::Hybrid, n(), Vector2::zeros(), s);
        assert!(
            (t0.y - P.sigma_c).abs() < TOL * P.sigma_c,
            "T_ins at zero opening"
        );
        s = s0;
        for &d in &[0.2e-4, 0.4e-4] {
            let (t, s1) = traction(&P, ClosingTreatment::Hybrid, n(), Vector2::new(0.0, d), s);
            assert!(
                (t.y - eq2(d)).abs() < TOL * P.sigma_c,
                "loading {d}: {} vs {}",
                t.y,
                eq2(d)
            );
            s = s1;
        }
        // unload to half: secant to origin, eq. (3)
        let (t, s2) = traction(&P, ClosingTreatment::Hybrid, n(), Vector2::new(0.0, 0.2e-4), s);
        let expect = eq2(0.4e-4) * 0.5;
        assert!(
            (t.y - expect).abs() < TOL * P.sigma_c,
            "unloading {} vs {}",
            t.y,
            expect
        );
        assert_eq!(s2.delta_max, 0.4e-4);
        // reload beyond previous max follows eq. (2) again
        let (t, s3) = traction(&P, ClosingTreatment::Hybrid, n(), Vector2::new(0.0, 0.7e-4), s2);
        assert!((t.y - eq2(0.7e-4)).abs() < TOL * P.sigma_c);
        let (t, s4) = traction(&P, ClosingTreatment::Hybrid, n(), Vector2::new(0.0, 1.0e-4), s3);
        assert_eq!(t, Vector2::zeros());
        assert_eq!(s4.damage, 1.0);
    }

    #[test]
    fn mixed_mode_matches_eq2_with_beta_kappa() {
        let p = LinearCohesive {
            beta: 0.8,
            kappa: 1.5,
            ..P
        };
        let s = CohesiveState::inserted(&p, p.sigma_c, Vector2::zeros());
        let s = CohesiveState {
            delta_max: 1e-12,
            damage: 1e-8,
            ..s
        };
        let open = Vector2::new(3e-5, 2e-5);
        let (t, s1) = traction(&p, ClosingTreatment::Hybrid, n(), open, s);
        let r = p.beta / p.kappa;
        let delta = (r * r * 9e-10 + 4e-10_f64).sqrt();
        let f = p.sigma_c * (1.0 - delta / p.delta_c) / delta;
        assert!((t.x - p.beta * p.beta / p.kappa * 3e-5 * f).abs() < TOL * p.sigma_c);
        assert!((t.y - 2e-5 * f).abs() < TOL * p.sigma_c);
        assert!((s1.delta_max - delta).abs() < 1e-20);
    }

    #[test]
    fn closing_hybrid_keeps_only_shear_standard_pushes_apart() {
        let s = CohesiveState {
            delta_max: 1e-5,
            damage: 0.1,
            ..fresh()
        };
        let open = Vector2::new(2e-5, -1e-6);
        let (t, _) = traction(&P, ClosingTreatment::Hybrid, n(), open, s);
        assert_eq!(t.y, 0.0, "hybrid: no normal resistance while closing");
        assert!(t.x > 0.0);
        let (ts, _) = traction(&P, ClosingTreatment::Standard { eps_n: 2.1e10 }, n(), open, s);
        assert!(
            (ts.y - 2.1e10 * -1e-6).abs() < 1e-6,
            "penalty −ε_n|δ_n| pushes apart: {}",
            ts.y
        );
        let broken = CohesiveState {
            delta_max: 2e-4,
            damage: 1.0,
            ..s
        };
        let (tb, _) = traction(
            &P,
            ClosingTreatment::Standard { eps_n: 2.1e10 },
            n(),
            open,
            broken,
        );
        assert!((tb.y + 2.1e4).abs() < 1e-6, "penalty acts after full failure");
        let (th, _) = traction(&P, ClosingTreatment::Hybrid, n(), open, broken);
        assert_eq!(th, Vector2::zeros());
    }

    #[test]
    fn pure_shear_fails_at_kappa_delta_c_over_beta_and_dissipates_kappa_gc() {
        let p = LinearCohesive { kappa: 2.0, ..P };
        let mut s = CohesiveState::inserted(&p, p.sigma_c, Vector2::new(p.sigma_c, 0.0));
        let (mut t_old, mut d_old, mut work) = (Vector2::new(p.sigma_c, 0.0), 0.0, 0.0);
        let steps = 200_000;
        for i in 1..=steps {
            let d = 2.2e-4 * i as f64 / steps as f64;
            let (t, s1) = traction(&p, ClosingTreatment::Hybrid, n(), Vector2::new(d, 0.0), s);
            work += 0.5 * (t.x + t_old.x) * (d - d_old);
            (t_old, d_old, s) = (t, d, s1);
        }
        assert_eq!(s.damage, 1.0);
        let g_ii = p.kappa * 0.5 * p.sigma_c * p.delta_c;
        assert!((work - g_ii).abs() < 1e-3 * g_ii, "G_II {work} vs {g_ii}");
    }

    #[test]
    fn a_round_off_opening_keeps_the_insertion_traction() {
        // right after insertion the two faces coincide and round-off leaves openings of
        // ~1e-20 m in any direction; they must not set the traction's direction (a closing
        // normal round-off used to flip T_ins = σ_c n into −σ_c n, tearing the facet open)
        for opening in [
            Vector2::new(0.0, -2.4e-20),
            Vector2::new(3e-21, 1e-22),
            Vector2::new(-1e-19, -1e-19),
        ] {
            let (t, s) = traction(&P, ClosingTreatment::Hybrid, n(), opening, fresh());
            assert_eq!(t, Vector2::new(0.0, P.sigma_c), "{opening:?}");
            assert_eq!(s.damage, 0.0, "{opening:?}");
        }
        // a physical opening softens as eq. (2) says
        let (t, _) = traction(
            &P,
            ClosingTreatment::Hybrid,
            n(),
            Vector2::new(0.0, 1e-2 * P.delta_c),
            fresh(),
        );
        assert!((t.y - eq2(1e-2 * P.delta_c)).abs() < TOL * P.sigma_c);
    }

    /// Paper eq. (2) at β = 0.5, κ = 2 in pure shear: peak traction β σ_c and
    /// G_II = ∫ T_t dδ_t = κ G_c = κ σ_c δ_c/2 (the spectral law's test checks the same numbers).
    #[test]
    fn kappa_and_beta_give_peak_shear_beta_sigma_c_and_g_ii_kappa_g_c() {
        let q = LinearCohesive {
            beta: 0.5,
            kappa: 2.0,
            ..P
        };
        // inserted in pure shear when σ_eff = τ/β reaches σ_c, i.e. at τ = β σ_c (docs/fem-model.md §4)
        let mut s = CohesiveState::inserted(&q, q.sigma_c, Vector2::new(q.beta * q.sigma_c, 0.0));
        let (steps, end) = (200_000, 1.2 * q.kappa * q.delta_c / q.beta);
        let (mut g, mut peak) = (0.0, 0.0f64);
        let mut prev_t = s.t_ins.x;
        for k in 1..=steps {
            let slip = k as f64 * end / steps as f64;
            let (t, next) = traction(&q, ClosingTreatment::Hybrid, n(), Vector2::new(slip, 0.0), s);
            s = next;
            peak = peak.max(t.x);
            g += 0.5 * (prev_t + t.x) * end / steps as f64;
            prev_t = t.x;
        }
        // the first sample sits at d = 6e-6 on the softening branch: peak within 1e-5 of β σ_c
        assert!(
            (peak / (q.beta * q.sigma_c) - 1.0).abs() < 1e-5,
            "peak shear {peak}"
        );
        let g_ii = q.kappa * 0.5 * q.sigma_c * q.delta_c;
        assert!((g / g_ii - 1.0).abs() < 1e-4, "G_II {g} against κ G_c {g_ii}");
        assert_eq!(s.damage, 1.0);
    }
}
