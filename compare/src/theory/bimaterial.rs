//! The generalized Rayleigh wave of two different half-spaces in frictionless contact (Weertman
//! 1963; Achenbach & Epstein 1967): the interface wave of a slipping, closed interface, and the
//! speed a slip pulse or a mode-II crack tip on a bimaterial interface is drawn to (Ranjith & Rice
//! 2001; Rubin & Ampuero 2007). It exists only for moderate contrasts.
//!
//! Derivation. A wave u ∝ e^{ik(x−vt)} in each half-space with zero shear traction on its face
//! has normal traction and normal displacement related by σ_yy = ∓ μ|k| R(v)/((v/c_s)² α_d) u_y
//! (R the Rayleigh function, α_d = √(1 − v²/c_d²); − for the upper body, + for the lower). The
//! faces stay in contact (u_y and σ_yy continuous), so a wave of speed v < min c_s exists when
//!
//! ```text
//! F(v) = μ₁ R₁(v)/(x₁² α_d₁) + μ₂ R₂(v)/(x₂² α_d₂) = 0,    x_i = v/c_s,i
//! ```
//!
//! With identical halves F = 2μR/(x²α_d) and the root is c_R. F > 0 as v → 0 and, at the slower
//! shear speed, R/x² = −1 in the slower body: the root exists when F there is negative.

use super::freund::Material;

/// One half-space: its wave speeds and its shear modulus μ [Pa].
#[derive(Debug, Clone, Copy)]
pub struct HalfSpace {
    /// Wave speeds.
    pub material: Material,
    /// Shear modulus μ = ρ c_s² [Pa].
    pub shear_modulus: f64,
}

impl HalfSpace {
    /// From Poisson's ratio ν [-], the shear modulus μ [Pa] and the density ρ [kg/m³]; `None` for
    /// a ν outside (−1, 1/2) or a non-positive μ or ρ.
    pub fn new(nu: f64, shear_modulus: f64, density: f64) -> Option<HalfSpace> {
        if !(shear_modulus > 0.0 && density > 0.0 && shear_modulus.is_finite() && density.is_finite()) {
            return None;
        }
        let material = Material::from_nu(nu, (shear_modulus / density).sqrt())?;
        Some(HalfSpace {
            material,
            shear_modulus,
        })
    }

    /// μ R(v)/((v/c_s)² α_d) at v = `x` c_s [Pa], free of the small-v cancellation.
    fn face_stiffness(&self, v: f64) -> f64 {
        let m = &self.material;
        let x = v / m.cs();
        let alpha_d = (1.0 - (v / m.cd()).powi(2)).sqrt();
        self.shear_modulus * m.rayleigh_over_x2(x) / alpha_d
    }
}

/// F(v) of the module's equation [Pa]; `NaN` outside [0, min c_s].
pub fn generalized_rayleigh_function(a: &HalfSpace, b: &HalfSpace, v: f64) -> f64 {
    if !(0.0..=a.material.cs().min(b.material.cs())).contains(&v) {
        return f64::NAN;
    }
    a.face_stiffness(v) + b.face_stiffness(v)
}

