//! A scalar map drawn cell by cell with a diverging colour scale, iso-lines and polylines on
//! top (paper Figure 10: σ_yy around the interface). Draws what it is given.

use super::contour::{GridCell, Segment};
use super::file::figure;
use super::style::{
    Curve, FONT, Labels, Scale, draw_axes, draw_colour_bar, draw_curves, draw_legend, register_font,
};
use anyhow::{Result, anyhow};
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

/// The y range [axis units] every column of cells covers from bottom to top: the highest of the
/// columns' lowest edges to the lowest of their highest edges (`None` if they do not overlap).
/// A window that cuts the rows of a mapped mesh leaves columns of uneven height; the map is drawn
/// over the range they all cover, so that the field reaches the frame instead of a ragged white
/// edge (the cells beyond are clipped by the frame).
fn covered_y(cells: &[GridCell]) -> Option<(f64, f64)> {
    // per column (the bits of its left edge, the same for every cell of a column): its lowest
    // and highest edge
    let mut columns = std::collections::BTreeMap::<u64, (f64, f64)>::new();
    for c in cells {
        let col = columns.entry(c.x.0.to_bits()).or_insert((c.y.0, c.y.1));
        *col = (col.0.min(c.y.0), col.1.max(c.y.1));
    }
    let lo = columns.values().map(|c| c.0).fold(f64::MIN, f64::max);
    let hi = columns.values().map(|c| c.1).fold(f64::MAX, f64::min);
    (lo < hi).then_some((lo, hi))
}

