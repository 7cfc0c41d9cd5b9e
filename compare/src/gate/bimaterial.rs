//! A centre crack between two different half-spaces: what each tip does. With two materials the
//! tips are no longer mirror images. The tip that runs in the direction of slip of the more
//! compliant body, the one with the lower shear-wave speed (the "positive" direction of Weertman 1980, Andrews & Ben-Zion 1997) is drawn
//! towards the generalized Rayleigh speed c_GR; the other is not (Ranjith & Rice 2001; Rubin &
//! Ampuero 2007). This module names each tip's direction and sets both models' tip speeds against
//! c_GR and the slower shear speed. Pure; the gate writes its rows as `bimaterial_tips.csv`.

use serde::Serialize;

use super::metrics::MuRuns;
use crate::series::{Series, Tip, mean_speed};
use crate::study::{Case, Pair};

/// One row of `bimaterial_tips.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct TipSpeedRow {
    /// Friction coefficient μ [-].
    pub mu: f64,
    /// Which tip.
    pub tip: Tip,
    /// "positive" (the direction of slip of the more compliant body) or "negative".
    pub direction: &'static str,
    /// FE mean tip speed between 1.2a and 1.9a of that tip's distance [m/s] (NaN if never reached).
    pub fem_speed: f64,
    /// Spectral mean tip speed over the same window [m/s].
    pub spectral_speed: f64,
    /// FE speed over c_GR [-] (NaN when c_GR does not exist).
    pub fem_over_c_gr: f64,
    /// Spectral speed over c_GR [-].
    pub spectral_over_c_gr: f64,
    /// c_GR over the slower c_s [-] (NaN when c_GR does not exist).
    pub c_gr_over_slower_cs: f64,
}

/// Each tip of each friction value: its direction and both models' speeds against c_GR.
pub fn tip_speeds(case: &Case, pair: &Pair, shear_sign: f64, runs: &[MuRuns]) -> Vec<TipSpeedRow> {
    let a = case.half_length;
    let c_gr = pair.generalized_rayleigh.unwrap_or(f64::NAN);
    let positive = pair.positive_tip(shear_sign);
    let mut rows = Vec::new();
    for r in runs {
        for tip in [Tip::Right, Tip::Left] {
            let speed = |rows: &[crate::series::TipRow]| {
                mean_speed(&Series::tip_distance(rows, case.center_x, tip), a).unwrap_or(f64::NAN)
            };
            let (vf, vs) = (speed(&r.fem), speed(&r.spectral));
            rows.push(TipSpeedRow {
                mu: r.mu,
                tip,
                direction: if tip == positive { "positive" } else { "negative" },
                fem_speed: vf,
                spectral_speed: vs,
                fem_over_c_gr: vf / c_gr,
                spectral_over_c_gr: vs / c_gr,
                c_gr_over_slower_cs: c_gr / pair.slower_cs(),
            });
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solid(e: f64) -> spectral::Solid {
        spectral::Solid {
            youngs_modulus: e,
            poisson_ratio: 0.35,
            density: 1230.0,
        }
    }

    #[test]
    fn the_positive_tip_follows_the_compliant_body_and_the_shear_sign() {
        let p = Pair::new(solid(70e6), solid(100.8e6));
        assert_eq!(p.positive_tip(1.0), Tip::Right);
        assert_eq!(p.positive_tip(-1.0), Tip::Left);
        let q = Pair::new(solid(100.8e6), solid(70e6));
        assert_eq!(q.positive_tip(1.0), Tip::Left);
        let c = p.generalized_rayleigh.unwrap() / p.slower_cs();
        assert!((c - 0.99448).abs() < 1e-4, "{c}");
        assert_eq!(Pair::new(solid(70e6), solid(118.3e6)).generalized_rayleigh, None);
    }
}
