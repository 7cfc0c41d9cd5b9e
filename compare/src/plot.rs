//! PNG plots with plotters and a bundled font (DejaVu Sans through the `dejavu` crate and
//! plotters' `ab_glyph` backend), so they render on a machine with no system fonts.
//! Draws what it is given; computes nothing.

use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;

mod lines;
mod map;

pub use lines::{Shading, line_chart, line_chart_shaded};
pub use map::{ContourSet, Map, diverging, map_with_contours};

const SIZE: (u32, u32) = (1000, 700);
const FONT: &str = "sans-serif";

/// Registers the bundled font with plotters (idempotent; cheap).
fn register_font() -> Result<()> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| anyhow!("the bundled DejaVu Sans font did not parse"))
}

/// The axes of every chart: labels with units, the bundled font, grid lines or not.
fn draw_axes(chart: &mut lines::Chart<'_, '_>, labels: Labels, grid: bool) -> Result<()> {
    let mut mesh = chart.configure_mesh();
    if !grid {
        mesh.disable_mesh();
    }
    mesh.x_desc(labels.x)
        .y_desc(labels.y)
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .draw()?;
    Ok(())
}

/// Line style of a curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dash {
    /// Solid line.
    Solid,
    /// Dashed line.
    Dashed,
    /// A filled circle at each point, no line.
    Markers,
}

/// One curve of a line chart.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Legend label.
    pub label: String,
    /// (x, y) points in axis units.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Solid or dashed.
    pub dash: Dash,
}

impl Curve {
    /// A curve in the i-th palette colour.
    pub fn nth(label: String, points: Vec<(f64, f64)>, i: usize, dash: Dash) -> Curve {
        Curve {
            label,
            points,
            color: PALETTE[i % PALETTE.len()],
            dash,
        }
    }
}

/// A vertical or horizontal reference line (not in the legend unless labelled).
#[derive(Debug, Clone)]
pub enum Mark {
    /// x = value.
    Vertical(f64, RGBColor),
    /// y = value, with a legend label.
    Horizontal(f64, RGBColor, String),
}

/// Titles and axis labels (with units) of a chart.
#[derive(Debug, Clone, Copy)]
pub struct Labels<'a> {
    /// Chart title.
    pub title: &'a str,
    /// x-axis label with unit.
    pub x: &'a str,
    /// y-axis label with unit.
    pub y: &'a str,
}

/// Palette for curves (colour-blind friendly order).
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(86, 180, 233),
    RGBColor(230, 159, 0),
];

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

/// Colour scale of a space-time diagram: value range and the colorbar label.
#[derive(Debug, Clone)]
pub struct Scale {
    /// Value mapped to the bottom of the colour map.
    pub min: f64,
    /// Value mapped to the top of the colour map.
    pub max: f64,
    /// Colorbar label with unit.
    pub label: String,
}

fn colour(v: f64, s: &Scale) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(235, 235, 235);
    }
    let f = ((v - s.min) / (s.max - s.min)).clamp(0.0, 1.0);
    ViridisRGB::get_color(f)
}

/// Draws a space-time diagram (x horizontal, t vertical) with a colour bar to `path` (PNG).
pub fn space_time(path: &Path, labels: Labels, field: &Field, scale: &Scale) -> Result<()> {
    let (nx, nt) = (field.x.len(), field.t.len());
    if nx < 2 || nt < 2 {
        return Err(anyhow!(
            "{}: a space-time diagram needs at least 2 × 2 samples",
            path.display()
        ));
    }
    register_font()?;
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
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
    draw_axes(&mut chart, labels, false)?;
    let cells = field.values.iter().enumerate().flat_map(|(it, row)| {
        let (te, xe) = (&te, &xe);
        row.iter().enumerate().map(move |(ix, &v)| {
            Rectangle::new(
                [(xe[ix].0, te[it].0), (xe[ix].1, te[it].1)],
                colour(v, scale).filled(),
            )
        })
    });
    chart.draw_series(cells)?;
    draw_colour_bar(&bar, scale, colour)?;
    root.present()
        .with_context(|| format!("writing {}", path.display()))
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

fn draw_colour_bar(
    area: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    s: &Scale,
    colour: fn(f64, &Scale) -> RGBColor,
) -> Result<()> {
    let mut bar = ChartBuilder::on(area)
        .margin_top(60)
        .margin_bottom(70)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, s.min..s.max)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(s.label.as_str())
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()?;
    let n = 100;
    let step = (s.max - s.min) / n as f64;
    bar.draw_series((0..n).map(|i| {
        let v = s.min + (i as f64 + 0.5) * step;
        Rectangle::new(
            [
                (0.0, s.min + i as f64 * step),
                (1.0, s.min + (i + 1) as f64 * step),
            ],
            colour(v, s).filled(),
        )
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("compare-plot-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn line_chart_renders_with_the_bundled_font() {
        let p = tmp("line.png");
        let c = Curve {
            label: "test".into(),
            points: (0..50).map(|i| (i as f64, (i as f64 * 0.1).sin())).collect(),
            color: PALETTE[0],
            dash: Dash::Dashed,
        };
        let marks = [
            Mark::Vertical(10.0, BLACK),
            Mark::Horizontal(0.5, RED, "ref".into()),
        ];
        line_chart(
            &p,
            Labels {
                title: "t",
                x: "x [m]",
                y: "y [-]",
            },
            &[c],
            &marks,
        )
        .unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
    }

    #[test]
    fn space_time_renders_and_rejects_degenerate_fields() {
        let p = tmp("st.png");
        let f = Field {
            x: (0..20).map(|i| i as f64).collect(),
            t: (0..10).map(|i| i as f64).collect(),
            values: (0..10)
                .map(|i| (0..20).map(|j| (i * j) as f64).collect())
                .collect(),
        };
        let s = Scale {
            min: 0.0,
            max: 171.0,
            label: "v [-]".into(),
        };
        space_time(
            &p,
            Labels {
                title: "st",
                x: "x [m]",
                y: "t [s]",
            },
            &f,
            &s,
        )
        .unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
        let g = Field {
            x: vec![0.0],
            t: vec![0.0],
            values: vec![vec![1.0]],
        };
        assert!(
            space_time(
                &p,
                Labels {
                    title: "st",
                    x: "x",
                    y: "t"
                },
                &g,
                &s
            )
            .is_err()
        );
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
}
