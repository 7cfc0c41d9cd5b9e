//! Paper Figures 10 and 11 from the snapshot records of each model: the σ_yy map around the
//! interface with stress contours (here), and σ_yy along the upper face of the right weak branch
//! with the true contact zone shaded ([`super::contact`]). Each figure's plotted data also go to
//! a CSV.

use super::contact::contact_profile;
use super::setup::{ModelRun, Setup, Snapshot};
use crate::output::write_rows;
use crate::plot::{self, CentroidGrid, ContourSet, Curve, Dash, Labels, Map, PALETTE, Scale};
use anyhow::Result;
use plotters::style::{BLACK, RGBColor};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Contour levels of the maps, ± each, in units of σ_c of the strong interface [-].
pub const CONTOUR_LEVELS: [f64; 3] = [0.25, 0.5, 1.0];

/// The colour scale of the maps is clipped at this quantile of |σ_yy|/σ_c^s over all models [-],
/// so that the stress concentrations at the tips do not wash the rest of the map out.
pub const SCALE_QUANTILE: f64 = 0.99;

/// Index of the snapshot taken nearest `t` [s] (`None`: the run took none).
pub fn snapshot_index(out: &fem::RunOutput, t: f64) -> Option<usize> {
    (0..out.snapshot_times.len()).min_by(|&i, &j| {
        (out.snapshot_times[i] - t)
            .abs()
            .total_cmp(&(out.snapshot_times[j] - t).abs())
    })
}

/// One element of a map (`fig10_sigma_y_<model>.csv`).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MapRow {
    /// Reference centroid x [m].
    pub x: f64,
    /// Reference centroid y [m].
    pub y: f64,
    /// (x − x_c)/a [-].
    pub x_over_a: f64,
    /// y/a [-].
    pub y_over_a: f64,
    /// σ_yy/σ_c^s [-].
    pub syy_over_sigma_c: f64,
}

/// One contour segment of a map (`fig10_contours_<model>.csv`), in units of a.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ContourRow {
    /// Level σ_yy/σ_c^s [-].
    pub level: f64,
    /// Start (x − x_c)/a [-].
    pub x0_over_a: f64,
    /// Start y/a [-].
    pub y0_over_a: f64,
    /// End (x − x_c)/a [-].
    pub x1_over_a: f64,
    /// End y/a [-].
    pub y1_over_a: f64,
}

/// The map rows of snapshot `k`, in the records' (row-major) order.
pub fn map_rows(setup: &Setup, out: &fem::RunOutput, k: usize) -> Vec<MapRow> {
    out.fields
        .iter()
        .filter(|f| f.snapshot == k)
        .map(|f| MapRow {
            x: f.x,
            y: f.y,
            x_over_a: setup.x_over_a(f.x),
            y_over_a: f.y / setup.half_length,
            syy_over_sigma_c: f.syy / setup.sigma_c_strong,
        })
        .collect()
}

/// The `q`-quantile of |v| (nearest rank; 1 when there is no non-zero finite value).
pub fn robust_bound(values: impl Iterator<Item = f64>, q: f64) -> f64 {
    let mut a: Vec<f64> = values.filter(|v| v.is_finite()).map(f64::abs).collect();
    a.sort_by(f64::total_cmp);
    let b = a
        .get(((q * a.len() as f64).ceil() as usize).saturating_sub(1))
        .copied()
        .unwrap_or(0.0);
    if b > 0.0 { b } else { 1.0 }
}

/// Draws Figures 10 and 11 for every run that took a snapshot; returns the files written.
pub fn snapshot_figures(dir: &Path, setup: &Setup, runs: &[ModelRun]) -> Result<Vec<PathBuf>> {
    let snaps: Vec<(&ModelRun, usize)> = runs
        .iter()
        .filter_map(|r| snapshot_index(&r.out, setup.snapshot_time).map(|k| (r, k)))
        .collect();
    let rows: Vec<Vec<MapRow>> = snaps.iter().map(|(r, k)| map_rows(setup, &r.out, *k)).collect();
    let bound = robust_bound(rows.iter().flatten().map(|m| m.syy_over_sigma_c), SCALE_QUANTILE);
    let mut files = Vec::new();
    for (&(run, k), rows) in snaps.iter().zip(&rows) {
        let snap = Snapshot {
            run,
            k,
            t_over_t: run.out.snapshot_times[k] / setup.duration,
        };
        files.extend(stress_map(dir, setup, &snap, rows, bound)?);
        files.extend(contact_profile(dir, setup, &snap)?);
    }
    Ok(files)
}

