//! What the suite measures on a Freund case: the tip speed of each model at each crack length,
//! the theory's speed there, and the metrics of `suite.csv`.
//!
//! A model's crack is a set of arrival points (half-length a [m], time t [s]): the FE model's
//! interface Gauss points with their failure times (exact per point, on both sides of the
//! centre), the spectral model's half-length at every step. The speed at a is 1/(dt/da), the
//! least-squares slope of t against a over the points within one process zone l_p of a: a
//! cohesive crack's tip is not defined more finely than its process zone.

use super::SuiteRow;
use crate::series::least_squares_slope;
use crate::theory::freund::{Material, Mode};
use serde::Serialize;

/// The crack lengths the speeds are compared at, over the initial half-length a₀ [-]: 1.2 to 3.0
/// in steps of 0.1.
pub fn lengths() -> impl Iterator<Item = f64> {
    (12..=30).map(|k| f64::from(k) / 10.0)
}

/// FE tip speeds agree with the spectral ones at each crack length from 1.2 a₀ to 3 a₀ within this
/// share of the spectral speed [-]: the gate's tolerance on the mean speeds (docs/outputs.md).
pub const SPEED_TOLERANCE: f64 = 0.05;

/// Each model's speed puts its crack, by the theory, within this many process zones l_p of its
/// measured length [-] (in the theory's speed range): a cohesive crack's tip is not defined more
/// finely than its process zone, and the equation of motion G = g(v) G_static ∝ a shifts by
/// l_p/a when a does by l_p.
pub const LENGTH_TOLERANCE: f64 = 1.0;

/// Speeds are compared with the theory only in this range of v/c_R [-]: below it the crack is
/// still starting, above it the theory's a(v) = L_c/g(v) is too steep for a speed to fix a length.
pub const THEORY_SPEED_RANGE: (f64, f64) = (0.2, 0.9);

/// The scales of a Freund case.
#[derive(Debug, Clone, Copy)]
pub struct FreundCase {
    /// Loading mode: I (tension) or II (shear).
    pub mode: Mode,
    /// Initial half-length a₀ [m].
    pub a0: f64,
    /// Static process zone l_p = (9π/32) μ' δ_c/σ_c [m] of the linear cohesive law.
    pub lp: f64,
    /// Material of the theory (c_d, c_s).
    pub material: Material,
    /// μ' = μ/(1 − ν) [Pa].
    pub mu_prime: f64,
    /// G_c = σ_c δ_c/2 [J/m²].
    pub gc: f64,
    /// The far-field load that drives the crack (σ_yy for mode I, σ_xy for mode II) [Pa].
    pub load: fem::scene::Ramp,
}

impl FreundCase {
    /// The Griffith length L_c = 2μ'G_c/(π load²) [m] under the load at time t [s].
    pub fn griffith_length(&self, t: f64) -> f64 {
        let s = self.load.value(t);
        2.0 * self.mu_prime * self.gc / (std::f64::consts::PI * s * s)
    }

    /// The theory's speed [m/s] of a crack of half-length a [m] under the load at time t [s].
    pub fn theory_speed(&self, a: f64, t: f64) -> f64 {
        self.material
            .speed_at_half_length(self.mode, a / self.griffith_length(t))
    }

    /// |a − L_c(t)/g(v)| / l_p [-]: how far from the measured length the theory puts the measured
    /// speed v [m/s], in process zones.
    pub fn length_residual(&self, a: f64, t: f64, v: f64) -> f64 {
        let g = self.material.g_of_v(self.mode, v);
        (a - self.griffith_length(t) / g).abs() / self.lp
    }
}

/// A speed measured at one crack length: v [m/s] and the time [s] the fit puts the tip at a.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Speed {
    /// Tip speed [m/s].
    pub v: f64,
    /// Time at which the fitted tip is at a [s].
    pub t: f64,
}

/// The speed at half-length `a` [m] from arrival `points` (a_i [m], t_i [s]) within `half_width`
/// [m] of it; `None` with fewer than three points there or a non-increasing fit.
pub fn speed_at(points: &[(f64, f64)], a: f64, half_width: f64) -> Option<Speed> {
    let (x, t): (Vec<f64>, Vec<f64>) = points
        .iter()
        .filter(|p| (p.0 - a).abs() <= half_width && p.1.is_finite())
        .copied()
        .unzip();
    if x.len() < 3 {
        return None;
    }
    let slowness = least_squares_slope(&x, &t);
    let (xm, tm) = (
        x.iter().sum::<f64>() / x.len() as f64,
        t.iter().sum::<f64>() / t.len() as f64,
    );
    (slowness > 0.0).then(|| Speed {
        v: 1.0 / slowness,
        t: tm + slowness * (a - xm),
    })
}

