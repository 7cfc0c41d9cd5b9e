//! The boundary study's figure: onset lag and mean-speed difference against the box size, one
//! curve per boundary field and friction value.

use super::rows::{BoundaryRow, Field};
use crate::plot::{Curve, Dash, Labels, Mark, line_chart};
use anyhow::Result;
use plotters::style::BLACK;
use std::path::{Path, PathBuf};

/// Draws `boundary_onset.png` and `boundary_speed.png` into `dir`; returns the first.
pub fn draw(dir: &Path, rows: &[BoundaryRow]) -> Result<PathBuf> {
    let mut mus: Vec<f64> = rows.iter().map(|r| r.mu).collect();
    mus.dedup();
    let curves = |value: fn(&BoundaryRow) -> f64| -> Vec<Curve> {
        let mut out = Vec::new();
        for (i, &mu) in mus.iter().enumerate() {
            for (field, dash) in [(Field::Case, Dash::Solid), (Field::Exact, Dash::Dashed)] {
                let pts = rows
                    .iter()
                    .filter(|r| r.mu == mu && r.field == field)
                    .map(|r| (4.0 * f64::from(r.box_factor), value(r)))
                    .collect();
                out.push(Curve::nth(format!("{field:?} field, μ = {mu}"), pts, i, dash));
            }
        }
        out
    };
    let onset = dir.join("boundary_onset.png");
    line_chart(
        &onset,
        Labels {
            title: "FE onset minus shifted spectral onset against the FE box (width / a)",
            x: "FE box width / a [-] (height = width / 2)",
            y: "onset lag / T [-]",
        },
        &curves(|r| r.onset_lag_over_t),
        &[Mark::Horizontal(0.0, BLACK, "agreement".into())],
    )?;
    line_chart(
        &dir.join("boundary_speed.png"),
        Labels {
            title: "FE against spectral mean speed (1.2a–1.9a) against the FE box",
            x: "FE box width / a [-] (height = width / 2)",
            y: "(v_FE − v_SBI) / v_SBI [-]",
        },
        &curves(|r| r.mean_speed_difference),
        &[Mark::Horizontal(0.0, BLACK, "agreement".into())],
    )?;
    Ok(onset)
}
