//! Element-centroid values of a mapped structured mesh as a grid (columns of uniform x, rows of
//! varying y) and their iso-lines by marching squares. Pure; the figures draw what it returns.

/// Centroid values on a structured grid: `y[row][col]` and `value[row][col]`, NaN where the
/// sample window left an element out.
#[derive(Debug, Clone, PartialEq)]
pub struct CentroidGrid {
    /// Column x [m] (or any length unit), increasing.
    pub x: Vec<f64>,
    /// Centroid y per row and column (same unit as x), NaN where missing.
    pub y: Vec<Vec<f64>>,
    /// Value per row and column, NaN where missing.
    pub value: Vec<Vec<f64>>,
}

/// A contour segment between two points (x, y).
pub type Segment = ((f64, f64), (f64, f64));

/// An element drawn as the rectangle reaching halfway to its neighbouring centroids.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridCell {
    /// x extent.
    pub x: (f64, f64),
    /// y extent.
    pub y: (f64, f64),
    /// Value.
    pub value: f64,
}

/// Sorted distinct values (merging values closer than `tol`).
fn distinct(mut v: Vec<f64>, tol: f64) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup_by(|b, a| (*b - *a).abs() <= tol);
    v
}

/// Index of the entry of `sorted` nearest `x`.
fn nearest(sorted: &[f64], x: f64) -> usize {
    let j = sorted.partition_point(|&c| c < x);
    match j.checked_sub(1) {
        Some(i) if j == sorted.len() || (x - sorted[i]) < (sorted[j] - x) => i,
        _ => j,
    }
}

impl CentroidGrid {
    /// Builds the grid from (x, y, value) samples in row-major order (a mesh row after the
    /// other, x increasing within a row): a new row starts where x does not increase. Rows cut
    /// by the sample window keep their columns; missing entries are NaN.
    pub fn from_row_major(samples: &[(f64, f64, f64)]) -> CentroidGrid {
        let span = samples
            .iter()
            .map(|s| s.0.abs())
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let x = distinct(samples.iter().map(|s| s.0).collect(), 1e-9 * span);
        let (mut y, mut value) = (Vec::new(), Vec::new());
        let mut last_x = f64::INFINITY;
        for &(sx, sy, v) in samples {
            if sx <= last_x {
                y.push(vec![f64::NAN; x.len()]);
                value.push(vec![f64::NAN; x.len()]);
            }
            last_x = sx;
            let c = nearest(&x, sx);
            let r = y.len() - 1;
            (y[r][c], value[r][c]) = (sy, v);
        }
        CentroidGrid { x, y, value }
    }

    /// Each present element as a rectangle: x halfway to the neighbouring columns (uniform
    /// spacing: the median column step), y halfway to the neighbouring centroids of its column
    /// (at the ends of a column, the half-step on the other side is mirrored).
    pub fn cells(&self) -> Vec<GridCell> {
        let mut steps: Vec<f64> = self.x.windows(2).map(|w| w[1] - w[0]).collect();
        steps.sort_by(f64::total_cmp);
        let dx = steps.get(steps.len() / 2).copied().unwrap_or(1.0);
        let mut out = Vec::new();
        for (c, &xc) in self.x.iter().enumerate() {
            let col: Vec<(f64, f64)> = (0..self.y.len())
                .map(|r| (self.y[r][c], self.value[r][c]))
                .filter(|p| p.0.is_finite())
                .collect();
            for (k, &(yc, v)) in col.iter().enumerate() {
                let below = k.checked_sub(1).map(|i| 0.5 * (yc - col[i].0));
                let above = col.get(k + 1).map(|p| 0.5 * (p.0 - yc));
                let (lo, hi) = match (below, above) {
                    (Some(b), Some(a)) => (b, a),
                    (Some(b), None) => (b, b),
                    (None, Some(a)) => (a, a),
                    (None, None) => (0.5 * dx, 0.5 * dx),
                };
                out.push(GridCell {
                    x: (xc - 0.5 * dx, xc + 0.5 * dx),
                    y: (yc - lo, yc + hi),
                    value: v,
                });
            }
        }
        out
    }

    fn corner(&self, r: usize, c: usize) -> (f64, f64, f64) {
        (self.x[c], self.y[r][c], self.value[r][c])
    }

    /// The iso-line `value = level` by marching squares over the cells formed by four
    /// neighbouring centroids (cells with a missing corner are skipped). Crossings are placed by
    /// linear interpolation between the two centroids of an edge; a saddle is resolved by the
    /// mean of the four corners.
    pub fn contour(&self, level: f64) -> Vec<Segment> {
        let mut out = Vec::new();
        for r in 0..self.y.len().saturating_sub(1) {
            for c in 0..self.x.len().saturating_sub(1) {
                let p = [
                    self.corner(r, c),
                    self.corner(r, c + 1),
                    self.corner(r + 1, c + 1),
                    self.corner(r + 1, c),
                ];
                if p.iter().all(|q| q.1.is_finite() && q.2.is_finite()) {
                    square(&p, level, &mut out);
                }
            }
        }
        out
    }
}

