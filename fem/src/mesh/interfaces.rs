//! Facets of the twinned interface row: pre-crack facets (free faces from the start), cohesive
//! facets (tied until inserted) and plain facets (never open), docs/fem-model.md §3.1.
//!
//! One row holds every interface chain of the body: the columns of chain 0, then those of chain
//! 1, …; a facet joins the two columns in [`InterfaceRow::ends`] (c and c + 1 along a chain, the
//! last and the first column of a closed chain for its closing facet), so that consecutive
//! columns of two chains share no facet (docs/meshes.md, "Several chains").

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

impl FacetKind {
    /// The kind of the grid's facet whose midpoint lies at x = `mid` [m]: pre-crack where
    /// |mid − x_c| < a for `crack` = (x_c, a) [m], cohesive elsewhere if `cohesive` is set (an
    /// `[interface]` is given), plain otherwise.
    pub(crate) fn of_grid_facet(mid: f64, crack: Option<(f64, f64)>, cohesive: bool) -> FacetKind {
        if crack.is_some_and(|(xc, a)| (mid - xc).abs() < a) {
            FacetKind::PreCrack
        } else if cohesive {
            FacetKind::Cohesive
        } else {
            FacetKind::Plain
        }
    }
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
    /// Each chain has its own: a chain's coordinate runs from its own first column.
    pub coord: Vec<f64>,
    /// Columns at the start and the end of each facet [-].
    pub ends: Vec<[u32; 2]>,
    /// Per column: the facet that ends at it and the facet that starts at it ([`NO_FACET`] at
    /// a chain's end) [-].
    pub col_facets: Vec<[u32; 2]>,
    /// Chain of each column (0, 1, … in the order the chains are stored) [-].
    pub chain: Vec<u16>,
    /// The columns of each junction (a node where three or more chains end, split into one copy
    /// per sector): each column's − and + nodes are copies of that node [-].
    pub junctions: Vec<Vec<u32>>,
    /// Per column: its junction ([`NO_JUNCTION`]: none) [-].
    pub col_junction: Vec<u32>,
}

/// "No junction" in [`InterfaceRow::col_junction`].
pub(crate) const NO_JUNCTION: u32 = u32::MAX;

/// "No facet" in [`InterfaceRow::col_facets`].
pub(crate) const NO_FACET: u32 = u32::MAX;

impl InterfaceRow {
    /// Classifies the facets of the twinned row ([`FacetKind::of_grid_facet`]).
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
            ends: (0..nx as u32).map(|c| [c, c + 1]).collect(),
            col_facets: Vec::new(),
            chain: vec![0; nx + 1],
            junctions: Vec::new(),
            col_junction: vec![NO_JUNCTION; nx + 1],
        };
        out.col_facets = column_facets(nx + 1, &out.ends);
        out.coord = out.minus.iter().map(|&n| grid.x0[n as usize].x).collect();
        for c in 0..nx {
            let (xa, xb) = (grid.x0[out.minus[c] as usize], grid.x0[out.minus[c + 1] as usize]);
            out.kind
                .push(FacetKind::of_grid_facet(0.5 * (xa.x + xb.x), crack, cohesive));
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

    /// Number of chains.
    pub fn num_chains(&self) -> usize {
        self.chain.last().map_or(0, |&k| k as usize + 1)
    }

    /// Columns at the start and the end of facet c.
    pub fn facet_columns(&self, c: usize) -> [usize; 2] {
        self.ends[c].map(|i| i as usize)
    }

    /// The facets (one or two) that touch column i.
    pub fn column_facets(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        self.col_facets[i]
            .into_iter()
            .filter(|&c| c != NO_FACET)
            .map(|c| c as usize)
    }

    /// Interface coordinates [m] of the start and end of facet c: those of its columns, except
    /// on the closing facet of a closed chain, whose end is its start plus its length.
    pub fn facet_span(&self, c: usize) -> [f64; 2] {
        let [a, b] = self.facet_columns(c);
        let sa = self.coord[a];
        [sa, if b > a { self.coord[b] } else { sa + self.length[c] }]
    }

    /// Whether facet `next` continues facet `prev` along their chain (the end column of `prev`
    /// is the start column of `next`).
    pub fn continues(&self, prev: usize, next: usize) -> bool {
        self.ends[prev][1] == self.ends[next][0]
    }
}

/// Per column, the facet ending at it and the facet starting at it ([`NO_FACET`]: none).
pub(crate) fn column_facets(num_columns: usize, ends: &[[u32; 2]]) -> Vec<[u32; 2]> {
    let mut out = vec![[NO_FACET; 2]; num_columns];
    for (c, [a, b]) in ends.iter().enumerate() {
        out[*a as usize][1] = c as u32;
        out[*b as usize][0] = c as u32;
    }
    out
}

/// Whether column i's twins are tied: some incident facet is neither inserted nor pre-crack (§3.1).
pub(crate) fn column_tied(row: &InterfaceRow, inserted: &[bool], i: usize) -> bool {
    row.column_facets(i).any(|c| match row.kind[c] {
        FacetKind::PreCrack => false,
        FacetKind::Plain => true,
        FacetKind::Cohesive => !inserted[c],
    })
}

/// Ties the copies of junction j (docs/meshes.md, "Several chains"): the copies joined through
/// tied columns (a closed facet at the junction joins its column's − and + copies) form one tie
/// group, a ring in `tied_twin` (each copy names the next; a copy alone is untied). A pair is the
/// ring of two, the same as a twin pair's tie. Allocates nothing.
pub(crate) fn tie_junction(row: &InterfaceRow, inserted: &[bool], j: usize, tied_twin: &mut [u32]) {
    let cols = &row.junctions[j];
    for &i in cols {
        let i = i as usize;
        tied_twin[row.minus[i] as usize] = row.minus[i];
        tied_twin[row.plus[i] as usize] = row.plus[i];
    }
    for &i in cols {
        let i = i as usize;
        let (a, b) = (row.minus[i] as usize, row.plus[i] as usize);
        if column_tied(row, inserted, i) && !in_ring(tied_twin, a, b as u32) {
            // splicing two rings at a and b makes one
            tied_twin.swap(a, b);
        }
    }
    for &i in cols {
        for n in [row.minus[i as usize], row.plus[i as usize]] {
            if tied_twin[n as usize] == n {
                tied_twin[n as usize] = u32::MAX;
            }
        }
    }
}

/// Whether node b is in the tie ring of node a (a tied pair: b is a's twin).
pub(crate) fn in_ring(tied_twin: &[u32], a: usize, b: u32) -> bool {
    let mut t = tied_twin[a];
    while t != u32::MAX && t != a as u32 {
        if t == b {
            return true;
        }
        t = tied_twin[t as usize];
    }
    false
}
