//! Line charts: curves (solid, dashed or markers), reference marks and shaded x-intervals, on
//! linear or logarithmic axes (plotters' own log scale).

use super::file::figure;
use super::style::{
    Chart, Curve, FONT, Labels, Mark, SIZE, draw_axes, draw_curves, draw_legend, register_font,
};
use anyhow::Result;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::element::DashedPathElement;
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

/// Which axes of a line chart are logarithmic (base 10).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LogAxes {
    /// Logarithmic x axis (points with x ≤ 0 are left out).
    pub x: bool,
    /// Logarithmic y axis (points with y ≤ 0 are left out).
    pub y: bool,
}

/// Everything one line chart shows.
#[derive(Debug, Clone, Copy)]
pub struct LineChart<'a> {
    /// Title and axis labels.
    pub labels: Labels<'a>,
    /// Curves.
    pub curves: &'a [Curve],
    /// Reference lines.
    pub marks: &'a [Mark],
    /// Shaded x-intervals under the curves.
    pub shading: Option<&'a Shading>,
    /// Logarithmic axes.
    pub log: LogAxes,
    /// Fixed y range (`None`: fitted to the curves and marks); points outside are left out.
    pub y_range: Option<(f64, f64)>,
}

/// The extent of one axis over the values `v` that the axis can show, padded by 4 % (in
/// decades on a log axis).
fn extent(v: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && (!log || *x > 0.0))
        .fold((f64::MAX, f64::MIN), |m, x| (m.0.min(x), m.1.max(x)));
    if lo > hi {
        return if log { (1.0, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        let (a, b) = (lo.log10(), hi.log10());
        let d = if b > a { 0.04 * (b - a) } else { 0.5 };
        (10f64.powf(a - d), 10f64.powf(b + d))
    } else {
        let d = if hi > lo {
            0.04 * (hi - lo)
        } else {
            0.5 * lo.abs().max(1e-12)
        };
        (lo - d, hi + d)
    }
}

fn bounds(c: &LineChart) -> ((f64, f64), (f64, f64)) {
    let pts = || c.curves.iter().flat_map(|k| k.points.iter());
    let xs = pts().map(|p| p.0).chain(c.marks.iter().filter_map(|m| match m {
        Mark::Vertical(x, _) => Some(*x),
        Mark::Horizontal(..) => None,
    }));
    let shaded = c.shading.map_or(&[][..], |s| &s.intervals[..]);
    let xs = xs.chain(shaded.iter().flat_map(|&(a, b)| [a, b]));
    let ys = pts().map(|p| p.1).chain(c.marks.iter().filter_map(|m| match m {
        Mark::Horizontal(y, _, _) => Some(*y),
        Mark::Vertical(..) => None,
    }));
    (
        extent(xs, c.log.x),
        c.y_range.unwrap_or_else(|| extent(ys, c.log.y)),
    )
}

/// Draws a line chart with a legend to `path` (PNG), linear axes.
pub fn line_chart(path: &Path, labels: Labels, curves: &[Curve], marks: &[Mark]) -> Result<()> {
    draw(
        path,
        &LineChart {
            labels,
            curves,
            marks,
            shading: None,
            log: LogAxes::default(),
            y_range: None,
        },
    )
}

/// Draws a line chart with a legend to `path` (PNG), with `shading` (if any) under the curves.
pub fn line_chart_shaded(
    path: &Path,
    labels: Labels,
    curves: &[Curve],
    marks: &[Mark],
    shading: Option<&Shading>,
) -> Result<()> {
    draw(
        path,
        &LineChart {
            labels,
            curves,
            marks,
            shading,
            log: LogAxes::default(),
            y_range: None,
        },
    )
}

/// Draws `chart` to `path` (PNG).
pub fn draw(path: &Path, chart: &LineChart) -> Result<()> {
    register_font()?;
    let ((x0, x1), (y0, y1)) = bounds(chart);
    figure(path, SIZE, |root| {
        root.fill(&WHITE)?;
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(chart.labels.title, (FONT, 26))
            .margin(15)
            .x_label_area_size(55)
            .y_label_area_size(85);
        match (chart.log.x, chart.log.y) {
            (false, false) => finish(builder.build_cartesian_2d(x0..x1, y0..y1)?, chart, (y0, y1))?,
            (true, false) => finish(
                builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1)?,
                chart,
                (y0, y1),
            )?,
            (false, true) => finish(
                builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale())?,
                chart,
                (y0, y1),
            )?,
            (true, true) => finish(
                builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?,
                chart,
                (y0, y1),
            )?,
        }
        Ok(())
    })
}