/// The generalized Rayleigh speed [m/s]: the root of F in (0, min c_s), or `None` when the
/// contrast is too large for the wave to exist (F keeps its sign up to the slower shear speed).
/// A scan on 4 096 intervals finds the first sign change; bisection refines it to full precision.
pub fn generalized_rayleigh_speed(a: &HalfSpace, b: &HalfSpace) -> Option<f64> {
    let top = a.material.cs().min(b.material.cs());
    let f = |v: f64| generalized_rayleigh_function(a, b, v);
    const SCAN: usize = 4096;
    let mut lo = 0.0;
    let mut hit = None;
    for i in 1..=SCAN {
        let hi = top * i as f64 / SCAN as f64;
        if f(hi) < 0.0 {
            hit = Some((lo, hi));
            break;
        }
        lo = hi;
    }
    let (mut lo, mut hi) = hit?;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) < 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's material: E = 70 MPa, ν = 0.35, ρ = 1230 kg/m³.
    fn paper() -> HalfSpace {
        HalfSpace::new(0.35, 70e6 / 2.7, 1230.0).unwrap()
    }

    /// The paper's material with its shear-wave speed raised by `r` through μ (ρ and ν kept).
    fn stiffer(r: f64) -> HalfSpace {
        HalfSpace::new(0.35, r * r * 70e6 / 2.7, 1230.0).unwrap()
    }

    #[test]
    fn identical_halves_give_the_rayleigh_speed() {
        let p = paper();
        let v = generalized_rayleigh_speed(&p, &p).unwrap();
        let cr = p.material.rayleigh_speed();
        println!("identical: {v} against c_R = {cr}");
        assert!((v / cr - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_moderate_contrast_has_a_wave_between_the_slower_rayleigh_and_shear_speeds() {
        // 20 % in c_s through μ: exists, between c_R and c_s of the slower (softer) body
        let (p, s) = (paper(), stiffer(1.2));
        let v = generalized_rayleigh_speed(&p, &s).unwrap();
        let (cr, cs) = (p.material.rayleigh_speed(), p.material.cs());
        println!("20 %: v/c_s,slow = {}", v / cs);
        assert!(v > cr && v < cs);
        assert_eq!(
            generalized_rayleigh_speed(&s, &p),
            Some(v),
            "symmetric in the two bodies"
        );
        // the function changes sign there, as the bisection assumes
        assert!(generalized_rayleigh_function(&p, &s, 0.999 * v) > 0.0);
        assert!(generalized_rayleigh_function(&p, &s, 1.001 * v) < 0.0);
    }

    #[test]
    fn past_the_existence_limit_there_is_none() {
        // 30 % in c_s through μ: F stays positive up to the slower shear speed
        let (p, s) = (paper(), stiffer(1.3));
        assert_eq!(generalized_rayleigh_speed(&p, &s), None);
        let at_cs = generalized_rayleigh_function(&p, &s, p.material.cs());
        assert!(at_cs > 0.0, "{at_cs}");
        // and the limit lies between: the speed rises to c_s,slow as the contrast grows
        let mut last = paper().material.rayleigh_speed();
        for r in [1.05, 1.1, 1.15, 1.2, 1.25] {
            let v = generalized_rayleigh_speed(&p, &stiffer(r)).unwrap();
            assert!(v > last, "r = {r}: {v} after {last}");
            last = v;
        }
    }
}

#[cfg(test)]
mod against_the_spectral_model {
    use super::*;

    /// The spectral model's own existence test (from its half-space relations) and this module's
    /// (from the Rayleigh function) agree on either side of the limit, for contrasts through μ
    /// and through ρ, and for two Poisson ratios.
    #[test]
    fn both_forms_agree_on_where_the_wave_exists() {
        let mut changes = 0;
        for nu2 in [0.35, 0.25] {
            for r in (0..=40).map(|i| 1.0 + 0.0125 * i as f64) {
                for (mu2, rho2) in [(r * r * 70e6 / 2.7, 1230.0), (70e6 / 2.7, 1230.0 / (r * r))] {
                    let top = spectral::Solid {
                        youngs_modulus: 70e6,
                        poisson_ratio: 0.35,
                        density: 1230.0,
                    };
                    let bottom = spectral::Solid {
                        youngs_modulus: 2.0 * mu2 * (1.0 + nu2),
                        poisson_ratio: nu2,
                        density: rho2,
                    };
                    let a = HalfSpace::new(0.35, 70e6 / 2.7, 1230.0).unwrap();
                    let b = HalfSpace::new(nu2, mu2, rho2).unwrap();
                    let theory = generalized_rayleigh_speed(&a, &b).is_some();
                    assert_eq!(
                        spectral::slip_wave_exists(top, bottom),
                        theory,
                        "ν₂ = {nu2}, r = {r}"
                    );
                    changes += usize::from(!theory);
                }
            }
        }
        assert!(changes > 0, "the range must cross the existence limit");
    }
}
