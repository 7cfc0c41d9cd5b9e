//! The tip figures of the comparison (paper Figures 7a–b, 8a–b), built from both models' tip
//! histories and drawn by `plot`. File names are listed in docs/outputs.md.

use super::metrics::MuRuns;
use crate::plot::{self, Curve, Dash, Labels, Mark, PALETTE};
use crate::series::{Series, onset};
use crate::study::Case;
use anyhow::Result;
use plotters::style::BLACK;
use std::path::{Path, PathBuf};

/// Least-squares half-window for tip speeds [s]: ±1e-4 s, in which a crack at c_R runs
/// ~14 elements of 1 mm (a tip moves one facet at a time, so a slope needs a few h/c_R at least).
const SPEED_HALF_WINDOW_S: f64 = 1e-4;

/// Tip curves are drawn up to this half-length [a]: the FE domain ends at 2a, and the
/// spectral crack, in its 30a periodic domain, runs on far beyond what the FE model can show.
const PLOT_MAX_HALF_LENGTH: f64 = 2.0;

fn normalised(s: &Series, case: &Case, t_origin: f64) -> Vec<(f64, f64)> {
    s.t.iter()
        .zip(&s.y)
        .map(|(t, y)| ((t - t_origin) / case.duration, y / case.half_length))
        .filter(|p| p.1 <= PLOT_MAX_HALF_LENGTH)
        .collect()
}

/// Which alignment a tip-position figure shows.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Alignment {
    /// As computed (Figure 7a), with the a/c_d marks.
    Raw,
    /// Spectral shifted by a/c_d (Figure 7b).
    Shifted,
    /// Each model from its own onset (Figure 8a).
    CommonOrigin,
}

fn tip_figure(path: &Path, case: &Case, runs: &[MuRuns], how: Alignment) -> Result<()> {
    let mut curves = Vec::new();
    let mut marks = Vec::new();
    for (i, r) in runs.iter().enumerate() {
        let f = Series::half_length(&r.fem);
        let s = Series::half_length(&r.spectral);
        let (of, os) = match how {
            Alignment::Raw => (0.0, 0.0),
            Alignment::Shifted => (0.0, -case.shift()),
            Alignment::CommonOrigin => (
                onset(&f, case.half_length).unwrap_or(f64::NAN),
                onset(&s, case.half_length).unwrap_or(f64::NAN),
            ),
        };
        if how == Alignment::Raw
            && let Some(ts) = onset(&s, case.half_length)
        {
            marks.push(Mark::Vertical(
                (ts + case.shift()) / case.duration,
                PALETTE[i % PALETTE.len()],
            ));
        }
        curves.push(Curve::nth(
            format!("FE, μ = {}", r.mu),
            normalised(&f, case, of),
            i,
            Dash::Solid,
        ));
        curves.push(Curve::nth(
            format!("spectral, μ = {}", r.mu),
            normalised(&s, case, os),
            i,
            Dash::Dashed,
        ));
    }
    let (title, x) = match how {
        Alignment::Raw => (
            "Crack-tip position (dashed verticals: spectral onset + a/c_d)",
            "t/T [-]",
        ),
        Alignment::Shifted => ("Crack-tip position, spectral shifted by a/c_d", "t/T [-]"),
        Alignment::CommonOrigin => (
            "Crack-tip position from a common origin (onset)",
            "(t − t_onset)/T [-]",
        ),
    };
    let labels = Labels {
        title,
        x,
        y: "crack half-length ℓ/a [-]",
    };
    plot::line_chart(path, labels, &curves, &marks)
}

fn velocity_figure(path: &Path, case: &Case, runs: &[MuRuns]) -> Result<()> {
    let mut curves = Vec::new();
    for (i, r) in runs.iter().enumerate() {
        for (name, rows, shift, dash) in [
            ("FE", &r.fem, 0.0, Dash::Solid),
            ("spectral", &r.spectral, case.shift(), Dash::Dashed),
        ] {
            let l = Series::half_length(rows);
            let v = l.slope(SPEED_HALF_WINDOW_S);
            let pts =
                v.t.iter()
                    .zip(&v.y)
                    .map(|(t, v)| ((t + shift) / case.duration, *v))
                    .collect();
            curves.push(Curve::nth(format!("{name}, μ = {}", r.mu), pts, i, dash));
        }
    }
    let marks = [Mark::Horizontal(
        case.cr,
        BLACK,
        format!("c_R = {:.1} m/s", case.cr),
    )];
    let labels = Labels {
        title: "Crack-tip speed (spectral shifted by a/c_d)",
        x: "t/T [-]",
        y: "tip speed dℓ/dt [m/s]",
    };
    plot::line_chart(path, labels, &curves, &marks)
}

/// Draws Figures 7a, 7b, 8a, 8b into `dir`; returns the files written.
pub fn tip_figures(dir: &Path, case: &Case, runs: &[MuRuns]) -> Result<Vec<PathBuf>> {
    let files = [
        ("fig7a_tip_position.png", Alignment::Raw),
        ("fig7b_tip_position_shifted.png", Alignment::Shifted),
        ("fig8a_tip_position_common_origin.png", Alignment::CommonOrigin),
    ];
    let mut written = Vec::new();
    for (name, how) in files {
        let p = dir.join(name);
        tip_figure(&p, case, runs, how)?;
        written.push(p);
    }
    let p = dir.join("fig8b_tip_velocity.png");
    velocity_figure(&p, case, runs)?;
    written.push(p);
    Ok(written)
}
