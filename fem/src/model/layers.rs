//! Which node layers the one-pass sweep of unsampled steps (`solver::sweep`) may advance, which
//! chunks of nodes the corrector may fuse with the next predictor, and the sweep's scratch,
//! allocated with the model.

use crate::mesh::interfaces::InterfaceRow;
use crate::mesh::structured::{Grid, LayerSide};

/// Layers per band: 16 bands on the paper's centre crack (252 layers), enough for any core count
/// of a workstation to share out, and the halo copies stay small (2 rows per band).
pub(crate) const BAND: usize = 16;

/// Nodes per chunk of the corrector on a Gmsh mesh (the grid's chunks are its layers).
pub(crate) const CHUNK: usize = 1024;

/// Per chunk of the corrector (`width` nodes, the last one possibly shorter): whether it holds a
/// node of the interface row. Such a chunk keeps its corrector and the next step's predictor as
/// two passes, since the velocity damping and the next step's first read (the row's displacements,
/// kept for the contact work) see the row's state between the two; every other chunk may take both
/// in one pass on unsampled steps.
pub(crate) fn apart_chunks(num_nodes: usize, width: usize, row: Option<&InterfaceRow>) -> Vec<bool> {
    let mut apart = vec![false; num_nodes.div_ceil(width)];
    if let Some(row) = row {
        for &n in row.minus.iter().chain(&row.plus) {
            apart[n as usize / width] = true;
        }
    }
    apart
}

/// Layers whose nodes must keep u_{n+1}, v_{n+1} until after contact and insertion: the two
/// layers of the interface and their neighbours (the insertion check reads the stresses of the
/// elements next to the interface), the bottom and top layers, and every layer holding a
/// prescribed DOF, a Neumann force or a dashpot off its edges.
pub(crate) fn deferred_layers(grid: &Grid, fixed_dof: &[[bool; 2]], neumann_nodes: &[u32]) -> Vec<bool> {
    let layers = grid.layer_side.len();
    let w = grid.nx + 1;
    let mut deferred = vec![false; layers];
    deferred[0] = true;
    deferred[layers - 1] = true;
    for (layer, side) in grid.layer_side.iter().enumerate() {
        match side {
            LayerSide::Single => {}
            LayerSide::Minus => {
                deferred[layer] = true;
                deferred[layer.saturating_sub(1)] = true;
            }
            LayerSide::Plus => {
                deferred[layer] = true;
                deferred[(layer + 1).min(layers - 1)] = true;
            }
        }
    }
    for (n, fixed) in fixed_dof.iter().enumerate() {
        let i = n % w;
        if (fixed[0] || fixed[1]) && i != 0 && i != w - 1 {
            deferred[n / w] = true;
        }
    }
    // a load or dashpot on an edge node needs nothing more: the sweep leaves every edge node
    // to the corrector pass (a box loaded and absorbing on its left and right sides keeps the sweep)
    for &n in neumann_nodes {
        let i = n as usize % w;
        if i != 0 && i != w - 1 {
            deferred[n as usize / w] = true;
        }
    }
    deferred
}

/// The scratch of the sweep, allocated at build: per band, copies of the two layers it reads
/// from its neighbours, two rows of forces and, on a mapped mesh, the element forces of two
/// element rows; per layer, whether the sweep advanced it.
#[derive(Debug, Clone)]
pub(crate) struct SweepBuffers {
    /// Per band: copies of the layer below it and of the layer above it [m].
    pub(crate) halo: Vec<f64>,
    /// Per band: two rows of scratch forces [N/m].
    pub(crate) ring: Vec<f64>,
    /// Per band, on a mapped mesh: the element forces of two element rows
    /// (`model::mapped::row_forces`) [N/m] (on a grid with a shared K_e, allocated and never
    /// touched).
    pub(crate) element_rows: Vec<f64>,
    /// Per layer: its interior nodes were advanced by the sweep of this step.
    pub(crate) done: Vec<bool>,
}

impl SweepBuffers {
    /// Buffers for `grid`.
    pub(crate) fn new(grid: &Grid) -> SweepBuffers {
        let layers = grid.layer_side.len();
        let bands = layers.div_ceil(BAND);
        let row = 2 * (grid.nx + 1);
        SweepBuffers {
            halo: vec![0.0; bands * 2 * row],
            ring: vec![0.0; bands * 2 * row],
            element_rows: vec![0.0; bands * 2 * crate::model::mapped::row_len(grid.nx)],
            done: vec![false; layers],
        }
    }

    /// No sweep (a Gmsh mesh): the corrector runs over `chunks` chunks of nodes, none done.
    pub(crate) fn none(chunks: usize) -> SweepBuffers {
        SweepBuffers {
            halo: Vec::new(),
            ring: Vec::new(),
            element_rows: Vec::new(),
            done: vec![false; chunks],
        }
    }
}