fn finish<'a, 'b: 'a, X, Y>(mut chart: Chart<'a, 'b, X, Y>, c: &LineChart, (y0, y1): (f64, f64)) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    draw_axes(&mut chart, c.labels, true, (c.log.x, c.log.y))?;
    if let Some(s) = c.shading {
        let color = s.color;
        let rects = s
            .intervals
            .iter()
            .map(|&(a, b)| Rectangle::new([(a, y0), (b, y1)], color.filled()));
        chart
            .draw_series(rects)?
            .label(s.label.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 24, y + 6)], color.filled()));
    }
    let keep = |p: &(f64, f64)| (!c.log.x || p.0 > 0.0) && (!c.log.y || p.1 > 0.0) && p.1 >= y0 && p.1 <= y1;
    let curves: Vec<Curve> = c
        .curves
        .iter()
        .map(|k| Curve {
            points: k.points.iter().copied().filter(keep).collect(),
            ..k.clone()
        })
        .collect();
    draw_curves(&mut chart, &curves)?;
    draw_marks(&mut chart, c.marks)?;
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)
}

fn draw_marks<X, Y>(chart: &mut Chart<'_, '_, X, Y>, marks: &[Mark]) -> Result<()>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let (xr, yr) = (chart.x_range(), chart.y_range());
    for m in marks {
        match m {
            Mark::Vertical(x, color) => {
                let pts = vec![(*x, yr.start), (*x, yr.end)];
                chart.draw_series(DashedLineSeries::new(pts, 4, 4, color.stroke_width(1)))?;
            }
            Mark::Horizontal(y, color, label) => {
                let style = color.stroke_width(1);
                let pts = vec![(xr.start, *y), (xr.end, *y)];
                chart
                    .draw_series(DashedLineSeries::new(pts, 4, 4, style))?
                    .label(label.clone())
                    .legend(move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], 4, 4, style));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::style::{Dash, PALETTE, log_tick};
    use super::*;

    fn tmp(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("compare-lines-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn shaded_chart_with_markers_renders_and_widens_to_the_shading() {
        let p = tmp("shaded.png");
        let line = Curve::nth(
            "line",
            (0..40)
                .map(|i| (i as f64 * 0.1, (i as f64 * 0.2).cos()))
                .collect(),
            0,
            Dash::Solid,
        );
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
        let curves = [line];
        let c = LineChart {
            labels,
            curves: &curves,
            marks: &[],
            shading: Some(&s),
            log: LogAxes::default(),
            y_range: None,
        };
        let ((_, x1), _) = bounds(&c);
        assert!(x1 > 4.5, "the x range covers the last interval: {x1}");
    }

    #[test]
    fn log_axes_leave_out_non_positive_values_and_pad_in_decades() {
        let (lo, hi) = extent([-1.0, 0.0, 1e-3, 1e-1].into_iter(), true);
        assert!((lo.log10() + 3.08).abs() < 1e-9 && (hi.log10() + 0.92).abs() < 1e-9);
        let p = tmp("loglog.png");
        let c = Curve::nth(
            "power law",
            vec![(1.0, 1.0), (10.0, 0.01), (0.0, 5.0)],
            0,
            Dash::Dashed,
        );
        let marks = [Mark::Horizontal(0.05, BLACK, "5 %".into())];
        let chart = LineChart {
            labels: Labels {
                title: "log-log",
                x: "wall time [s]",
                y: "error [-]",
            },
            curves: &[c],
            marks: &marks,
            shading: None,
            log: LogAxes { x: true, y: true },
            y_range: None,
        };
        draw(&p, &chart).unwrap();
        assert_eq!(log_tick(&1e-3), "1e-3");
        assert_eq!(log_tick(&0.1), "0.1");
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
    }
}