/// The part of the segment a–b inside the box `xr` × `yr` (Liang–Barsky), `None` if none is.
fn clip(a: (f64, f64), b: (f64, f64), xr: (f64, f64), yr: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - xr.0),
        (dx, xr.1 - a.0),
        (-dy, a.1 - yr.0),
        (dy, yr.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    (t0 <= t1).then_some(((a.0 + t0 * dx, a.1 + t0 * dy), (a.0 + t1 * dx, a.1 + t1 * dy)))
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
    let (xr, yr) = (fold(|c| c.x), covered_y(&map.cells).unwrap_or(fold(|c| c.y)));
    let plot_w = 1100;
    let size = (plot_w + 85 + 130 + 30, plot_height(plot_w, xr, yr) + 55 + 45 + 30);
    figure(path, size, |root| {
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
            // plotters moves a point outside the axes onto the frame instead of cutting the line
            // there, so the segments are cut at the frame first
            let anno = chart.draw_series(
                set.segments
                    .iter()
                    .filter_map(|&(a, b)| clip(a, b, xr, yr))
                    .map(|(a, b)| PathElement::new(vec![a, b], color.stroke_width(1))),
            )?;
            if let Some(l) = &set.label {
                anno.label(l.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(1)));
            }
        }
        draw_curves(&mut chart, &map.lines)?;
        if !map.lines.is_empty() || map.contours.iter().any(|c| c.label.is_some()) {
            draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        }
        draw_colour_bar(&bar, scale, |v| diverging(v, scale))?;
        Ok(())
    })
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

    /// The picture itself: circles r² = x² + y² = 0.0625, 0.25, 0.5 on a grid whose window cuts
    /// the top rows on the right, as a snapshot window cuts a mapped mesh. The field fills the
    /// frame (no white left inside it), and every dark pixel drawn
    /// where the field is sampled must lie on one of those circles (within 1.5 grid steps: the
    /// iso-lines are traced linearly between centroids). Before the fix of
    /// `CentroidGrid::contour`, segments ending on the edge of a cell with a missing corner got a
    /// NaN end and were drawn as straight lines across the whole plot.
    #[test]
    fn a_map_draws_no_line_that_is_not_an_iso_line() {
        let dir = std::env::temp_dir().join(format!("compare-map-pixels-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("map.png");
        let (step, levels) = (0.025, [0.0625, 0.25, 0.5]);
        // the window: the top three rows only up to x = 0
        let sampled = |x: f64, y: f64| y <= 0.425 + 1e-9 || x <= 1e-9;
        let mut samples = Vec::new();
        for r in 0..41 {
            for c in 0..81 {
                let (x, y) = (step * c as f64 - 1.0, step * r as f64 - 0.5);
                if sampled(x, y) {
                    samples.push((x, y, x * x + y * y));
                }
            }
        }
        let g = CentroidGrid::from_row_major(&samples);
        let segments: Vec<_> = levels.iter().flat_map(|&l| g.contour(l)).collect();
        let map = Map {
            cells: g.cells(),
            contours: vec![ContourSet {
                label: None,
                segments,
                color: BLACK,
            }],
            lines: vec![],
        };
        let labels = Labels {
            title: "",
            x: "x [m]",
            y: "y [m]",
        };
        map_with_contours(&p, labels, &map, &Scale::new(-1.0, 1.0, "v [-]")).unwrap();
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&p).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.line_size / info.width as usize;
        let rgb = |i: usize, j: usize| {
            let k = j * info.line_size + i * channels;
            (i32::from(buf[k]), i32::from(buf[k + 1]), i32::from(buf[k + 2]))
        };
        // the plot area: the box of the map's red cells (the field is largest at x = ±1, where
        // the cells are red from bottom to top), left of the colour bar
        let (w, h) = (info.width as usize, info.height as usize);
        let red: Vec<(usize, usize)> = (0..w - 130)
            .flat_map(|i| (0..h).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let (r, _, b) = rgb(i, j);
                r > b + 60
            })
            .collect();
        let (i0, i1) = red.iter().fold((w, 0), |m, p| (m.0.min(p.0), m.1.max(p.0)));
        let (j0, j1) = red.iter().fold((h, 0), |m, p| (m.0.min(p.1), m.1.max(p.1)));
        // the map is drawn over the y range every column covers: up to the cut rows' edge
        let (xr, yr) = (
            (-1.0 - 0.5 * step, 1.0 + 0.5 * step),
            (-0.5 - 0.5 * step, 0.425 + 0.5 * step),
        );
        let at = |i: usize, j: usize| {
            (
                xr.0 + (i - i0) as f64 / (i1 - i0) as f64 * (xr.1 - xr.0),
                yr.1 - (j - j0) as f64 / (j1 - j0) as f64 * (yr.1 - yr.0),
            )
        };
        let (mut dark, mut astray) = (0, Vec::new());
        for i in i0 + 2..i1 - 1 {
            for j in j0 + 2..j1 - 1 {
                let (r, g, b) = rgb(i, j);
                let (x, y) = at(i, j);
                if r.max(g).max(b) >= 80 || !sampled(x, y) {
                    continue;
                }
                dark += 1;
                let off = levels
                    .iter()
                    .map(|l| ((x * x + y * y).sqrt() - l.sqrt()).abs())
                    .fold(f64::MAX, f64::min);
                if off > 1.5 * step {
                    astray.push((x, y));
                }
            }
        }
        // the field reaches the frame: no pixel of the plot area is left white (the cells'
        // lightest colour is the scale's middle grey, 242); before the map was drawn over the
        // covered range, the cut rows left a white band along the top on the right
        let white = (i0 + 2..i1 - 1)
            .flat_map(|i| (j0 + 2..j1 - 1).map(move |j| (i, j)))
            .filter(|&(i, j)| {
                let (r, g, b) = rgb(i, j);
                r.min(g).min(b) >= 250
            })
            .count();
        println!(
            "{dark} dark pixels in the sampled plot area, {} off every iso-line; {white} white",
            astray.len()
        );
        assert_eq!(white, 0, "the map leaves white inside its frame");
        assert!(dark > 500, "the iso-lines are drawn");
        assert!(
            astray.is_empty(),
            "lines off the iso-lines, e.g. at {:?}",
            &astray[..astray.len().min(5)]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn segments_are_cut_at_the_frame() {
        let (xr, yr) = ((0.0, 1.0), (0.0, 1.0));
        // inside: unchanged; across the top: cut at y = 1; outside: gone
        assert_eq!(
            clip((0.2, 0.2), (0.4, 0.6), xr, yr),
            Some(((0.2, 0.2), (0.4, 0.6)))
        );
        let ((_, _), (x, y)) = clip((0.5, 0.5), (0.5, 1.5), xr, yr).unwrap();
        assert_eq!((x, y), (0.5, 1.0));
        assert_eq!(clip((0.2, 1.2), (0.8, 1.4), xr, yr), None);
        assert_eq!(clip((-1.0, 0.5), (-0.5, 0.5), xr, yr), None);
    }

    #[test]
    fn diverging_scale_is_symmetric_and_clipped() {
        let s = Scale::new(-2.0, 2.0, "");
        assert_eq!(diverging(0.0, &s), RGBColor(242, 242, 242));
        assert_eq!(diverging(-5.0, &s), RGBColor(59, 76, 192));
        assert_eq!(diverging(2.0, &s), RGBColor(180, 4, 38));
    }
}
