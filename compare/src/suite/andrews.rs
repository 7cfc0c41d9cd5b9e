//! What the suite measures on an Andrews case: the rupture front of each model, its speed at each
//! half-length, the half-length at which it turns supershear, and the metrics of `suite.csv`.
//!
//! The front is the contiguous failed set walking out from the centre, in both models: the
//! spectral model's tip (its last fully broken point of that set, docs/spectral-model.md), and on
//! the FE side, from the failure time of every interface Gauss point, the time by which every point
//! between the pre-crack and x has failed. A daughter rupture born ahead of the front joins it when
//! the set between them has broken: there the front jumps.
//!
//! The speed at a half-length a is 1/(dt/da), the least-squares slope of t against a over the front
//! points within one process zone Λ₀ of a ([`super::metrics::speed_at`]). The transition half-length
//! is the first a, from a₀ + Λ₀ in steps of Λ₀/10, at which that speed exceeds √2 c_s: the slowest
//! speed of a steady supershear rupture (Freund 1990, §6.4; Andrews 1976). A sub-Rayleigh front stays
//! below c_R in the continuum; a threshold of c_s, just above c_R, would also count a discretised
//! sub-Rayleigh front that overshoots c_R (docs/results.md gives both).

use super::SuiteRow;
use super::metrics::speed_at;
use crate::theory::freund::{andrews_critical_length, andrews_transition_distance, seismic_ratio};
use anyhow::{Result, anyhow, bail, ensure};
use serde::Serialize;

/// FE and spectral transition half-lengths agree within this share of the spectral one [-].
pub const TRANSITION_TOLERANCE: f64 = 0.10;

/// Each model's transition half-length lies within this factor of Andrews' fit [-]: the fit
/// belongs to Andrews' nucleation, and ours (a pre-crack at the residual strength, loads ramped)
/// differs.
pub const ANDREWS_FACTOR: f64 = 2.0;

/// The crack must run over at least this many initial half-lengths [-] for "no transition" at
/// S > 1.77 to mean something: Andrews' S = 1.2 transition lies at 26 a_c there.
pub const REACH_MIN: f64 = 8.0;

/// The scales of an Andrews case, from its scene.
#[derive(Debug, Clone, Copy)]
pub struct AndrewsCase {
    /// Initial half-length a₀ [m] (the pre-crack at the residual strength).
    pub a0: f64,
    /// Static process zone Λ₀ = (9π/32) μ' D_c/(τ_p − τ_r) [m] of linear slip weakening.
    pub lp: f64,
    /// Shear wave speed c_s [m/s].
    pub cs: f64,
    /// Dilatational wave speed c_d [m/s].
    pub cd: f64,
    /// Rayleigh speed c_R [m/s].
    pub cr: f64,
    /// Seismic ratio S = (τ_p − τ_0)/(τ_0 − τ_r) of the final load [-].
    pub s: f64,
    /// Andrews' critical length L_c [m] (`theory::freund::andrews_critical_length`).
    pub lc: f64,
    /// Griffith half-length a_c = 2 L_c [m].
    pub ac: f64,
}

impl AndrewsCase {
    /// The case of `scene`: its interface in shear under the compression of `[loading]` is linear
    /// slip weakening from τ_p = βσ_c + μ|σ_yy| to τ_r = μ|σ_yy| over the slip κδ_c/β (the hybrid
    /// rule: the cohesive shear law on top of Coulomb friction).
    pub fn from_scene(scene: &fem::Scene) -> Result<Self> {
        let (crack, law) = match (scene.crack, scene.interface) {
            (Some(c), Some(l)) => (c, l),
            _ => bail!("an Andrews case needs [crack] and [interface]"),
        };
        let normal = scene.loading.normal.final_value;
        ensure!(
            normal < 0.0,
            "loading.normal.final: an Andrews case needs compression (< 0), got {normal} Pa"
        );
        let tau_r = scene.friction_coeff * normal.abs();
        let tau_p = law.beta * law.sigma_c + tau_r;
        let tau_0 = scene.loading.shear.final_value;
        let dc = law.kappa * law.delta_c / law.beta;
        let s = seismic_ratio(tau_p, tau_0, tau_r).ok_or_else(|| {
            anyhow!(
                "loading.shear.final: {tau_0} Pa must lie between tau_r = {tau_r} Pa and tau_p = {tau_p} Pa"
            )
        })?;
        let m = scene.material;
        let lc = andrews_critical_length(m.shear_modulus, m.poisson_ratio, dc, tau_p, tau_0, tau_r)
            .ok_or_else(|| anyhow!("invariant: a validated material and law"))?;
        let w = m.wave_speeds();
        let mu_prime = m.shear_modulus / (1.0 - m.poisson_ratio);
        Ok(Self {
            a0: crack.half_length,
            lp: 9.0 * std::f64::consts::PI / 32.0 * mu_prime * dc / (tau_p - tau_r),
            cs: w.cs,
            cd: w.cd,
            cr: w.cr,
            s,
            lc,
            ac: 2.0 * lc,
        })
    }

