//! Structured Q4 grid of a rectangle, stored layer by layer, with an optional twinned node row
//! (docs/fem-model.md §3.1) and an optional mapping of that row onto y = f(x).
//!
//! Node id = layer · (nx + 1) + column. A twinned row j_c has two layers, − (used by the elements
//! below) then + (used by the elements above); every other row has one layer. Element row r
//! (between node rows r and r+1) uses layers `upper_layer[r]` and `upper_layer[r] + 1`, so the
//! elements of one row touch two consecutive layers only.

use nalgebra::Vector2;

/// Side of a layer with respect to the twinned row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LayerSide {
    /// Ordinary row.
    Single,
    /// Twinned row, copy used by the elements below (− side).
    Minus,
    /// Twinned row, copy used by the elements above (+ side).
    Plus,
}

/// Geometry of the grid to generate.
pub(crate) struct GridSpec<'a> {
    /// x range [m].
    pub x_range: [f64; 2],
    /// y range [m].
    pub y_range: [f64; 2],
    /// Elements along x and y.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Node row carrying twins (the interface row), if any.
    pub twinned_row: Option<usize>,
    /// Horizontal shift [m] of every node of the + layer and above.
    pub upper_shift: f64,
    /// Node row `row` follows y = f(x); rows in between are interpolated linearly in y.
    pub row_map: Option<(usize, &'a dyn Fn(f64) -> f64)>,
}

/// The generated grid.
#[derive(Debug, Clone)]
pub(crate) struct Grid {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Node row of each layer.
    pub layer_row: Vec<usize>,
    /// Side of each layer.
    pub layer_side: Vec<LayerSide>,
    /// Layer used by the elements above node row j.
    pub upper_layer: Vec<usize>,
    /// Reference positions X [m], per node.
    pub x0: Vec<Vector2<f64>>,
    /// Twinned row, if any.
    pub twinned_row: Option<usize>,
}

impl Grid {
    /// Generates the grid.
    pub fn new(spec: &GridSpec<'_>) -> Grid {
        let (nx, ny) = (spec.nx, spec.ny);
        let (mut layer_row, mut layer_side, mut upper_layer) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..=ny {
            if spec.twinned_row == Some(j) {
                layer_row.extend([j, j]);
                layer_side.extend([LayerSide::Minus, LayerSide::Plus]);
            } else {
                layer_row.push(j);
                layer_side.push(LayerSide::Single);
            }
            upper_layer.push(layer_row.len() - 1);
        }
        let hx = (spec.x_range[1] - spec.x_range[0]) / nx as f64;
        let hy = (spec.y_range[1] - spec.y_range[0]) / ny as f64;
        let mut x0 = Vec::with_capacity(layer_row.len() * (nx + 1));
        let mut upper = false;
        for (&j, &side) in layer_row.iter().zip(&layer_side) {
            upper |= side == LayerSide::Plus || spec.twinned_row.is_some_and(|jc| j > jc);
            for i in 0..=nx {
                let x = spec.x_range[0] + i as f64 * hx;
                let y = match spec.row_map {
                    None => spec.y_range[0] + j as f64 * hy,
                    Some((jm, f)) => mapped_y(x, j, jm, ny, spec.y_range, f),
                };
                let shift = if upper { spec.upper_shift } else { 0.0 };
                x0.push(Vector2::new(x + shift, y));
            }
        }
        Grid {
            nx,
            ny,
            layer_row,
            layer_side,
            upper_layer,
            x0,
            twinned_row: spec.twinned_row,
        }
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.x0.len()
    }

    /// Number of elements.
    pub fn num_elements(&self) -> usize {
        self.nx * self.ny
    }

    /// Node id of (layer, column).
    #[inline]
    pub fn node(&self, layer: usize, i: usize) -> u32 {
        (layer * (self.nx + 1) + i) as u32
    }

    /// Nodes of element e, counter-clockwise from the bottom-left corner.
    #[inline]
    pub fn element_nodes(&self, e: usize) -> [u32; 4] {
        let (r, c) = (e / self.nx, e % self.nx);
        let (lb, lt) = (self.upper_layer[r], self.upper_layer[r] + 1);
        [
            self.node(lb, c),
            self.node(lb, c + 1),
            self.node(lt, c + 1),
            self.node(lt, c),
        ]
    }

    /// Reference corner positions of element e [m].
    pub fn element_coords(&self, e: usize) -> [Vector2<f64>; 4] {
        self.element_nodes(e).map(|n| self.x0[n as usize])
    }

    /// Element rows touching a layer: (row below, row above).
    pub fn layer_element_rows(&self, layer: usize) -> (Option<usize>, Option<usize>) {
        let j = self.layer_row[layer];
        let below = (j > 0 && self.layer_side[layer] != LayerSide::Plus).then(|| j - 1);
        let above = (j < self.ny && self.layer_side[layer] != LayerSide::Minus).then_some(j);
        (below, above)
    }

    /// Whether node n lies on the outer boundary of the rectangle.
    pub fn on_outer_boundary(&self, n: usize) -> bool {
        let (layer, i) = (n / (self.nx + 1), n % (self.nx + 1));
        let j = self.layer_row[layer];
        i == 0 || i == self.nx || j == 0 || j == self.ny
    }
}

/// y of node row j in a grid whose row jm follows y = f(x): linear interpolation in j between the
/// bottom edge and f(x), and between f(x) and the top edge.
fn mapped_y(x: f64, j: usize, jm: usize, ny: usize, y_range: [f64; 2], f: &dyn Fn(f64) -> f64) -> f64 {
    let ym = f(x);
    if j <= jm {
        y_range[0] + (ym - y_range[0]) * j as f64 / jm as f64
    } else {
        ym + (y_range[1] - ym) * (j - jm) as f64 / (ny - jm) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twinned_layers_and_element_nodes() {
        let g = Grid::new(&GridSpec {
            x_range: [0.0, 3.0],
            y_range: [-1.0, 1.0],
            nx: 3,
            ny: 2,
            twinned_row: Some(1),
            upper_shift: 0.0,
            row_map: None,
        });
        assert_eq!(g.layer_row, vec![0, 1, 1, 2]);
        assert_eq!(g.num_nodes(), 16);
        // element row 0 uses layers 0, 1 (− copy); row 1 uses layers 2 (+ copy), 3
        assert_eq!(g.element_nodes(0), [0, 1, 5, 4]);
        assert_eq!(g.element_nodes(3), [8, 9, 13, 12]);
        assert_eq!(g.x0[5], g.x0[9]);
        assert_eq!(g.layer_element_rows(1), (Some(0), None));
        assert_eq!(g.layer_element_rows(2), (None, Some(1)));
    }

    #[test]
    fn mapped_row_follows_curve() {
        let f = |x: f64| 0.1 * x.sin();
        let g = Grid::new(&GridSpec {
            x_range: [0.0, 2.0],
            y_range: [-1.0, 1.0],
            nx: 4,
            ny: 4,
            twinned_row: Some(2),
            upper_shift: 0.0,
            row_map: Some((2, &f)),
        });
        for i in 0..=4 {
            let n = g.node(g.upper_layer[2], i) as usize;
            assert!((g.x0[n].y - f(g.x0[n].x)).abs() < 1e-15);
        }
    }
}
