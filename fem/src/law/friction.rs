//! Regularised Coulomb friction, paper eq. (8): explicit return map (stick/slip); pure.
//!
//! docs/fem-model.md §5.3: backward Euler on the elastic slip of eq. (8), Akantu's scheme in 2D with
//! unit tangents. The tangential traction is a signed scalar T [Pa] along the master tangent t_e.

/// Parameters of the regularised Coulomb law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Friction {
    /// Tangential penalty ε_t [Pa/m] (traction per unit elastic slip; the paper uses ε_t = ε_n).
    pub eps_t: f64,
    /// Coulomb coefficient μ [-] (static = kinetic).
    pub friction_coeff: f64,
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
    /// Normal pressure p_N ≥ 0 [Pa].
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
}
