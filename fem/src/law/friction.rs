//! Regularised Coulomb friction, paper eq. (8): explicit return map (stick/slip); pure. And the
//! Prakash regularisation of the normal stress of its strength, paper eq. (14).
//!
//! docs/fem-model.md §5.3: backward Euler on the elastic slip of eq. (8), Akantu's scheme in 2D with
//! unit tangents. The tangential traction is a signed scalar T [Pa] along the master tangent t_e.
//!
//! # Deviation
//! The paper prints eq. (14) as dσ̃/dt = (σ̃ − σ)/t*, which is unstable (a typo); we integrate
//! dσ̃/dt = −(σ̃ − σ)/t*, as the spectral model does (docs/spectral-model.md §5.3).

/// Parameters of the regularised Coulomb law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Friction {
    /// Tangential penalty ε_t [Pa/m] (traction per unit elastic slip; the paper uses ε_t = ε_n).
    pub eps_t: f64,
    /// Coulomb coefficient μ [-] (static = kinetic).
    pub friction_coeff: f64,
    /// r = Δt/t* [-] of the Prakash regularisation of the normal stress (paper eq. 14, see
    /// [`regularized_normal`]); `None`: t* = 0, plain Coulomb.
    pub prakash_ratio: Option<f64>,
}

/// Backward-Euler step of dσ̃/dt = −(σ̃ − σ)/t* (paper eq. 14, sign corrected):
/// σ̃ = (σ̃_prev + r σ)/(1 + r), r = Δt/t*; `r = None` (t* = 0) gives σ̃ = σ exactly. σ [Pa] is the
/// contact pressure where the faces touch and 0 where they are apart, so out of contact σ̃ decays
/// over t* and a point touching again starts from what is left. The Coulomb strength is μ σ̃.
pub(crate) fn regularized_normal(prev: f64, normal_stress: f64, r: Option<f64>) -> f64 {
    match r {
        None => normal_stress,
        Some(r) => (prev + r * normal_stress) / (1.0 + r),
    }
}

/// Input of one return-map step for one slave node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrictionInput {
    /// Previous tangential traction T_prev [Pa], along the previous tangent t_prev.
    pub traction_prev: f64,
    /// Basis change t_prev · t_e [-] that transports T_prev onto the current tangent.
    pub transport: f64,
    /// Relative slip of the slave over the master this step, Δs = (x_ρ − x_ρ,prev)·t_e [m].
    pub slip: f64,
    /// Normal pressure of the Coulomb strength ≥ 0 [Pa]: p_N, or its regularised σ̃ (eq. 14).
    pub normal_pressure: f64,
}

/// Result of one return-map step.
///
/// Sign convention: T is measured along t_e and the force on the slave is A T t_e, so a slave
/// sliding along +t_e over a fixed master (Δs > 0) gets T < 0: friction opposes the motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FrictionStep {
    /// Tangential traction T along t_e [Pa]; |T| ≤ μ p_N.
    pub traction: f64,
    /// `true` when the trial traction exceeded μ p_N (slip), `false` for stick.
    pub slipping: bool,
    /// Plastic slip Δs_p = (|T_tr| − μ p_N)/ε_t ≥ 0 [m]; zero when sticking.
    pub plastic_slip: f64,
}

