//! The mean contact tractions in the limit ε_n → ∞. A penalty layer is a compliance 1/ε_n in
//! series with the bulk between the crack and the displacement-controlled boundary, so a window
//! mean falls short of its far-field value by an amount ∝ 1/ε_n: mean = m_∞ + b·(E/ε_n). The
//! paper's claim (the means tend to |s_yy| and μ|s_yy|, Figure 6c, Appendix D) is the
//! statement about m_∞, fitted by least squares through the runs of the study.

use super::rows::SummaryRow;
use crate::series::least_squares_slope;
use serde::Serialize;

/// One traction's limit (a row of `penalty_limit.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Limit {
    /// `normal` (before the onset) or `tangential` (while slipping).
    pub traction: &'static str,
    /// Extrapolated mean m_∞ [Pa].
    pub limit: f64,
    /// Its far-field value: |s_yy| or μ|s_yy| [Pa].
    pub expected: f64,
    /// (m_∞ − expected)/expected [-].
    pub rel_error: f64,
    /// Slope b of mean against E/ε_n [Pa].
    pub slope: f64,
    /// Whether |error| falls at every step up in ε_n among the runs.
    pub monotone: bool,
}

/// Intercept and slope of the least-squares line through (x, y).
fn line(points: &[(f64, f64)]) -> (f64, f64) {
    let (x, y): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
    let b = least_squares_slope(&x, &y);
    let n = points.len() as f64;
    (y.iter().sum::<f64>() / n - b * x.iter().sum::<f64>() / n, b)
}

/// The limits of both tractions from the study's summary rows (at least two factors with a
/// mean), against |s_yy| [Pa] and μ [-].
pub fn limits(rows: &[SummaryRow], s_yy: f64, friction_coeff: f64) -> Vec<Limit> {
    let mut rows: Vec<&SummaryRow> = rows.iter().collect();
    rows.sort_by_key(|r| r.eps_factor);
    let mut out = Vec::new();
    for (traction, expected, mean) in [
        (
            "normal",
            s_yy,
            (|r: &SummaryRow| r.mean_normal_before_onset) as fn(&SummaryRow) -> Option<f64>,
        ),
        ("tangential", friction_coeff * s_yy, |r: &SummaryRow| {
            r.mean_tangential_while_slipping
        }),
    ] {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| mean(r).map(|m| (1.0 / f64::from(r.eps_factor), m)))
            .collect();
        if pts.len() < 2 || expected <= 0.0 {
            continue;
        }
        let (limit, slope) = line(&pts);
        let errors: Vec<f64> = pts.iter().map(|p| (p.1 - expected).abs()).collect();
        out.push(Limit {
            traction,
            limit,
            expected,
            rel_error: (limit - expected) / expected,
            slope,
            monotone: errors.windows(2).all(|w| w[1] < w[0]),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(eps_factor: u32, normal: f64, tangential: f64) -> SummaryRow {
        SummaryRow {
            eps_factor,
            max_penetration_over_2a_at_profile: 0.0,
            mean_normal_before_onset: Some(normal),
            rel_error_normal: None,
            mean_tangential_while_slipping: Some(tangential),
            rel_error_tangential: None,
        }
    }

    #[test]
    fn a_compliance_in_series_extrapolates_to_the_far_field() {
        // mean = 50 kPa − 2.4e6 Pa · (E/ε_n): exactly on the model, so m_∞ = 50 kPa
        let m = |f: f64| 5e4 - 2.4e6 / f;
        let rows = [
            row(1000, m(1000.0), 0.3 * m(1000.0)),
            row(300, m(300.0), 0.3 * m(300.0)),
        ];
        let l = limits(&rows, 5e4, 0.3);
        assert_eq!(l.len(), 2);
        assert!(
            (l[0].limit - 5e4).abs() < 1e-6 && l[0].rel_error.abs() < 1e-12,
            "{l:?}"
        );
        assert!((l[0].slope + 2.4e6).abs() < 1e-3 && l[0].monotone);
        assert!((l[1].limit - 1.5e4).abs() < 1e-6, "{l:?}");
    }

    #[test]
    fn an_error_that_grows_with_the_penalty_is_not_monotone() {
        let rows = [row(300, 4.9e4, 1.4e4), row(1000, 4.8e4, 1.45e4)];
        let l = limits(&rows, 5e4, 0.3);
        assert!(!l[0].monotone && l[1].monotone, "{l:?}");
        assert!(limits(&rows[..1], 5e4, 0.3).is_empty(), "one run has no limit");
    }
}