/// The iso-lines of `grid` at ±[`CONTOUR_LEVELS`].
fn contour_rows(grid: &CentroidGrid) -> Vec<ContourRow> {
    let mut rows = Vec::new();
    for level in CONTOUR_LEVELS.iter().flat_map(|l| [-l, *l]) {
        rows.extend(grid.contour(level).into_iter().map(|(a, b)| ContourRow {
            level,
            x0_over_a: a.0,
            y0_over_a: a.1,
            x1_over_a: b.0,
            y1_over_a: b.1,
        }));
    }
    rows
}

fn interface_lines(setup: &Setup, snap: &Snapshot, x_range: (f64, f64)) -> Vec<Curve> {
    let inside = |x: f64| x >= x_range.0 && x <= x_range.1;
    let row = |from: f64, to: f64| -> Vec<(f64, f64)> {
        setup
            .interface
            .iter()
            .map(|p| (setup.x_over_a(p[0]), p[1] / setup.half_length))
            .filter(|p| p.0 >= from && p.0 <= to && inside(p.0))
            .collect()
    };
    let mut weak: Vec<(f64, f64)> = snap
        .run
        .out
        .profiles
        .iter()
        .filter(|p| p.snapshot == snap.k && p.x >= setup.weak_right[0] && p.x <= setup.weak_right[1])
        .map(|p| (setup.x_over_a(p.x), p.y / setup.half_length))
        .filter(|p| inside(p.0))
        .collect();
    weak.sort_by(|a, b| a.0.total_cmp(&b.0));
    let line = |label: &str, points, color, dash| Curve {
        label: label.to_string(),
        points,
        color,
        dash,
    };
    let junction = setup.x_over_a(setup.weak_right[1]);
    vec![
        line("pre-crack", row(-1.0, 1.0), RGBColor(70, 70, 70), Dash::Dashed),
        line(
            "weak interface (+ face, reference)",
            weak,
            PALETTE[2],
            Dash::Solid,
        ),
        line(
            "strong interface",
            row(junction, f64::MAX),
            RGBColor(120, 0, 150),
            Dash::Solid,
        ),
    ]
}

