//! A Freund case's figure: tip speed against crack length, both models and the theory.

use super::metrics::{FreundCase, SpeedRow};
use crate::plot::{Curve, Dash, Labels, Mark, line_chart};
use anyhow::Result;
use plotters::style::BLACK;
use std::path::{Path, PathBuf};

/// Draws `path`: v/c_R against a/a₀ for the FE model, the spectral model and the theory under the
/// final load (a/L_c = 1/g(v)); the speeds are compared with the theory under the load of the
/// moment (`speeds.csv`), which the final load's curve reaches once the ramp is over.
pub fn draw(path: &Path, name: &str, case: &FreundCase, speeds: &[SpeedRow]) -> Result<PathBuf> {
    let cr = case.material.rayleigh_speed();
    let points = |v: fn(&SpeedRow) -> f64| -> Vec<(f64, f64)> {
        speeds
            .iter()
            .filter(|s| v(s).is_finite())
            .map(|s| (s.a_over_a0, v(s) / cr))
            .collect()
    };
    let end = case.load.ramp_end.max(case.load.ramp_start);
    let theory: Vec<(f64, f64)> = (0..=200)
        .map(|k| {
            let x = 1.0 + 2.2 * f64::from(k) / 200.0;
            (x, case.theory_speed(x * case.a0, end) / cr)
        })
        .collect();
    let title = format!("{name}: tip speed against crack length");
    line_chart(
        path,
        Labels {
            title: &title,
            x: "crack half-length a / a0 [-]",
            y: "tip speed v / c_R [-]",
        },
        &[
            Curve::nth("FE", points(|s| s.fem_speed), 0, Dash::Solid),
            Curve::nth("spectral", points(|s| s.spectral_speed), 1, Dash::Solid),
            Curve::nth("theory, a/L_c = 1/g(v)", theory, 2, Dash::Dashed),
        ],
        &[Mark::Horizontal(1.0, BLACK, "c_R".into())],
    )?;
    Ok(path.to_path_buf())
}
