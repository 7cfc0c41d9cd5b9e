//! A Freund case's figure: tip speed against crack length, both models and the theory.

use super::andrews::{AndrewsCase, FrontSpeedRow};
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

/// Draws an Andrews case's `path`: front speed over c_s against half-length over a_c for both
/// models, with c_R, c_s, √2 c_s and c_d; the theory is Andrews' transition half-length (a
/// vertical line, none above S = 1.77) and the supershear range (√2 c_s, c_d). Each model's
/// transition is marked where it was read (a point on √2 c_s).
pub fn draw_andrews(
    path: &Path,
    name: &str,
    case: &AndrewsCase,
    speeds: &[FrontSpeedRow],
    transitions: [Option<f64>; 2],
) -> Result<PathBuf> {
    let points = |v: fn(&FrontSpeedRow) -> f64| -> Vec<(f64, f64)> {
        speeds
            .iter()
            .filter(|s| v(s).is_finite())
            .map(|s| (s.half_length / case.ac, v(s) / case.cs))
            .collect()
    };
    let title = format!("{name}: front speed against half-length (S = {:.2})", case.s);
    let marks = [
        Mark::Horizontal(case.cr / case.cs, BLACK, "c_R".into()),
        Mark::Horizontal(std::f64::consts::SQRT_2, BLACK, "sqrt(2) c_s".into()),
        Mark::Horizontal(case.cd / case.cs, BLACK, "c_d".into()),
    ];
    let mut curves = vec![
        Curve::nth("FE", points(|s| s.fem_speed), 0, Dash::Solid),
        Curve::nth("spectral", points(|s| s.spectral_speed), 1, Dash::Solid),
    ];
    if let Some(a) = case.andrews_distance() {
        let x = a / case.ac;
        curves.push(Curve::nth(
            "Andrews' fit 9.8 (1.77 - S)^-3 L_c",
            vec![(x, 0.0), (x, case.cd / case.cs)],
            2,
            Dash::Dashed,
        ));
    }
    for (k, (label, tr)) in ["FE transition", "spectral transition"]
        .iter()
        .zip(transitions)
        .enumerate()
    {
        if let Some(a) = tr {
            let x = a / case.ac;
            let point = vec![(x, std::f64::consts::SQRT_2)];
            curves.push(Curve::nth(label.to_string(), point, k, Dash::Markers));
        }
    }
    line_chart(
        path,
        Labels {
            title: &title,
            x: "front half-length a / a_c [-] (a_c: Griffith half-length)",
            y: "front speed / c_s [-]",
        },
        &curves,
        &marks,
    )?;
    Ok(path.to_path_buf())
}
