//! Element-centroid values of a mapped structured mesh as a grid (columns of uniform x, rows of
//! varying y) and their iso-lines. The iso-lines come from the `contour` crate's marching squares
//! in index space, mapped back onto the centroids. Pure; the figures draw what it returns.

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

    /// The index-space cell (first column, first row) that holds (c, r); a point on a shared
    /// edge belongs to the cell above or to the right of it.
    fn cell_of(&self, c: f64, r: f64) -> (usize, usize) {
        (
            (c.floor() as usize).min(self.x.len() - 2),
            (r.floor() as usize).min(self.y.len() - 2),
        )
    }

    /// The point of index-space coordinates (column c, row r) by bilinear interpolation of the
    /// four centroids of `cell`, which must hold the point (on its edges included). A segment's
    /// two ends are both mapped through the cell its midpoint lies in: an end on an edge shared
    /// with a cell that has a missing corner would otherwise be interpolated there, to NaN.
    fn at(&self, (c0, r0): (usize, usize), c: f64, r: f64) -> (f64, f64) {
        let (fc, fr) = (c - c0 as f64, r - r0 as f64);
        let x = self.x[c0] + fc * (self.x[c0 + 1] - self.x[c0]);
        let lerp = |row: &Vec<f64>| row[c0] + fc * (row[c0 + 1] - row[c0]);
        let (ya, yb) = (lerp(&self.y[r0]), lerp(&self.y[r0 + 1]));
        (x, ya + fr * (yb - ya))
    }

    /// Whether every corner of the index-space cell is present.
    fn complete(&self, (c0, r0): (usize, usize)) -> bool {
        [(r0, c0), (r0, c0 + 1), (r0 + 1, c0), (r0 + 1, c0 + 1)]
            .iter()
            .all(|&(i, j)| self.y[i][j].is_finite() && self.value[i][j].is_finite())
    }

    /// The iso-line `value = level` as segments between centroid-grid crossings. The `contour`
    /// crate traces it in index space with linear interpolation along cell edges; pieces on the
    /// outer edge of the grid (where it closes its rings) and pieces through cells with a
    /// missing corner are left out, and the rest is mapped onto the centroids bilinearly.
    pub fn contour(&self, level: f64) -> Vec<Segment> {
        let (nr, nc) = (self.y.len(), self.x.len());
        if nr < 2 || nc < 2 {
            return Vec::new();
        }
        let values: Vec<f64> = self.value.iter().flatten().copied().collect();
        let Ok(lines) = contour::ContourBuilder::new(nc, nr, true).lines(&values, &[level]) else {
            return Vec::new();
        };
        // the crate puts sample (i, j) at the centre (i + ½, j + ½) of its pixel
        let inside = |p: &contour::Pt| {
            let (c, r) = (p.x - 0.5, p.y - 0.5);
            (c >= 0.0 && c <= (nc - 1) as f64 && r >= 0.0 && r <= (nr - 1) as f64).then_some((c, r))
        };
        let mut out = Vec::new();
        for line in &lines {
            for ring in &line.geometry().0 {
                for w in ring.0.windows(2) {
                    let (Some(a), Some(b)) = (inside(&w[0]), inside(&w[1])) else {
                        continue;
                    };
                    let cell = self.cell_of(0.5 * (a.0 + b.0), 0.5 * (a.1 + b.1));
                    if a != b && self.complete(cell) {
                        out.push((self.at(cell, a.0, a.1), self.at(cell, b.0, b.1)));
                    }
                }
            }
        }
        out
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

    /// A window that cuts the top row leaves cells with a missing corner. A segment in the cell
    /// below them ends on the edge it shares with them; that end used to be interpolated in the
    /// incomplete cell, to a NaN ordinate, which the map drew as a line across the whole plot.
    #[test]
    fn segments_next_to_a_missing_corner_have_finite_ends() {
        let mut s = samples(|x, _| x);
        s.retain(|p| !(p.1 > 0.3 && p.0 > 0.25));
        let g = CentroidGrid::from_row_major(&s);
        let seg = g.contour(0.23);
        assert_eq!(seg.len(), 3, "the cell row with a missing corner is left out");
        for (a, b) in &seg {
            for p in [a, b] {
                assert!(p.0.is_finite() && p.1.is_finite(), "{a:?} {b:?}");
                assert!((p.0 - 0.23).abs() < 1e-12, "{p:?}");
            }
        }
    }

    #[test]
    fn a_circle_is_traced_inside_the_grid_and_not_along_its_edge() {
        // r² = x² + y² on a 21 × 21 grid of spacing 0.1 centred on 0: the level 0.25 is the
        // circle of radius 0.5, every crossing within one cell of it
        let mut s = Vec::new();
        for r in 0..21 {
            for c in 0..21 {
                let (x, y) = (0.1 * c as f64 - 1.0, 0.1 * r as f64 - 1.0);
                s.push((x, y, x * x + y * y));
            }
        }
        let g = CentroidGrid::from_row_major(&s);
        let seg = g.contour(0.25);
        assert!(seg.len() >= 20, "{}", seg.len());
        for (a, b) in &seg {
            for p in [a, b] {
                let rad = (p.0 * p.0 + p.1 * p.1).sqrt();
                assert!((rad - 0.5).abs() < 0.02, "{p:?} at radius {rad}");
            }
        }
        // the level 1.5 only exists in the corners: no piece runs along the grid's edge
        let pieces = g.contour(1.5);
        assert!(!pieces.is_empty());
        for (a, b) in pieces {
            let along_x_edge = (a.1 - b.1).abs() < 1e-12 && a.1.abs() > 0.999;
            let along_y_edge = (a.0 - b.0).abs() < 1e-12 && a.0.abs() > 0.999;
            assert!(!along_x_edge && !along_y_edge, "{a:?} {b:?}");
        }
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
