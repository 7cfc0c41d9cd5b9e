//! Plane-strain isotropic elasticity: Lamé constants, wave speeds, stable time step
//! (docs/fem-model.md §1–2). Pure.

/// Plane-strain elastic constants derived from (E, ν, ρ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneStrain {
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson ratio ν [-].
    pub poisson_ratio: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
    /// Lamé λ = Eν/((1+ν)(1−2ν)) [Pa].
    pub lambda: f64,
    /// Shear modulus G = E/(2(1+ν)) [Pa].
    pub shear_modulus: f64,
}

/// Plane-strain wave speeds [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveSpeeds {
    /// Dilatational speed c_d = √((λ+2G)/ρ) [m/s].
    pub cd: f64,
    /// Shear speed c_s = √(G/ρ) [m/s].
    pub cs: f64,
    /// Rayleigh speed c_R [m/s], root of (2−x)² = 4√(1−x)√(1−x c_s²/c_d²), x = c²/c_s².
    pub cr: f64,
}

impl PlaneStrain {
    /// Constants from E [Pa], ν [-], ρ [kg/m³].
    pub fn new(youngs_modulus: f64, poisson_ratio: f64, density: f64) -> Self {
        let nu = poisson_ratio;
        Self {
            youngs_modulus,
            poisson_ratio,
            density,
            lambda: youngs_modulus * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
            shear_modulus: youngs_modulus / (2.0 * (1.0 + nu)),
        }
    }

    /// Voigt matrix D = [[λ+2G, λ, 0], [λ, λ+2G, 0], [0, 0, G]] [Pa], docs/fem-model.md §1.
    pub fn d_matrix(&self) -> [[f64; 3]; 3] {
        let (l, g) = (self.lambda, self.shear_modulus);
        [[l + 2.0 * g, l, 0.0], [l, l + 2.0 * g, 0.0], [0.0, 0.0, g]]
    }

    /// Wave speeds c_d, c_s, c_R [m/s].
    pub fn wave_speeds(&self) -> WaveSpeeds {
        let cd = ((self.lambda + 2.0 * self.shear_modulus) / self.density).sqrt();
        let cs = (self.shear_modulus / self.density).sqrt();
        WaveSpeeds {
            cd,
            cs,
            cr: cs * rayleigh_ratio(cs / cd),
        }
    }
}

/// Whether two bodies bonded along a slipping, closed interface carry a generalized Rayleigh wave
/// (Weertman 1963): the speed v < min c_s where the two faces' normal stiffnesses under free slip,
/// G R(v)/((v/c_s)² α_d) each (R the Rayleigh function, α_d = √(1 − v²/c_d²)), sum to zero. Both
/// are positive as v → 0; the wave exists when the sum is negative at the slower shear speed.
/// Identical bodies always carry one (the Rayleigh wave).
pub fn slip_wave_exists(a: &PlaneStrain, b: &PlaneStrain) -> bool {
    let v = a.wave_speeds().cs.min(b.wave_speeds().cs);
    let stiffness = |m: &PlaneStrain| {
        let w = m.wave_speeds();
        let x2 = (v / w.cs).powi(2);
        let (alpha_s, alpha_d) = ((1.0 - x2).max(0.0).sqrt(), (1.0 - (v / w.cd).powi(2)).sqrt());
        let r = 4.0 * alpha_s * alpha_d - (2.0 - x2).powi(2);
        m.shear_modulus * r / (x2 * alpha_d)
    };
    a == b || stiffness(a) + stiffness(b) < 0.0
}

/// c_R/c_s from the Rayleigh equation by bisection on x = (c/c_s)² ∈ (0, 1).
fn rayleigh_ratio(cs_over_cd: f64) -> f64 {
    let k2 = cs_over_cd * cs_over_cd;
    let g = |x: f64| (2.0 - x).powi(2) - 4.0 * (1.0 - x).sqrt() * (1.0 - x * k2).sqrt();
    let (mut lo, mut hi) = (1e-6, 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(lo) * g(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (0.5 * (lo + hi)).sqrt()
}

/// Penalty correction of paper eq. (12) (Belytschko & Neal 1991): f(β) = √(2/(1+β+√(1+β²))) [-].
pub fn penalty_factor(beta_p: f64) -> f64 {
    (2.0 / (1.0 + beta_p + (1.0 + beta_p * beta_p).sqrt())).sqrt()
}

/// Stable step Δt = α h_min/c_d · f(β_p) [s], docs/fem-model.md §2, with β_p = ε h_min/E (ε [Pa/m]).
pub fn stable_time_step(alpha: f64, h_min: f64, cd: f64, beta_p: f64) -> f64 {
    alpha * h_min / cd * penalty_factor(beta_p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_section3_speeds() {
        let w = PlaneStrain::new(70e6, 0.35, 1230.0).wave_speeds();
        assert!((w.cd - 302.22).abs() < 0.01, "cd {}", w.cd);
        assert!((w.cs - 145.18).abs() < 0.01, "cs {}", w.cs);
        assert!((w.cr / w.cs - 0.93501).abs() < 1e-4, "cr/cs {}", w.cr / w.cs);
    }

    #[test]
    fn penalty_factor_values() {
        assert!((penalty_factor(0.0) - 1.0).abs() < 1e-15);
        assert!((penalty_factor(0.3) - 0.9238).abs() < 1e-3);
    }
}
