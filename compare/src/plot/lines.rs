//! Line charts: curves (solid, dashed or markers), reference marks and shaded x-intervals.

use super::{Curve, Dash, FONT, Labels, Mark, SIZE, draw_axes, register_font};
use anyhow::{Context, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::path::Path;

/// Shaded x-intervals spanning the chart's height, with one legend entry.
#[derive(Debug, Clone)]
pub struct Shading {
    /// Legend label.
    pub label: String,
    /// (x_start, x_end) intervals in axis units.
    pub intervals: Vec<(f64, f64)>,
    /// Fill colour (drawn under the curves; choose a light one).
    pub color: RGBColor,
}

fn bounds(curves: &[Curve], marks: &[Mark], shading: Option<&Shading>) -> ((f64, f64), (f64, f64)) {
    let pts = curves
        .iter()
        .flat_map(|c| c.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    for m in marks {
        match m {
            Mark::Vertical(x, _) => (x0, x1) = (x0.min(*x), x1.max(*x)),
            Mark::Horizontal(y, _, _) => (y0, y1) = (y0.min(*y), y1.max(*y)),
        }
    }
    for &(a, b) in shading.map_or(&[][..], |s| &s.intervals[..]) {
        (x0, x1) = (x0.min(a), x1.max(b));
    }
    if x0 > x1 || y0 > y1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let pad = |a: f64, b: f64| {
        let d = if b > a {
            0.04 * (b - a)
        } else {
            0.5 * a.abs().max(1e-12)
        };
        (a - d, b + d)
    };
    (pad(x0, x1), pad(y0, y1))
}

/// Draws a line chart with a legend to `path` (PNG).
pub fn line_chart(path: &Path, labels: Labels, curves: &[Curve], marks: &[Mark]) -> Result<()> {
    line_chart_shaded(path, labels, curves, marks, None)
}

pub(super) type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws a line chart with a legend to `path` (PNG), with `shading` (if any) under the curves.
pub fn line_chart_shaded(
    path: &Path,
    labels: Labels,
    curves: &[Curve],
    marks: &[Mark],
    shading: Option<&Shading>,
) -> Result<()> {
    register_font()?;
    let ((x0, x1), (y0, y1)) = bounds(curves, marks, shading);
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(labels.title, (FONT, 26))
        .margin(15)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    draw_axes(&mut chart, labels, true)?;
    if let Some(s) = shading {
        let color = s.color;
        let rects = s
            .intervals
            .iter()
            .map(|&(a, b)| Rectangle::new([(a, y0), (b, y1)], color.filled()));
        chart
            .draw_series(rects)?
            .label(s.label.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], color.filled()));
    }
    draw_curves(&mut chart, curves)?;
    draw_marks(&mut chart, marks, (x0, x1), (y0, y1))?;
    chart
        .configure_series_labels()
        .label_font((FONT, 16))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperLeft)
        .draw()?;
    root.present()
        .with_context(|| format!("writing {}", path.display()))
}

pub(super) fn draw_curves(chart: &mut Chart, curves: &[Curve]) -> Result<()> {
    for c in curves {
        let style = ShapeStyle::from(&c.color).stroke_width(2);
        let pts = c
            .points
            .iter()
            .copied()
            .filter(|p| p.0.is_finite() && p.1.is_finite());
        let color = c.color;
        let anno = match c.dash {
            Dash::Solid => chart.draw_series(LineSeries::new(pts, style))?,
            Dash::Dashed => chart.draw_series(DashedLineSeries::new(pts, 8, 5, style))?,
            Dash::Markers => {
                chart
                    .draw_series(pts.map(|p| Circle::new(p, 3, color.filled())))?
                    .label(c.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
                continue;
            }
        };
        anno.label(c.label.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    Ok(())
}

fn draw_marks(chart: &mut Chart, marks: &[Mark], (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> Result<()> {
    for m in marks {
        match m {
            Mark::Vertical(x, color) => {
                let pts = vec![(*x, y0), (*x, y1)];
                chart.draw_series(DashedLineSeries::new(pts, 4, 4, color.stroke_width(1)))?;
            }
            Mark::Horizontal(y, color, label) => {
                let color = *color;
                let pts = vec![(x0, *y), (x1, *y)];
                chart
                    .draw_series(DashedLineSeries::new(pts, 4, 4, color.stroke_width(1)))?
                    .label(label.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1)));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::PALETTE;
    use super::*;

    #[test]
    fn shaded_chart_with_markers_renders_and_widens_to_the_shading() {
        let dir = std::env::temp_dir().join(format!("compare-lines-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("shaded.png");
        let line = Curve {
            label: "line".into(),
            points: (0..40)
                .map(|i| (i as f64 * 0.1, (i as f64 * 0.2).cos()))
                .collect(),
            color: PALETTE[0],
            dash: Dash::Solid,
        };
        let dots = Curve {
            label: "markers".into(),
            points: vec![(0.5, -0.5), (1.0, -0.25)],
            color: PALETTE[1],
            dash: Dash::Markers,
        };
        let s = Shading {
            label: "band".into(),
            intervals: vec![(0.2, 0.7), (3.5, 4.5)],
            color: RGBColor(220, 220, 220),
        };
        let labels = Labels {
            title: "shaded",
            x: "x [m]",
            y: "y [-]",
        };
        line_chart_shaded(&p, labels, &[line.clone(), dots], &[], Some(&s)).unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
        let ((_, x1), _) = bounds(&[line], &[], Some(&s));
        assert!(x1 > 4.5, "the x range covers the last interval: {x1}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
