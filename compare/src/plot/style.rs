//! What every chart shares: the bundled font, titles and axis labels, curve and mark styles, the
//! palette, colour scales, and drawing a curve with a legend sample in its own style.

use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::FontStyle;

/// Size of a chart [px].
pub const SIZE: (u32, u32) = (1000, 700);
/// Name the bundled font is registered under.
pub const FONT: &str = "sans-serif";

/// Registers the bundled font (DejaVu Sans through the `dejavu` crate) with plotters'
/// `ab_glyph` backend, so charts render on a machine with no system fonts (idempotent; cheap).
pub fn register_font() -> Result<()> {
    plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| anyhow!("the bundled DejaVu Sans font did not parse"))
}

/// A chart on a PNG with axes of coordinate types X and Y (linear or logarithmic).
pub type Chart<'a, 'b, X, Y> = ChartContext<'a, BitMapBackend<'b>, Cartesian2d<X, Y>>;

/// Tick label of a logarithmic axis: 1e-3, 0.01, 0.1, 1, 10, 1e3.
pub fn log_tick(v: &f64) -> String {
    if (1e-2..1e3).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:.0e}")
    }
}

/// The axes of every chart: labels with units, the bundled font, grid lines or not; a
/// logarithmic axis gets [`log_tick`] labels.
pub fn draw_axes<X, Y>(
    chart: &mut Chart<'_, '_, X, Y>,
    labels: Labels,
    grid: bool,
    log: (bool, bool),
) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut mesh = chart.configure_mesh();
    if !grid {
        mesh.disable_mesh();
    }
    if log.0 {
        mesh.x_label_formatter(&log_tick);
    }
    if log.1 {
        mesh.y_label_formatter(&log_tick);
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
    /// Solid, dashed or markers; the legend sample is drawn the same way.
    pub dash: Dash,
}

impl Curve {
    /// A curve in the i-th palette colour.
    pub fn nth(label: impl Into<String>, points: Vec<(f64, f64)>, i: usize, dash: Dash) -> Curve {
        Curve {
            label: label.into(),
            points,
            color: PALETTE[i % PALETTE.len()],
            dash,
        }
    }
}

/// A vertical or horizontal reference line, dashed (in the legend when labelled).
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

/// Colour scale of a map: value range and the colour bar label.
#[derive(Debug, Clone)]
pub struct Scale {
    /// Value mapped to the bottom of the colour map.
    pub min: f64,
    /// Value mapped to the top of the colour map.
    pub max: f64,
    /// Colour bar label with unit.
    pub label: String,
}

impl Scale {
    /// A scale from `min` to `max` labelled `label`.
    pub fn new(min: f64, max: f64, label: &str) -> Scale {
        Scale {
            min,
            max,
            label: label.to_string(),
        }
    }

    /// Position of `v` on the scale, clamped to [0, 1].
    pub fn fraction(&self, v: f64) -> f64 {
        ((v - self.min) / (self.max - self.min)).clamp(0.0, 1.0)
    }
}

/// Dash length and gap of dashed curves and their legend samples [px].
const DASH: (u32, u32) = (8, 5);

/// Draws `curves` on `chart`, each with a legend sample in its own style (solid, dashed or a
/// marker). Points that are not finite are skipped.
pub fn draw_curves<X, Y>(chart: &mut Chart<'_, '_, X, Y>, curves: &[Curve]) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for c in curves {
        let style = ShapeStyle::from(&c.color).stroke_width(2);
        let pts = c
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite());
        let color = c.color;
        let label = c.label.clone();
        match c.dash {
            Dash::Solid => {
                chart
                    .draw_series(LineSeries::new(pts, style))?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style));
            }
            Dash::Dashed => {
                chart
                    .draw_series(DashedLineSeries::new(pts, DASH.0, DASH.1, style))?
                    .label(label)
                    .legend(move |(x, y)| {
                        DashedPathElement::new(vec![(x, y), (x + 24, y)], DASH.0, DASH.1, style)
                    });
            }
            Dash::Markers => {
                chart
                    .draw_series(pts.map(|p| Circle::new(p, 3, color.filled())))?
                    .label(label)
                    .legend(move |(x, y)| Circle::new((x + 12, y), 3, color.filled()));
            }
        }
    }
    Ok(())
}

/// The legend box of every chart.
pub fn draw_legend<'a, 'b: 'a, X, Y>(
    chart: &mut Chart<'a, 'b, X, Y>,
    position: SeriesLabelPosition,
) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(position)
        .draw()?;
    Ok(())
}

/// Draws a vertical colour bar of `scale` with `colour` into `area`.
pub fn draw_colour_bar(
    area: &DrawingArea<BitMapBackend, Shift>,
    scale: &Scale,
    colour: impl Fn(f64) -> RGBColor,
) -> Result<()> {
    let mut bar = ChartBuilder::on(area)
        .margin_top(60)
        .margin_bottom(70)
        .margin_right(10)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..1.0, scale.min..scale.max)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(scale.label.as_str())
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .draw()?;
    let n = 100;
    let step = (scale.max - scale.min) / n as f64;
    bar.draw_series((0..n).map(|i| {
        let v = scale.min + (i as f64 + 0.5) * step;
        Rectangle::new(
            [
                (0.0, scale.min + i as f64 * step),
                (1.0, scale.min + (i + 1) as f64 * step),
            ],
            colour(v).filled(),
        )
    }))?;
    Ok(())
}
