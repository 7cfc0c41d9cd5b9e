//! Universal crack-tip-speed functions of plane-strain elastodynamic fracture, the bilateral-crack
//! equation of motion built on them, and Andrews' fit for the supershear transition distance.
//!
//! # References
//! * L. B. Freund, *Dynamic Fracture Mechanics*, Cambridge University Press, 1990:
//!   ch. 5 (near-tip fields of a moving crack, energy factors `A(v)`), ch. 6 (crack growth under
//!   time-independent loading, universal function `k(v)` from a Wiener–Hopf factorisation of the
//!   Rayleigh function) and ch. 7 (crack-tip equation of motion, `g(v) = A(v) k(v)²`).
//! * D. J. Andrews, "Rupture velocity of plane strain shear cracks", *J. Geophys. Res.* 81(32),
//!   5679–5687, 1976 (transition of a slip-weakening shear crack to supershear speed).
//!
//! # Conventions (all derived for this file, SI units)
//! Slownesses `a = 1/c_d`, `b = 1/c_s`, `c = 1/c_R`; inside the code every slowness is made
//! dimensionless with `c_s` (so `b = 1`) and every speed with `c_s`.
//!
//! Speed form of the Rayleigh function: `R(v) = 4 α_d α_s − (1 + α_s²)²`, `α = sqrt(1 − v²/c²)`.
//! Slowness form: `R(ζ) = (b² − 2ζ²)² + 4ζ² sqrt(a² − ζ²) sqrt(b² − ζ²)`; on `a < η < b` its phase
//! is `θ(η) = arctan[4η² sqrt(η² − a²) sqrt(b² − η²) / (b² − 2η²)²] ∈ [0, π/2]`. The factor
//! `S₊(ζ) = exp(−(1/π) ∫_a^b θ(η) dη / (η + ζ))` is analytic off the cut `[−b, −a]`, tends to 1 at
//! infinity and gives `R(ζ) = 2(b² − a²)(c² − ζ²) S₊(ζ) S₊(−ζ)` (checked in the tests).
//!
//! A semi-infinite crack whose tip starts moving at speed `v` under time-independent loading has
//! (derived with a two-sided transform in the moving coordinate `x − vt`; every "+" factor of the
//! kernel ends up evaluated at the lab-frame slowness `−1/v`):
//! `k_I(v) = (1 − v/c_R) S₊(−1/v) / sqrt(1 − v/c_d)`, `k_II(v) = (1 − v/c_R) S₊(−1/v) / sqrt(1 − v/c_s)`,
//! with `S₊(−1/v) = exp((1/π) ∫_a^b θ(η) v dη / (1 − vη)) ≥ 1`. By the factorisation identity at
//! `ζ = ±1/v` this equals `k = (1−ν) c_s² R(v) / (v² (1 + v/c_R) S₊(1/v) sqrt(1 − v/c_{d|s}))`, so an
//! expression written with `S₊(+1/v)` can be compared directly; both forms are evaluated in the
//! tests. (The same steps give the exact mode III result `sqrt(1 − v/c_s)`, a check on signs and
//! on the direction of motion.)
//! Energy factors: `A_I = v² α_d / ((1−ν) c_s² R(v))`, `A_II = v² α_s / ((1−ν) c_s² R(v))`, both → 1
//! as `v → 0`; `G = A(v) (1−ν) K² / (2μ)` and `g(v) = A(v) k(v)²` with `g(0) = 1`, `g(c_R) = 0`.
//!
//! # Numerics
//! The integrand `θ(η)` has square-root zeros at both ends of `(a, b)`. The substitution
//! `η = a + (b − a) sin²(φ/2)`, `φ ∈ [0, π]`, makes it analytic in `φ`; `η − a`, `b − η`,
//! `sqrt(η² − a²)` and `sqrt(b² − η²)` are then built from `sin(φ/2)`, `cos(φ/2)` without
//! subtraction, `θ` is an `atan2` of two non-negative numbers, and `1 − vη` is formed as
//! `(1 − v) + v(1 − η)`. Gauss–Legendre in `φ` then converges geometrically. `R(v)/v²` is
//! evaluated in a rearranged form that avoids the catastrophic cancellation of `4α_dα_s` against
//! `(1 + α_s²)²` at small `v`.

use super::quadrature::gauss_legendre;
use std::f64::consts::PI;

/// Number of Gauss–Legendre nodes used for the slowness integral (the tests show 64 → 128 nodes
/// changes `g` by less than 1e-10 up to 0.95 `c_R`).
const QUAD_NODES: usize = 64;