/// Crossing on the edge from corner `a` to corner `b` (x, y, value).
fn crossing(a: (f64, f64, f64), b: (f64, f64, f64), level: f64) -> (f64, f64) {
    let f = (level - a.2) / (b.2 - a.2);
    (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1))
}

/// Segments of one cell; corners counter-clockwise from the lower left, edge k joins corners
/// k and k + 1.
fn square(p: &[(f64, f64, f64); 4], level: f64, out: &mut Vec<Segment>) {
    let above: Vec<bool> = p.iter().map(|q| q.2 > level).collect();
    let cut: Vec<usize> = (0..4).filter(|&k| above[k] != above[(k + 1) % 4]).collect();
    let point = |k: usize| crossing(p[k], p[(k + 1) % 4], level);
    match cut.len() {
        2 => out.push((point(cut[0]), point(cut[1]))),
        4 => {
            let centre_above = p.iter().map(|q| q.2).sum::<f64>() / 4.0 > level;
            if centre_above == above[0] {
                // corners 0 and 2 are joined through the centre: cut off corners 1 and 3
                out.push((point(0), point(1)));
                out.push((point(2), point(3)));
            } else {
                out.push((point(3), point(0)));
                out.push((point(1), point(2)));
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 6 × 5 grid whose rows are mapped column by column (y spacing varies per column), value
    /// from `f(x, y)`, in row-major order.
    fn samples(f: impl Fn(f64, f64) -> f64) -> Vec<(f64, f64, f64)> {
        let mut s = Vec::new();
        for r in 0..5 {
            for c in 0..6 {
                let x = 0.1 * c as f64;
                let y = (r as f64 - 2.0) * (0.1 + 0.02 * c as f64) + 0.03 * c as f64;
                s.push((x, y, f(x, y)));
            }
        }
        s
    }

    #[test]
    fn grid_recovers_rows_and_columns() {
        let g = CentroidGrid::from_row_major(&samples(|x, _| x));
        assert_eq!((g.x.len(), g.y.len()), (6, 5));
        assert!((g.y[4][5] - (2.0 * 0.2 + 0.15)).abs() < 1e-12);
        // a row cut by the window: only the columns present are filled, the row stays aligned
        let mut s = samples(|x, _| x);
        s.retain(|p| !(p.1 > 0.3 && p.0 > 0.25));
        let g = CentroidGrid::from_row_major(&s);
        assert_eq!(g.y.len(), 5);
        assert!(g.value[4][5].is_nan() && g.value[4][0] == 0.0);
    }

    #[test]
    fn plane_z_equals_x_gives_a_straight_contour_at_the_level() {
        let g = CentroidGrid::from_row_major(&samples(|x, _| x));
        let seg = g.contour(0.23);
        assert_eq!(seg.len(), 4, "one segment per row of cells");
        for (a, b) in &seg {
            assert!(
                (a.0 - 0.23).abs() < 1e-12 && (b.0 - 0.23).abs() < 1e-12,
                "{a:?} {b:?}"
            );
        }
        // the contour spans the column's rows: from its lowest to its highest centroid
        let ys: Vec<f64> = seg.iter().flat_map(|(a, b)| [a.1, b.1]).collect();
        let (lo, hi) = ys
            .iter()
            .fold((f64::MAX, f64::MIN), |m, &y| (m.0.min(y), m.1.max(y)));
        let col = |r: usize| g.y[r][2] + 0.3 * (g.y[r][3] - g.y[r][2]);
        assert!((lo - col(0)).abs() < 1e-12 && (hi - col(4)).abs() < 1e-12);
        assert!(g.contour(2.0).is_empty());
    }

    #[test]
    fn saddle_gives_two_segments() {
        let p = [
            (0.0, 0.0, 1.0),
            (1.0, 0.0, -1.0),
            (1.0, 1.0, 1.0),
            (0.0, 1.0, -1.0),
        ];
        let mut out = Vec::new();
        square(&p, 0.0, &mut out);
        assert_eq!(out.len(), 2);
        square(&p, 0.5, &mut out);
        assert_eq!(out.len(), 4);
    }

    #[test]
    fn cells_reach_halfway_to_their_neighbours() {
        let g = CentroidGrid::from_row_major(&samples(|x, y| x + y));
        let cells = g.cells();
        assert_eq!(cells.len(), 30);
        let c = cells[2]; // column 0, row 2: centroids at -0.1, 0.0, 0.1 around it
        assert!((c.x.0 + 0.05).abs() < 1e-12 && (c.x.1 - 0.05).abs() < 1e-12);
        assert!((c.y.0 + 0.05).abs() < 1e-12 && (c.y.1 - 0.05).abs() < 1e-12);
        let top = cells[4];
        assert!(
            (top.y.1 - top.y.0 - 0.1).abs() < 1e-12,
            "end cells mirror the inner half-step"
        );
    }
}
