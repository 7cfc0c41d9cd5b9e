//! Space-time diagrams (paper Figures 5b, 6a, 6b): a field over position and time, drawn cell by
//! cell with plotters' viridis colour map and a colour bar.

use super::file::figure;
use super::style::{
    Curve, FONT, Labels, SIZE, Scale, draw_axes, draw_colour_bar, draw_curves, draw_legend, register_font,
};
use anyhow::{Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

/// A space-time field sampled on a regular grid: `values[i_t][i_x]`, NaN where undefined.
#[derive(Debug, Clone)]
pub struct Field {
    /// Cell-centre positions along x (axis units), increasing.
    pub x: Vec<f64>,
    /// Cell-centre times (axis units), increasing.
    pub t: Vec<f64>,
    /// Values per time row, one per x.
    pub values: Vec<Vec<f64>>,
}

impl Field {
    /// Builds a field from (t, x, value) samples: one row per distinct time (the samples of one
    /// time are contiguous), columns at the x positions of the first row; a sample goes to the
    /// column nearest its x. Axis units come from `to_x` and `to_t`.
    pub fn from_samples(
        samples: impl Iterator<Item = (f64, f64, f64)>,
        to_x: impl Fn(f64) -> f64,
        to_t: impl Fn(f64) -> f64,
    ) -> Field {
        let mut t_rows: Vec<f64> = Vec::new();
        let mut rows: Vec<Vec<(f64, f64)>> = Vec::new();
        for (t, x, v) in samples {
            if t_rows.last() != Some(&t) {
                t_rows.push(t);
                rows.push(Vec::new());
            }
            rows.last_mut()
                .expect("invariant: a row was just pushed")
                .push((x, v));
        }
        let mut xs: Vec<f64> = rows
            .first()
            .map(|r| r.iter().map(|p| p.0).collect())
            .unwrap_or_default();
        xs.sort_by(f64::total_cmp);
        xs.dedup();
        let values = rows
            .iter()
            .map(|row| {
                let mut out = vec![f64::NAN; xs.len()];
                for &(x, v) in row {
                    let j = xs.partition_point(|&c| c < x);
                    let j = match (j.checked_sub(1), xs.get(j)) {
                        (Some(i), Some(&c)) if (x - xs[i]).abs() < (c - x).abs() => i,
                        (Some(i), None) => i,
                        _ => j,
                    };
                    if let Some(o) = out.get_mut(j) {
                        *o = v;
                    }
                }
                out
            })
            .collect();
        Field {
            x: xs.into_iter().map(to_x).collect(),
            t: t_rows.into_iter().map(to_t).collect(),
            values,
        }
    }
}

fn viridis(v: f64, s: &Scale) -> RGBColor {
    if v.is_finite() {
        ViridisRGB::get_color(s.fraction(v))
    } else {
        RGBColor(235, 235, 235)
    }
}

/// Draws a space-time diagram (x horizontal, t vertical) with a colour bar to `path` (PNG), and
/// `lines` over it (guide lines such as the stick-to-slip boundary of Figure 6b) with a legend.
pub fn space_time(path: &Path, labels: Labels, field: &Field, scale: &Scale, lines: &[Curve]) -> Result<()> {
    let (nx, nt) = (field.x.len(), field.t.len());
    if nx < 2 || nt < 2 {
        return Err(anyhow!(
            "{}: a space-time diagram needs at least 2 × 2 samples",
            path.display()
        ));
    }
    register_font()?;
    figure(path, SIZE, |root| {
        root.fill(&WHITE)?;
        let (main, bar) = root.split_horizontally(SIZE.0 - 130);
        let (xe, te) = (cell_edges(&field.x), cell_edges(&field.t));
        let (x0, x1) = (xe[0].0, xe[nx - 1].1);
        let (t0, t1) = (te[0].0, te[nt - 1].1);
        let mut chart = ChartBuilder::on(&main)
            .caption(labels.title, (FONT, 26))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(75)
            .build_cartesian_2d(x0..x1, t0..t1)?;
        draw_axes(&mut chart, labels, false, (false, false))?;
        let cells = field.values.iter().enumerate().flat_map(|(it, row)| {
            let (te, xe) = (&te, &xe);
            row.iter().enumerate().map(move |(ix, &v)| {
                Rectangle::new(
                    [(xe[ix].0, te[it].0), (xe[ix].1, te[it].1)],
                    viridis(v, scale).filled(),
                )
            })
        });
        chart.draw_series(cells)?;
        if !lines.is_empty() {
            draw_curves(&mut chart, lines)?;
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        draw_colour_bar(&bar, scale, |v| viridis(v, scale))?;
        Ok(())
    })
}

/// Cell extents around sample positions `v` (increasing): each cell reaches halfway to its
/// neighbours, but never more than 0.75 × the median spacing on either side, so a gap in the
/// samples (the pre-crack, where no interface point exists) stays empty instead of being
/// covered by the cells at its edges.
fn cell_edges(v: &[f64]) -> Vec<(f64, f64)> {
    let mut d: Vec<f64> = v.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let cap = 0.75 * d.get(d.len() / 2).copied().unwrap_or(1.0);
    let n = v.len();
    (0..n)
        .map(|i| {
            let left = 0.5 * if i > 0 { v[i] - v[i - 1] } else { v[1] - v[0] };
            let right = 0.5
                * if i + 1 < n {
                    v[i + 1] - v[i]
                } else {
                    v[i] - v[i - 1]
                };
            (v[i] - left.min(cap), v[i] + right.min(cap))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn space_time_renders_and_rejects_degenerate_fields() {
        let dir = std::env::temp_dir().join(format!("compare-st-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("st.png");
        let f = Field {
            x: (0..20).map(|i| i as f64).collect(),
            t: (0..10).map(|i| i as f64).collect(),
            values: (0..10)
                .map(|i| (0..20).map(|j| (i * j) as f64).collect())
                .collect(),
        };
        let s = Scale::new(0.0, 171.0, "v [-]");
        let labels = Labels {
            title: "st",
            x: "x [m]",
            y: "t [s]",
        };
        space_time(&p, labels, &f, &s, &[]).unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
        let g = Field {
            x: vec![0.0],
            t: vec![0.0],
            values: vec![vec![1.0]],
        };
        assert!(space_time(&p, labels, &g, &s, &[]).is_err());
    }

    #[test]
    fn cells_touch_their_neighbours_but_do_not_cover_a_gap() {
        let e = cell_edges(&[0.0, 1.0, 2.0, 10.0, 11.0]);
        assert_eq!(e[0], (-0.5, 0.5));
        assert_eq!(e[1], (0.5, 1.5));
        assert_eq!(e[2], (1.5, 2.75));
        assert_eq!(e[3], (9.25, 10.5));
        assert_eq!(e[4], (10.5, 11.5));
    }

    #[test]
    fn samples_of_one_time_form_a_row_and_land_in_the_nearest_column() {
        let samples = [
            (0.0, 1.0, 10.0),
            (0.0, 2.0, 20.0),
            (1.0, 2.1, 21.0),
            (1.0, 0.9, 9.0),
        ];
        let f = Field::from_samples(samples.into_iter(), |x| 10.0 * x, |t| t / 2.0);
        assert_eq!(f.x, [10.0, 20.0]);
        assert_eq!(f.t, [0.0, 0.5]);
        assert_eq!(f.values, [[10.0, 20.0], [9.0, 21.0]]);
    }
}
