//! A scalar map drawn cell by cell with a diverging colour scale, iso-lines and polylines on
//! top (paper Figure 10: σ_yy around the interface). Draws what it is given.

use super::contour::{GridCell, Segment};
use super::style::{
    Curve, FONT, Labels, Scale, draw_axes, draw_colour_bar, draw_curves, draw_legend, register_font,
};
use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;
use std::path::Path;

/// Iso-lines of one or more levels, drawn in one style.
#[derive(Debug, Clone)]
pub struct ContourSet {
    /// Legend label (`None`: not in the legend).
    pub label: Option<String>,
    /// Segments in axis units.
    pub segments: Vec<Segment>,
    /// Line colour.
    pub color: RGBColor,
}

/// Everything a map shows.
#[derive(Debug, Clone)]
pub struct Map {
    /// Filled cells in axis units.
    pub cells: Vec<GridCell>,
    /// Iso-lines on top of the cells.
    pub contours: Vec<ContourSet>,
    /// Polylines on top of everything (e.g. an interface).
    pub lines: Vec<Curve>,
}

/// Blue (low) – light grey (middle) – red (high), linear in RGB; grey for NaN.
pub fn diverging(v: f64, s: &Scale) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(200, 200, 200);
    }
    let f = s.fraction(v);
    let (lo, mid, hi) = ([59.0, 76.0, 192.0], [242.0, 242.0, 242.0], [180.0, 4.0, 38.0]);
    let (a, b, g) = if f < 0.5 {
        (lo, mid, 2.0 * f)
    } else {
        (mid, hi, 2.0 * f - 1.0)
    };
    let c = |k: usize| (a[k] + g * (b[k] - a[k])).round() as u8;
    RGBColor(c(0), c(1), c(2))
}

/// Plot height [px] for a plot width [px] that keeps one axis unit the same length on both axes.
fn plot_height(width: u32, x: (f64, f64), y: (f64, f64)) -> u32 {
    let h = f64::from(width) * (y.1 - y.0) / (x.1 - x.0);
    h.clamp(250.0, 900.0) as u32
}

/// Draws `map` with equal axis scales and a colour bar of `scale` to `path` (PNG).
pub fn map_with_contours(path: &Path, labels: Labels, map: &Map, scale: &Scale) -> Result<()> {
    if map.cells.is_empty() {
        return Err(anyhow!("{}: a map needs at least one cell", path.display()));
    }
    register_font()?;
    let fold = |f: fn(&GridCell) -> (f64, f64)| {
        map.cells
            .iter()
            .map(f)
            .fold((f64::MAX, f64::MIN), |m, c| (m.0.min(c.0), m.1.max(c.1)))
    };
    let (xr, yr) = (fold(|c| c.x), fold(|c| c.y));
    let plot_w = 1100;
    let size = (plot_w + 85 + 130 + 30, plot_height(plot_w, xr, yr) + 55 + 45 + 30);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE)?;
    let (main, bar) = root.split_horizontally(size.0 - 130);
    let mut chart = ChartBuilder::on(&main)
        .caption(labels.title, (FONT, 24))
        .margin(15)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    draw_axes(&mut chart, labels, false, (false, false))?;
    chart.draw_series(map.cells.iter().map(|c| {
        Rectangle::new(
            [(c.x.0, c.y.0), (c.x.1, c.y.1)],
            diverging(c.value, scale).filled(),
        )
    }))?;
    for set in &map.contours {
        let color = set.color;
        let anno = chart.draw_series(
            set.segments
                .iter()
                .map(|&(a, b)| PathElement::new(vec![a, b], color.stroke_width(1))),
        )?;
        if let Some(l) = &set.label {
            anno.label(l.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1)));
        }
    }
    draw_curves(&mut chart, &map.lines)?;
    draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    draw_colour_bar(&bar, scale, |v| diverging(v, scale))?;
    root.present()
        .with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::super::contour::CentroidGrid;
    use super::super::style::{Dash, PALETTE};
    use super::*;

    #[test]
    fn map_renders_cells_contours_and_lines() {
        let dir = std::env::temp_dir().join(format!("compare-map-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("map.png");
        let samples: Vec<(f64, f64, f64)> = (0..10)
            .flat_map(|r| (0..30).map(move |c| (c as f64 * 0.1, r as f64 * 0.1, c as f64 * 0.1 - 1.5)))
            .collect();
        let g = CentroidGrid::from_row_major(&samples);
        let map = Map {
            cells: g.cells(),
            contours: vec![ContourSet {
                label: Some("value = 0".into()),
                segments: g.contour(0.0),
                color: BLACK,
            }],
            lines: vec![Curve {
                label: "line".into(),
                points: vec![(0.0, 0.45), (2.9, 0.45)],
                color: PALETTE[2],
                dash: Dash::Solid,
            }],
        };
        let scale = Scale::new(-1.0, 1.0, "v [-]");
        let labels = Labels {
            title: "map",
            x: "x [m]",
            y: "y [m]",
        };
        map_with_contours(&p, labels, &map, &scale).unwrap();
        assert!(std::fs::metadata(&p).unwrap().len() > 1000);
        let empty = Map { cells: vec![], ..map };
        assert!(map_with_contours(&p, labels, &empty, &scale).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn diverging_scale_is_symmetric_and_clipped() {
        let s = Scale::new(-2.0, 2.0, "");
        assert_eq!(diverging(0.0, &s), RGBColor(242, 242, 242));
        assert_eq!(diverging(-5.0, &s), RGBColor(59, 76, 192));
        assert_eq!(diverging(2.0, &s), RGBColor(180, 4, 38));
    }
}