/// Coefficient of Andrews' (1976) fit `L/L_c = 9.8 (1.77 − S)^−3` [-].
const ANDREWS_COEFFICIENT: f64 = 9.8;

/// Critical seismic ratio of Andrews' plane-strain fit; no transition for `S ≥ 1.77` [-].
const ANDREWS_S_MAX: f64 = 1.77;

/// In-plane loading mode of the crack tip.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Opening (tensile) mode; the load is the remote normal stress σ [Pa].
    I,
    /// In-plane shear (sliding) mode; the load is the stress drop Δτ [Pa].
    II,
}

/// Isotropic, linear elastic solid in plane strain, described by its bulk wave speeds.
///
/// Invariant (enforced by the constructors): `c_s > 0`, both speeds finite, and
/// `c_d / c_s > 2/√3`, i.e. Poisson's ratio `−1 < ν < 1/2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Dilatational (P) wave speed `c_d` [m/s].
    cd: f64,
    /// Shear (S) wave speed `c_s` [m/s].
    cs: f64,
}

/// Position on the slowness interval handed to the integrand weight, all in units of `1/c_s`.
#[derive(Clone, Copy, Debug)]
struct Slowness {
    /// `(η − a) c_s`, formed without subtraction [-].
    above_a: f64,
    /// `(b − η) c_s = 1 − η c_s`, formed without subtraction [-].
    below_b: f64,
}

impl Material {
    /// Material from the dilatational speed `cd` [m/s] and shear speed `cs` [m/s].
    ///
    /// Returns `None` unless both are finite, `cs > 0` and `cd/cs > 2/√3` (`−1 < ν < 1/2`).
    pub fn new(cd: f64, cs: f64) -> Option<Self> {
        let valid = cd.is_finite() && cs.is_finite() && cs > 0.0 && 3.0 * cd * cd > 4.0 * cs * cs;
        valid.then_some(Self { cd, cs })
    }