fn stress_map(
    dir: &Path,
    setup: &Setup,
    snap: &Snapshot,
    rows: &[MapRow],
    bound: f64,
) -> Result<Vec<PathBuf>> {
    let samples: Vec<(f64, f64, f64)> = rows
        .iter()
        .map(|r| (r.x_over_a, r.y_over_a, r.syy_over_sigma_c))
        .collect();
    let grid = CentroidGrid::from_row_major(&samples);
    let contour_rows = contour_rows(&grid);
    let cells = grid.cells();
    let x_range = cells
        .iter()
        .fold((f64::MAX, f64::MIN), |m, c| (m.0.min(c.x.0), m.1.max(c.x.1)));
    let levels: Vec<String> = CONTOUR_LEVELS.iter().map(|l| format!("±{l}")).collect();
    let map = Map {
        cells,
        contours: vec![ContourSet {
            label: Some(format!("σyy/σc,strong = {}", levels.join(", "))),
            segments: contour_rows
                .iter()
                .map(|c| ((c.x0_over_a, c.y0_over_a), (c.x1_over_a, c.y1_over_a)))
                .collect(),
            color: BLACK,
        }],
        lines: interface_lines(setup, snap, x_range),
    };
    let (m, t_over_t) = (&snap.run.model, snap.t_over_t);
    let png = dir.join(format!("fig10_sigma_y_{m}.png"));
    let title = format!(
        "σyy/σc,strong, {m} model, t/T = {t_over_t:.3} (colours clipped at ±{bound:.2}: \
         {:.0}th percentile of |σyy|/σc,strong, all models)",
        100.0 * SCALE_QUANTILE
    );
    let labels = Labels {
        title: &title,
        x: "(x − x_c)/a [-]",
        y: "y/a [-]",
    };
    let scale = Scale::new(-bound, bound, "σyy/σc,strong [-]");
    plot::map_with_contours(&png, labels, &map, &scale)?;
    Ok(vec![
        png,
        write_rows(&dir.join(format!("fig10_sigma_y_{m}.csv")), rows)?,
        write_rows(&dir.join(format!("fig10_contours_{m}.csv")), &contour_rows)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_bound_is_a_quantile_of_the_magnitudes() {
        let v = (1..=100).map(|i| if i % 2 == 0 { i as f64 } else { -(i as f64) });
        assert_eq!(robust_bound(v, 0.99), 99.0);
        assert_eq!(robust_bound([0.0, f64::NAN].into_iter(), 0.99), 1.0);
    }

    #[test]
    fn snapshot_figures_render_and_write_their_data() {
        let setup = crate::sinusoid::setup::tests::setup();
        let (a, t) = (setup.half_length, setup.snapshot_time);
        let sc = setup.sigma_c_strong;
        let fields = (0..6)
            .flat_map(|r| {
                (0..24).map(move |c| fem::FieldRecord {
                    snapshot: 0,
                    t,
                    x: a * (c as f64 + 0.5) / 8.0,
                    y: a * (r as f64 - 2.5) / 6.0,
                    sxx: 0.0,
                    syy: sc * (c as f64 / 12.0 - 1.0),
                    sxy: 0.0,
                })
            })
            .collect();
        let profiles = (0..=30)
            .map(|i| fem::ProfileRecord {
                snapshot: 0,
                t,
                x: a * (1.0 + 0.05 * i as f64),
                y: 0.0,
                syy: -0.2 * sc,
                crack_face: i < 25,
                gap: if i % 4 == 0 { -1e-6 } else { 1e-6 },
                compressive_traction: if i % 3 == 0 { 0.2 * sc } else { 0.0 },
            })
            .collect();
        let run = ModelRun {
            model: "standard".into(),
            out: fem::RunOutput {
                fields,
                profiles,
                snapshot_times: vec![t],
                ..fem::RunOutput::default()
            },
            wall_s: 0.0,
            failure: None,
        };
        let dir = std::env::temp_dir().join(format!("compare-snapshot-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let files = snapshot_figures(&dir, &setup, &[run]).unwrap();
        assert_eq!(files.len(), 6);
        let text = std::fs::read_to_string(dir.join("fig10_contours_standard.csv")).unwrap();
        assert!(text.starts_with("level,x0_over_a,y0_over_a,x1_over_a,y1_over_a\n"));
        // σ_yy/σ_c = c/12 − 1 per column c at x/a = (c + ½)/8: the level −0.25 lies at c = 9,
        // x/a = 1.1875, on every one of the 5 rows of cells
        let at = |level: &str| text.lines().filter(move |l| l.starts_with(level)).count();
        assert_eq!(at("-0.25,"), 5);
        assert!(
            text.lines()
                .filter(|l| l.starts_with("-0.25,"))
                .all(|l| l.contains(",1.1875,"))
        );
        let text = std::fs::read_to_string(dir.join("fig11_sigma_y_contact_standard.csv")).unwrap();
        assert!(
            text.starts_with(
                "x,x_over_a,syy_over_sigma_c,gap,in_contact,compressive_traction_over_sigma_c\n"
            )
        );
        // crack-face nodes of the right weak branch only: x ≤ 2.5a and i < 25
        assert_eq!(text.lines().count(), 1 + 25);
        let zones = std::fs::read_to_string(dir.join("fig11_contact_zones_standard.csv")).unwrap();
        assert_eq!(zones.lines().count(), 1 + 7, "nodes 0, 4, ..., 24 in contact");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn snapshot_nearest_the_requested_time() {
        let out = fem::RunOutput {
            snapshot_times: vec![0.01, 0.0303, 0.05],
            ..fem::RunOutput::default()
        };
        assert_eq!(snapshot_index(&out, 0.03), Some(1));
        assert_eq!(snapshot_index(&fem::RunOutput::default(), 0.03), None);
    }
}