    /// Andrews' transition half-length 9.8 (1.77 − S)⁻³ L_c [m]; `None` for S ≥ 1.77.
    pub fn andrews_distance(&self) -> Option<f64> {
        andrews_transition_distance(self.s, self.lc)
    }

    /// The speed threshold of a supershear front, √2 c_s [m/s].
    pub fn supershear_threshold(&self) -> f64 {
        std::f64::consts::SQRT_2 * self.cs
    }

    /// The half-lengths the front speed is read at [m]: from a₀ + Λ₀ to `a_end` in steps of Λ₀/10.
    pub fn lengths(&self, a_end: f64) -> impl Iterator<Item = f64> + '_ {
        let step = 0.1 * self.lp;
        (0..)
            .map(move |k| self.a0 + self.lp + step * f64::from(k))
            .take_while(move |a| *a <= a_end)
    }
}

/// The FE front: from `points` (x [m], failure time [s], NaN if never), on each side of `centre`
/// [m], the time by which every point from the pre-crack's tip out to x has failed, as (half-length
/// [m], time [s]); walking out, it stops at the first point that never failed.
pub fn contiguous_front(points: &[(f64, f64)], centre: f64, a0: f64) -> Vec<(f64, f64)> {
    let mut front = Vec::new();
    for side in [1.0, -1.0] {
        let mut out: Vec<(f64, f64)> = points
            .iter()
            .map(|&(x, t)| (side * (x - centre), t))
            .filter(|(a, _)| *a > a0)
            .collect();
        out.sort_by(|p, q| p.0.total_cmp(&q.0));
        let mut latest = f64::NEG_INFINITY;
        for (a, t) in out {
            if !t.is_finite() {
                break;
            }
            latest = latest.max(t);
            front.push((a, latest));
        }
    }
    front
}

/// The spectral front: (half-length (tip_right − tip_left)/2 [m], time [s]) of each record whose
/// half-length is the largest so far and beyond a₀.
pub fn spectral_front(tips: &[spectral::TipRecord], a0: f64) -> Vec<(f64, f64)> {
    let mut front = Vec::new();
    let mut largest = a0;
    for r in tips {
        let a = 0.5 * (r.tip_right - r.tip_left);
        if a > largest {
            largest = a;
            front.push((a, r.t));
        }
    }
    front
}

/// The largest half-length of a front [m] (NaN for an empty one).
pub fn reach(front: &[(f64, f64)]) -> f64 {
    front.iter().map(|p| p.0).fold(f64::NAN, f64::max)
}

/// One half-length of `front_speeds.csv`.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FrontSpeedRow {
    /// Half-length a [m].
    pub half_length: f64,
    /// FE front speed [m/s] (NaN: too few points).
    pub fem_speed: f64,
    /// Spectral front speed [m/s].
    pub spectral_speed: f64,
}

/// What one model's front gives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrontMeasure {
    /// Transition half-length [m] (`None`: the front never exceeded √2 c_s up to `a_end`).
    pub transition: Option<f64>,
    /// Mean speed of the supershear front [m/s]: the least-squares speed over the half-lengths from
    /// halfway between the transition and `a_end` to `a_end` (NaN without a transition).
    pub supershear_speed: f64,
    /// Largest front speed over the read half-lengths [m/s].
    pub max_speed: f64,
}

/// Measures `front` up to `a_end` [m].
pub fn measure_front(case: &AndrewsCase, front: &[(f64, f64)], a_end: f64) -> FrontMeasure {
    let speeds: Vec<(f64, f64)> = case
        .lengths(a_end)
        .map(|a| (a, speed_at(front, a, case.lp).map_or(f64::NAN, |s| s.v)))
        .collect();
    let transition = speeds
        .iter()
        .find(|(_, v)| *v > case.supershear_threshold())
        .map(|(a, _)| *a);
    let supershear_speed = transition.map_or(f64::NAN, |a_tr| {
        let lo = 0.5 * (a_tr + a_end);
        let (x, t): (Vec<f64>, Vec<f64>) = front
            .iter()
            .filter(|p| p.0 >= lo && p.0 <= a_end)
            .copied()
            .unzip();
        let slowness = crate::series::least_squares_slope(&x, &t);
        if x.len() >= 3 && slowness > 0.0 {
            1.0 / slowness
        } else {
            f64::NAN
        }
    });
    let max_speed = speeds.iter().map(|p| p.1).fold(f64::NAN, f64::max);
    FrontMeasure {
        transition,
        supershear_speed,
        max_speed,
    }
}

/// The rows of `front_speeds.csv`.
pub fn speed_rows(
    case: &AndrewsCase,
    fem: &[(f64, f64)],
    spectral: &[(f64, f64)],
    a_end: f64,
) -> Vec<FrontSpeedRow> {
    case.lengths(a_end)
        .map(|a| FrontSpeedRow {
            half_length: a,
            fem_speed: speed_at(fem, a, case.lp).map_or(f64::NAN, |s| s.v),
            spectral_speed: speed_at(spectral, a, case.lp).map_or(f64::NAN, |s| s.v),
        })
        .collect()
}