/// One crack length of `speeds.csv`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SpeedRow {
    /// Crack half-length over the initial one, a/a₀ [-].
    pub a_over_a0: f64,
    /// FE tip speed [m/s] (NaN: too few points).
    pub fem_speed: f64,
    /// Spectral tip speed [m/s].
    pub spectral_speed: f64,
    /// The theory's speed under the load when the FE tip was at a [m/s].
    pub fem_theory_speed: f64,
    /// The theory's speed under the load when the spectral tip was at a [m/s].
    pub spectral_theory_speed: f64,
    /// |a − L_c/g(v_FE)|/l_p [-] (NaN outside the theory's speed range).
    pub fem_length_residual: f64,
    /// |a − L_c/g(v_SBI)|/l_p [-].
    pub spectral_length_residual: f64,
}

/// The rows of `speeds.csv` from both models' arrival points.
pub fn speed_rows(case: &FreundCase, fem: &[(f64, f64)], spectral: &[(f64, f64)]) -> Vec<SpeedRow> {
    let cr = case.material.rayleigh_speed();
    let in_range = |v: f64| v > THEORY_SPEED_RANGE.0 * cr && v < THEORY_SPEED_RANGE.1 * cr;
    lengths()
        .map(|x| {
            let a = x * case.a0;
            let (f, s) = (speed_at(fem, a, case.lp), speed_at(spectral, a, case.lp));
            let theory = |s: Option<Speed>| s.map_or(f64::NAN, |s| case.theory_speed(a, s.t));
            let residual = |s: Option<Speed>| match s {
                Some(s) if in_range(s.v) => case.length_residual(a, s.t, s.v),
                _ => f64::NAN,
            };
            SpeedRow {
                a_over_a0: x,
                fem_speed: f.map_or(f64::NAN, |s| s.v),
                spectral_speed: s.map_or(f64::NAN, |s| s.v),
                fem_theory_speed: theory(f),
                spectral_theory_speed: theory(s),
                fem_length_residual: residual(f),
                spectral_length_residual: residual(s),
            }
        })
        .collect()
}

/// The largest of `values`, NaN if any is NaN (a length a model never reached fails the metric)
/// or if there are none.
pub fn worst(values: impl Iterator<Item = f64>) -> f64 {
    let mut worst = f64::NAN;
    for (k, v) in values.enumerate() {
        if v.is_nan() {
            return f64::NAN;
        }
        worst = if k == 0 { v } else { worst.max(v) };
    }
    worst
}

/// The metrics of a Freund case from its `speeds`.
pub fn rows(case: &str, speeds: &[SpeedRow]) -> Vec<SuiteRow> {
    let row = |metric: &str, value: f64, limit: f64| SuiteRow {
        case: case.to_string(),
        metric: metric.to_string(),
        value,
        tolerance: format!("<= {limit}"),
        pass: value <= limit,
    };
    let in_range = |v: f64| !v.is_nan();
    vec![
        row(
            "speed_difference_max",
            worst(
                speeds
                    .iter()
                    .map(|s| (s.fem_speed - s.spectral_speed).abs() / s.spectral_speed),
            ),
            SPEED_TOLERANCE,
        ),
        row(
            "fem_theory_length_residual_max_over_lp",
            worst(
                speeds
                    .iter()
                    .map(|s| s.fem_length_residual)
                    .filter(|v| in_range(*v)),
            ),
            LENGTH_TOLERANCE,
        ),
        row(
            "spectral_theory_length_residual_max_over_lp",
            worst(
                speeds
                    .iter()
                    .map(|s| s.spectral_length_residual)
                    .filter(|v| in_range(*v)),
            ),
            LENGTH_TOLERANCE,
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tip running at 100 m/s from 0.05 m at t = 1 ms, sampled every 0.1 mm: the fit returns
    /// that speed and the time at each length; too few points give none.
    #[test]
    fn the_speed_is_the_inverse_slope_of_the_arrivals() {
        let points: Vec<(f64, f64)> = (0..1000)
            .map(|k| {
                let a = 0.05 + 1e-4 * f64::from(k);
                (a, 1e-3 + (a - 0.05) / 100.0)
            })
            .collect();
        let s = speed_at(&points, 0.08, 0.005).unwrap();
        assert!(
            (s.v - 100.0).abs() < 1e-9 && (s.t - (1e-3 + 0.03 / 100.0)).abs() < 1e-15,
            "{s:?}"
        );
        assert!(speed_at(&points, 0.2, 0.005).is_none());
        assert!(worst([1.0, 3.0, 2.0].into_iter()) == 3.0 && worst([1.0, f64::NAN].into_iter()).is_nan());
    }
}