    /// Material from Poisson's ratio `nu` [-] and shear speed `cs` [m/s], using the plane-strain
    /// relation `c_d/c_s = sqrt(2(1 − ν)/(1 − 2ν))`. Returns `None` unless `−1 < ν < 1/2` and
    /// `cs` is finite and positive.
    pub fn from_nu(nu: f64, cs: f64) -> Option<Self> {
        if !(nu > -1.0 && nu < 0.5) {
            return None;
        }
        let ratio = (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt();
        Self::new(ratio * cs, cs)
    }

    /// Dilatational wave speed `c_d` [m/s].
    pub fn cd(&self) -> f64 {
        self.cd
    }

    /// Shear wave speed `c_s` [m/s].
    pub fn cs(&self) -> f64 {
        self.cs
    }

    /// Poisson's ratio `ν` [-] implied by `c_d/c_s` in plane strain.
    pub fn nu(&self) -> f64 {
        let r2 = (self.cd / self.cs).powi(2);
        (r2 - 2.0) / (2.0 * (r2 - 1.0))
    }

    /// `c_s/c_d`, the dilatational slowness in units of the shear slowness [-].
    fn a_hat(&self) -> f64 {
        self.cs / self.cd
    }

    /// `1/(1 − ν) = 2 (1 − c_s²/c_d²)` [-].
    fn inv_one_minus_nu(&self) -> f64 {
        2.0 * (1.0 - self.a_hat().powi(2))
    }

    /// `R(v)/(v/c_s)²` for `x = v/c_s ∈ [0, 1]`, free of the small-`v` cancellation:
    /// `R/x² = 4 α_s (α_d − â² α_s)/(1 + α_d α_s) − x²` with `â = c_s/c_d`.
    pub(crate) fn rayleigh_over_x2(&self, x: f64) -> f64 {
        let a2 = self.a_hat().powi(2);
        let x2 = x * x;
        let alpha_d = (1.0 - a2 * x2).sqrt();
        let alpha_s = (1.0 - x2).sqrt();
        4.0 * alpha_s * (alpha_d - a2 * alpha_s) / (1.0 + alpha_d * alpha_s) - x2
    }

    /// Rayleigh function `R(v) = 4 α_d α_s − (1 + α_s²)²` [-] for a speed `0 ≤ v ≤ c_s` [m/s];
    /// `NaN` outside that range. Positive below `c_R`, negative between `c_R` and `c_s`.
    pub fn rayleigh_function(&self, v: f64) -> f64 {
        let x = v / self.cs;
        if !(0.0..=1.0).contains(&x) {
            return f64::NAN;
        }
        x * x * self.rayleigh_over_x2(x)
    }

    /// Rayleigh wave speed `c_R` [m/s]: the single root of `R(v)` in `(0, c_s)`, found by
    /// bisection on `R(v)/v²` (positive at `0⁺`, equal to −1 at `c_s`) to full double precision.
    pub fn rayleigh_speed(&self) -> f64 {
        let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.rayleigh_over_x2(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi) * self.cs
    }

    /// `∫_a^b θ(η) w(η) dη` in `c_s`-scaled slowness, with the end-point substitution and an
    /// `n`-node Gauss–Legendre rule in `φ` (see the module notes).
    fn theta_integral<W: Fn(Slowness) -> f64>(&self, n: usize, weight: W) -> f64 {
        let a = self.a_hat();
        let width = 1.0 - a;
        let half_pi = 0.5 * PI;
        gauss_legendre(n, |t| {
            let phi = half_pi * (t + 1.0);
            let (sh, ch) = (0.5 * phi).sin_cos();
            let above_a = width * sh * sh;
            let below_b = width * ch * ch;
            let eta = a + above_a;
            let root_d = (width * (eta + a)).sqrt() * sh; // sqrt(η² − a²)
            let root_s = (width * (1.0 + eta)).sqrt() * ch; // sqrt(1 − η²)
            let q = 1.0 - 2.0 * eta * eta;
            let theta = (4.0 * eta * eta * root_d * root_s).atan2(q * q);
            let jacobian = half_pi * width * sh * ch; // dη/dt
            theta * weight(Slowness { above_a, below_b }) * jacobian
        })
    }

    /// Wiener–Hopf factor `S₊(ζ) = exp(−(1/π) ∫_a^b θ(η) dη/(η + ζ))` [-] of the Rayleigh function,
    /// for a real slowness `zeta` [s/m] off the cut `[−1/c_s, −1/c_d]` (`NaN` on the cut).
    /// `S₊(±∞) = 1`, and `R(ζ) = 2(b² − a²)(c² − ζ²) S₊(ζ) S₊(−ζ)`.
    pub fn s_plus(&self, zeta: f64) -> f64 {
        self.s_plus_with_nodes(zeta, QUAD_NODES)
    }

    /// [`Material::s_plus`] with an explicit number of quadrature nodes.
    fn s_plus_with_nodes(&self, zeta: f64, n: usize) -> f64 {
        let z = zeta * self.cs;
        let a = self.a_hat();
        if z.is_nan() || (-1.0..=-a).contains(&z) {
            return f64::NAN;
        }
        if z.is_infinite() {
            return 1.0;
        }
        let integral = if z > -a {
            // η + ζ = (η − a) + (ζ + a), both terms non-negative.
            self.theta_integral(n, |s| 1.0 / (s.above_a + (z + a)))
        } else {
            // η + ζ = −[(b − η) + (−ζ − b)], both bracketed terms non-negative.
            self.theta_integral(n, |s| -1.0 / (s.below_b + (-z - 1.0)))
        };
        (-integral / PI).exp()
    }

    /// `ln S₊(−1/v) = (1/π) ∫_a^b θ(η) x dη/(1 − xη)` for `x = v/c_s ∈ [0, 1)`, with
    /// `1 − xη = (1 − x) + x(1 − η)` (no cancellation, finite at `x = 0`).
    fn ln_s_plus_behind(&self, x: f64, n: usize) -> f64 {
        let one_minus_x = 1.0 - x;
        self.theta_integral(n, |s| x / (one_minus_x + x * s.below_b)) / PI
    }

    /// Sorts a speed [m/s] into invalid (`NaN` or negative), at or above `c_R`, or sub-Rayleigh
    /// with its value `x = v/c_s`.
    fn classify(&self, v: f64) -> SpeedRange {
        let cr = self.rayleigh_speed();
        if v.is_nan() || v < 0.0 {
            SpeedRange::Invalid
        } else if v >= cr {
            SpeedRange::AtOrAboveRayleigh
        } else {
            SpeedRange::Sub {
                x: v / self.cs,
                x_r: cr / self.cs,
            }
        }
    }

    /// Universal function `k(v)` [-]: dynamic stress intensity factor of a crack tip moving at
    /// `v` [m/s] divided by the equilibrium one for the same crack length and load history
    /// (Freund 1990, ch. 6). `k(0) = 1`; returns 0 for `v ≥ c_R` and `NaN` for `v < 0` or `NaN`.
    pub fn k_of_v(&self, mode: Mode, v: f64) -> f64 {
        self.k_with_nodes(mode, v, QUAD_NODES)
    }

    /// [`Material::k_of_v`] with an explicit number of quadrature nodes.
    fn k_with_nodes(&self, mode: Mode, v: f64, n: usize) -> f64 {
        match self.classify(v) {
            SpeedRange::Invalid => f64::NAN,
            SpeedRange::AtOrAboveRayleigh => 0.0,
            SpeedRange::Sub { x, x_r } => {
                let x_wave = match mode {
                    Mode::I => x * self.a_hat(),
                    Mode::II => x,
                };
                (1.0 - x / x_r) / (1.0 - x_wave).sqrt() * self.ln_s_plus_behind(x, n).exp()
            }
        }
    }

    /// Energy factor `A(v)` [-] in `G = A(v) (1 − ν) K² / (2μ)` for a tip moving at `v` [m/s]:
    /// `A_I = v² α_d/((1−ν) c_s² R(v))`, `A_II = v² α_s/((1−ν) c_s² R(v))` (Freund 1990, ch. 5),
    /// with `A(0) = 1`. Returns `+∞` for `v ≥ c_R` and `NaN` for `v < 0` or `NaN`.
    pub fn a_of_v(&self, mode: Mode, v: f64) -> f64 {
        match self.classify(v) {
            SpeedRange::Invalid => f64::NAN,
            SpeedRange::AtOrAboveRayleigh => f64::INFINITY,
            SpeedRange::Sub { x, .. } => {
                let alpha = match mode {
                    Mode::I => (1.0 - (x * self.a_hat()).powi(2)).sqrt(),
                    Mode::II => (1.0 - x * x).sqrt(),
                };
                self.inv_one_minus_nu() * alpha / self.rayleigh_over_x2(x)
            }
        }
    }

    /// Universal function `g(v) = A(v) k(v)²` [-]: dynamic energy release rate of a tip moving at
    /// `v` [m/s] over the equilibrium one, `G = g(v) G_0` (Freund 1990, ch. 7). Decreases from
    /// `g(0) = 1` to `g(c_R) = 0`; returns 0 for `v ≥ c_R` and `NaN` for `v < 0` or `NaN`.
    pub fn g_of_v(&self, mode: Mode, v: f64) -> f64 {
        self.g_with_nodes(mode, v, QUAD_NODES)
    }

    /// [`Material::g_of_v`] with an explicit number of quadrature nodes.
    fn g_with_nodes(&self, mode: Mode, v: f64, n: usize) -> f64 {
        match self.classify(v) {
            SpeedRange::Invalid => f64::NAN,
            SpeedRange::AtOrAboveRayleigh => 0.0,
            SpeedRange::Sub { .. } => self.a_of_v(mode, v) * self.k_with_nodes(mode, v, n).powi(2),
        }
    }

    /// Tip speed [m/s] of a bilateral crack of half-length `a` under uniform remote load, from the
    /// equation of motion `g(v) G_0(a) = G_c`, i.e. `g(v) = L_c/a` with `a_over_lc = a/L_c` [-] and
    /// `L_c` from [`griffith_length`]. Returns 0 for `a ≤ L_c`, `c_R` for an infinite ratio and
    /// `NaN` for `NaN`; otherwise the root of the monotone `g` by bisection on `(0, c_R)`.
    /// Non-decreasing in `a_over_lc`. (Uses the semi-infinite-crack `g`, an approximation for a
    /// finite crack, as in Freund 1990, ch. 7.)
    pub fn speed_at_half_length(&self, mode: Mode, a_over_lc: f64) -> f64 {
        if a_over_lc.is_nan() {
            return f64::NAN;
        }
        if a_over_lc <= 1.0 {
            return 0.0;
        }
        let cr = self.rayleigh_speed();
        if a_over_lc.is_infinite() {
            return cr;
        }
        let target = 1.0 / a_over_lc;
        let (mut lo, mut hi) = (0.0_f64, cr);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if self.g_of_v(mode, mid) > target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// Speed classification used by the universal functions.
#[derive(Clone, Copy, Debug)]
enum SpeedRange {
    /// Negative or `NaN` speed.
    Invalid,
    /// `v ≥ c_R`: outside the sub-Rayleigh range of the functions.
    AtOrAboveRayleigh,
    /// `0 ≤ v < c_R`, with `x = v/c_s` and `x_r = c_R/c_s`.
    Sub { x: f64, x_r: f64 },
}

/// Griffith half-length `L_c` [m] of a crack in an unbounded plane-strain body under uniform
/// remote load `load` [Pa] (σ for mode I, stress drop Δτ for mode II): `L_c = 2 μ' G_c/(π load²)`,
/// `μ' = μ/(1 − ν)`, with shear modulus `mu` [Pa], Poisson's ratio `nu` [-] and fracture energy
/// `gc` [J/m²]. It solves `G_0(L_c) = G_c` with [`static_energy_release_rate`]. No validation:
/// non-physical inputs give non-finite or negative results.
pub fn griffith_length(mu: f64, nu: f64, gc: f64, load: f64) -> f64 {
    2.0 * mu / (1.0 - nu) * gc / (PI * load * load)
}

/// Static energy release rate `G_0 = π a load² (1 − ν)/(2μ)` [J/m²] of a crack of half-length `a`
/// [m] under uniform remote load `load` [Pa] in plane strain (`mu` [Pa], `nu` [-]).
pub fn static_energy_release_rate(mu: f64, nu: f64, a: f64, load: f64) -> f64 {
    PI * a * load * load * (1.0 - nu) / (2.0 * mu)
}

/// Seismic ratio `S = (τ_s − τ_0)/(τ_0 − τ_d)` [-] from the static strength `tau_s`, initial
/// shear stress `tau_0` and dynamic (residual) strength `tau_d` [Pa]. `None` unless the inputs are
/// finite with `τ_0 > τ_d` (positive stress drop) and `τ_s ≥ τ_0` (fault not already failing).
pub fn seismic_ratio(tau_s: f64, tau_0: f64, tau_d: f64) -> Option<f64> {
    let finite = tau_s.is_finite() && tau_0.is_finite() && tau_d.is_finite();
    (finite && tau_0 > tau_d && tau_s >= tau_0).then(|| (tau_s - tau_0) / (tau_0 - tau_d))
}

/// Critical length `L_c` [m] of Andrews (1976) for linear slip weakening (strength falls from
/// `tau_s` to `tau_d` [Pa] over slip `dc` [m]; initial stress `tau_0` [Pa]; shear modulus `mu` [Pa],
/// Poisson's ratio `nu` [-]): `L_c = [(λ + μ)/(λ + 2μ)] μ D_c (τ_s − τ_d)/(π (τ_0 − τ_d)²)
/// = μ D_c (τ_s − τ_d)/(2π (1 − ν) (τ_0 − τ_d)²)`.
///
/// This is half the plane-strain Griffith half-length [`griffith_length`] with fracture energy
/// `G_c = (τ_s − τ_d) D_c / 2` and load `Δτ = τ_0 − τ_d`, the length the coefficient 9.8 of
/// [`andrews_transition_distance`] is quoted with (docs/spectral-model.md §7.7, whose test of the
/// spectral model uses the same). `None` unless `τ_0 > τ_d`, `τ_s > τ_d`, `dc > 0`, `mu > 0`,
/// `−1 < ν < 1/2` and all finite.
pub fn andrews_critical_length(mu: f64, nu: f64, dc: f64, tau_s: f64, tau_0: f64, tau_d: f64) -> Option<f64> {
    let finite = [mu, nu, dc, tau_s, tau_0, tau_d].iter().all(|x| x.is_finite());
    let valid = finite && tau_0 > tau_d && tau_s > tau_d && dc > 0.0 && mu > 0.0 && nu > -1.0 && nu < 0.5;
    valid.then(|| 0.5 * griffith_length(mu, nu, 0.5 * (tau_s - tau_d) * dc, tau_0 - tau_d))
}

/// Andrews' (1976) fit for the rupture half-length [m] (propagation distance from the centre of a
/// bilateral 2D plane-strain shear crack) at which a supershear daughter rupture appears:
/// `L = 9.8 (1.77 − S)^−3 L_c`, with seismic ratio `s` [-] ([`seismic_ratio`]) and `lc` [m] the
/// critical half-length of [`andrews_critical_length`].
///
/// `None` for `S ≥ 1.77` (no transition in Andrews' 2D runs), for `S < 0` (outside the fitted
/// range: the fault is already above its strength), or for non-finite input. The fit belongs to
/// Andrews' nucleation procedure and linear slip-weakening law: the transition distance depends
/// on how the rupture is nucleated, on the shape of the weakening law and on resolution, and later
/// studies find values differing by factors of order one, so treat the result as an estimate.
pub fn andrews_transition_distance(s: f64, lc: f64) -> Option<f64> {
    let valid = s.is_finite() && lc.is_finite() && (0.0..ANDREWS_S_MAX).contains(&s);
    valid.then(|| ANDREWS_COEFFICIENT * lc / (ANDREWS_S_MAX - s).powi(3))
}

#[cfg(test)]
mod tests;