/// Explicit return map, docs/fem-model.md §5.3:
///
/// ```text
/// T_tr = T_prev (t_prev·t_e) − ε_t Δs
/// stick if |T_tr| ≤ μ p_N:  T = T_tr,                 Δs_p = 0
/// slip otherwise:           T = μ p_N sign(T_tr),     Δs_p = (|T_tr| − μ p_N)/ε_t
/// ```
///
/// With μ = 0 any non-zero trial slips and T = 0 (frictionless contact).
pub(crate) fn return_map(law: &Friction, input: &FrictionInput) -> FrictionStep {
    let trial = input.traction_prev * input.transport - law.eps_t * input.slip;
    let limit = law.friction_coeff * input.normal_pressure.max(0.0);
    if trial.abs() <= limit {
        FrictionStep {
            traction: trial,
            slipping: false,
            plastic_slip: 0.0,
        }
    } else {
        FrictionStep {
            traction: limit * trial.signum(),
            slipping: true,
            plastic_slip: (trial.abs() - limit) / law.eps_t,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LAW: Friction = Friction {
        eps_t: 2.1e10,
        friction_coeff: 0.3,
        prakash_ratio: None,
    };
    const P_N: f64 = 0.05e6; // Pa

    fn input(traction_prev: f64, slip: f64) -> FrictionInput {
        FrictionInput {
            traction_prev,
            transport: 1.0,
            slip,
            normal_pressure: P_N,
        }
    }

    #[test]
    fn small_slip_sticks_with_elastic_traction() {
        // μ p_N / ε_t = 7.1e-7 m: a slip of 1e-7 m stays elastic.
        let s = return_map(&LAW, &input(0.0, 1e-7));
        assert!(!s.slipping);
        assert_eq!(s.traction, -LAW.eps_t * 1e-7);
        assert_eq!(s.plastic_slip, 0.0);
    }

    #[test]
    fn large_slip_slides_at_the_coulomb_limit_with_plastic_slip() {
        let s = return_map(&LAW, &input(0.0, 1e-5));
        assert!(s.slipping);
        assert_eq!(s.traction, -LAW.friction_coeff * P_N);
        let expected = (LAW.eps_t * 1e-5 - LAW.friction_coeff * P_N) / LAW.eps_t;
        assert!((s.plastic_slip - expected).abs() < 1e-15);
    }

    #[test]
    fn traction_opposes_slip_in_both_directions() {
        // Sign convention pinned: Δs > 0 (slave moves along +t_e) gives T < 0, and vice versa.
        assert!(return_map(&LAW, &input(0.0, 1e-8)).traction < 0.0);
        assert!(return_map(&LAW, &input(0.0, -1e-8)).traction > 0.0);
        assert!(return_map(&LAW, &input(0.0, 1e-3)).traction < 0.0);
        assert!(return_map(&LAW, &input(0.0, -1e-3)).traction > 0.0);
    }

    #[test]
    fn history_is_transported_and_reversal_unloads_elastically() {
        // Sliding at −μp_N, then a small reverse slip: elastic unloading, back inside the cone.
        let s = return_map(&LAW, &input(-LAW.friction_coeff * P_N, -1e-7));
        assert!(!s.slipping);
        assert!((s.traction - (-LAW.friction_coeff * P_N + LAW.eps_t * 1e-7)).abs() < 1e-9);
        // A reversed tangent (t_prev·t_e = −1) flips the sign of the stored traction.
        let flipped = FrictionInput {
            transport: -1.0,
            ..input(-1000.0, 0.0)
        };
        assert_eq!(return_map(&LAW, &flipped).traction, 1000.0);
    }

    #[test]
    fn zero_friction_coefficient_gives_zero_traction() {
        let law = Friction {
            friction_coeff: 0.0,
            ..LAW
        };
        let s = return_map(&law, &input(0.0, 1e-6));
        assert_eq!(s.traction, 0.0);
        assert!(s.slipping);
        assert_eq!(return_map(&law, &input(0.0, 0.0)).traction, 0.0);
    }

    #[test]
    fn no_pressure_means_no_tangential_traction() {
        let s = return_map(
            &LAW,
            &FrictionInput {
                normal_pressure: 0.0,
                ..input(0.0, 1e-6)
            },
        );
        assert_eq!(s.traction, 0.0);
    }

    /// Eq. (14) under a pressure step σ from σ̃ = 0: backward Euler gives σ̃_n = σ(1 − (1 + r)^−n)
    /// exactly (up to round-off, 1e-15 relative for a few hundred steps of values ~1), which tends
    /// to the exponential σ(1 − e^(−t/t*)) as r = Δt/t* → 0: at r = 1e-3 the two differ by at
    /// most r/(2e) σ ≈ 1.8e-4 σ (the first-order error of the scheme over one t*), so 5e-4 σ
    /// bounds it; a forward-Euler or a sign slip (the paper's typo grows without bound) fails both.
    #[test]
    fn the_regularised_pressure_approaches_a_step_exponentially_over_t_star() {
        let (sigma, r) = (2.0e5, 1e-3);
        let mut s = 0.0;
        let mut worst_exp = 0.0f64;
        for n in 1..=3000 {
            s = regularized_normal(s, sigma, Some(r));
            let exact = sigma * (1.0 - (1.0 + r).powi(-n));
            assert!(
                (s - exact).abs() <= 1e-15 * sigma * n as f64,
                "step {n}: {s} vs {exact}"
            );
            let t_over = n as f64 * r;
            worst_exp = worst_exp.max((s - sigma * (1.0 - (-t_over).exp())).abs() / sigma);
        }
        println!("worst |σ̃ − σ(1 − e^(−t/t*))|/σ over 3 t*: {worst_exp:.3e}");
        assert!(worst_exp < 5e-4, "{worst_exp}");
        // after one t* the strength has built up to 1 − 1/e of the step, not all of it
        let mut s = 0.0;
        for _ in 0..1000 {
            s = regularized_normal(s, sigma, Some(r));
        }
        assert!(
            (s / sigma - (1.0 - (-1.0f64).exp())).abs() < 5e-4,
            "{}",
            s / sigma
        );
        // out of contact (σ = 0) it decays by 1/(1 + r) per step, and t* = 0 follows σ exactly
        assert_eq!(regularized_normal(s, 0.0, Some(r)), s / (1.0 + r));
        assert_eq!(regularized_normal(123.0, sigma, None), sigma);
        assert_eq!(regularized_normal(123.0, 0.0, None), 0.0);
    }
}
