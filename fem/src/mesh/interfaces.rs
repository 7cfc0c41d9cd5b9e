//! Facets of the twinned interface row: pre-crack facets (free faces from the start), cohesive
//! facets (tied until inserted) and plain facets (never open), docs/fem-model.md §3.1.

use super::structured::Grid;
use nalgebra::Vector2;

/// What a facet of the interface row is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FacetKind {
    /// Pre-crack: two free faces from t = 0 (paper Γ1, Γ2).
    PreCrack,
    /// Cohesive interface: candidate for extrinsic insertion.
    Cohesive,
    /// Not on any interface: its twins stay tied for ever.
    Plain,
}

/// The facets of the twinned row, facet c between columns c and c+1.
#[derive(Debug, Clone)]
pub(crate) struct InterfaceRow {
    /// Kind of each facet.
    pub kind: Vec<FacetKind>,
    /// − copy of each column's node.
    pub minus: Vec<u32>,
    /// + copy of each column's node.
    pub plus: Vec<u32>,
    /// Element below each facet (− side).
    pub elem_minus: Vec<u32>,
    /// Element above each facet (+ side).
    pub elem_plus: Vec<u32>,
    /// Local edge of the facet in its (+, −) elements (joining their nodes k and k + 1).
    pub face_edges: Vec<[u8; 2]>,
    /// Reference length L₀ of each facet [m].
    pub length: Vec<f64>,
    /// Reference unit normal (− → +) of each facet [-].
    pub normal: Vec<Vector2<f64>>,
    /// Interface coordinate of each column [m], increasing along the row: x on the built-in
    /// grids; the arc length from the row's first node, plus that node's x, on a Gmsh mesh (so
    /// that it is x on a straight interface along +x). Tips and interface records are given in it.
    pub coord: Vec<f64>,
}

impl InterfaceRow {
    /// Classifies the facets of the twinned row: pre-crack where the facet midpoint satisfies
    /// |x − x_c| < a, cohesive elsewhere if `cohesive` is set, plain otherwise.
    pub fn new(grid: &Grid, crack: Option<(f64, f64)>, cohesive: bool) -> Option<InterfaceRow> {
        let row = grid.twinned_row?;
        let nx = grid.nx;
        let lm = grid.upper_layer[row] - 1;
        let lp = grid.upper_layer[row];
        let minus: Vec<u32> = (0..=nx).map(|i| grid.node(lm, i)).collect();
        let plus: Vec<u32> = (0..=nx).map(|i| grid.node(lp, i)).collect();
        let mut out = InterfaceRow {
            kind: Vec::with_capacity(nx),
            minus,
            plus,
            elem_minus: (0..nx).map(|c| ((row - 1) * nx + c) as u32).collect(),
            elem_plus: (0..nx).map(|c| (row * nx + c) as u32).collect(),
            // the facet is the bottom edge of the + element, the top edge of the − one
            face_edges: vec![[0, 2]; nx],
            length: Vec::with_capacity(nx),
            normal: Vec::with_capacity(nx),
            coord: Vec::new(),
        };
        out.coord = out.minus.iter().map(|&n| grid.x0[n as usize].x).collect();
        for c in 0..nx {
            let (xa, xb) = (grid.x0[out.minus[c] as usize], grid.x0[out.minus[c + 1] as usize]);
            let mid = 0.5 * (xa.x + xb.x);
            let pre = crack.is_some_and(|(xc, a)| (mid - xc).abs() < a);
            out.kind.push(if pre {
                FacetKind::PreCrack
            } else if cohesive {
                FacetKind::Cohesive
            } else {
                FacetKind::Plain
            });
            let t = xb - xa;
            out.length.push(t.norm());
            out.normal.push(Vector2::new(-t.y, t.x) / t.norm());
        }
        Some(out)
    }

    /// Number of facets.
    pub fn num_facets(&self) -> usize {
        self.kind.len()
    }

    /// Number of facets that are pre-crack or cohesive (can ever be free faces).
    pub fn num_interface_facets(&self) -> usize {
        self.kind.iter().filter(|k| **k != FacetKind::Plain).count()
    }
}