/// The metrics of an Andrews case from each model's front (FE, spectral) and how far each front
/// reached [m]. Below S = 1.77: the transition half-lengths agree, each lies within a factor of
/// Andrews' fit, and each supershear front runs between √2 c_s and c_d. Above: neither front
/// exceeds c_s, over a crack that ran at least [`REACH_MIN`] initial half-lengths.
pub fn rows(name: &str, case: &AndrewsCase, m: [FrontMeasure; 2], reach: [f64; 2]) -> Vec<SuiteRow> {
    let row = |metric: &str, value: f64, tolerance: String, pass: bool| SuiteRow {
        case: name.to_string(),
        metric: metric.to_string(),
        value,
        tolerance,
        pass: pass && !value.is_nan(),
    };
    let tr = |k: usize| m[k].transition.unwrap_or(f64::NAN);
    let Some(andrews) = case.andrews_distance() else {
        let mut rows = Vec::new();
        for (k, model) in ["fem", "spectral"].into_iter().enumerate() {
            let max = m[k].max_speed / case.cs;
            rows.push(row(
                &format!("{model}_front_speed_max_over_cs"),
                max,
                "<= 1".into(),
                max <= 1.0,
            ));
        }
        for (k, model) in ["fem", "spectral"].into_iter().enumerate() {
            let reached = reach[k] / case.a0;
            rows.push(row(
                &format!("{model}_reach_over_a0"),
                reached,
                format!(">= {}", REACH_MIN),
                reached >= REACH_MIN,
            ));
        }
        return rows;
    };
    let difference = (tr(0) - tr(1)).abs() / tr(1);
    let mut rows = vec![row(
        "transition_difference",
        difference,
        format!("<= {TRANSITION_TOLERANCE}"),
        difference <= TRANSITION_TOLERANCE,
    )];
    let bounds = (std::f64::consts::SQRT_2, case.cd / case.cs);
    for (k, model) in ["fem", "spectral"].into_iter().enumerate() {
        let factor = tr(k) / andrews;
        rows.push(row(
            &format!("{model}_transition_over_andrews"),
            factor,
            format!("in [{}, {}]", 1.0 / ANDREWS_FACTOR, ANDREWS_FACTOR),
            (1.0 / ANDREWS_FACTOR..=ANDREWS_FACTOR).contains(&factor),
        ));
    }
    for (k, model) in ["fem", "spectral"].into_iter().enumerate() {
        let speed = m[k].supershear_speed / case.cs;
        rows.push(row(
            &format!("{model}_supershear_speed_over_cs"),
            speed,
            format!("in ({:.4}, {:.4})", bounds.0, bounds.1),
            speed > bounds.0 && speed < bounds.1,
        ));
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case() -> AndrewsCase {
        AndrewsCase {
            a0: 0.01,
            lp: 0.005,
            cs: 100.0,
            cd: 200.0,
            cr: 93.0,
            s: 1.0,
            lc: 0.01,
            ac: 0.02,
        }
    }

    /// A front at 90 m/s that jumps at 0.1 m to 180 m/s: the transition is read within half a
    /// process zone of the jump, the supershear speed is 180 m/s, and a front that never jumps
    /// has none (its largest speed is 90 m/s).
    #[test]
    fn a_jump_to_supershear_is_found_near_where_it_happens() {
        let c = case();
        let front: Vec<(f64, f64)> = (0..4000)
            .map(|k| {
                let a = 0.01 + 1e-4 * f64::from(k);
                let t = if a < 0.1 {
                    (a - 0.01) / 90.0
                } else {
                    0.09 / 90.0 + (a - 0.1) / 180.0
                };
                (a, t)
            })
            .collect();
        let m = measure_front(&c, &front, 0.4);
        let tr = m.transition.expect("a transition");
        assert!((tr - 0.1).abs() < 0.5 * c.lp, "{tr}");
        assert!((m.supershear_speed - 180.0).abs() < 1e-6, "{m:?}");
        let slow: Vec<(f64, f64)> = front.iter().map(|p| (p.0, (p.0 - 0.01) / 90.0)).collect();
        let m = measure_front(&c, &slow, 0.4);
        assert!(m.transition.is_none() && m.supershear_speed.is_nan());
        assert!((m.max_speed - 90.0).abs() < 1e-6, "{m:?}");
    }

    /// The FE front waits for every point behind it: a point that fails early ahead of an
    /// unbroken one does not move it, and a point that never fails ends it.
    #[test]
    fn the_fe_front_is_the_contiguous_failed_set() {
        let points = [
            (0.011, 1.0),
            (0.012, 3.0),
            (0.013, 2.0),
            (0.014, 4.0),
            (0.015, f64::NAN),
            (0.016, 5.0),
            (-0.012, 1.5),
        ];
        let front = contiguous_front(&points, 0.0, 0.01);
        assert_eq!(
            front,
            vec![
                (0.011, 1.0),
                (0.012, 3.0),
                (0.013, 3.0),
                (0.014, 4.0),
                (0.012, 1.5)
            ]
        );
    }
}
