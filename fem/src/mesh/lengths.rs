//! Element lengths of a Gmsh mesh: the h_e of the stable step Δt = α min_e h_e/c_d,e
//! (docs/fem-model.md §2, docs/meshes.md "Several materials").

use crate::mesh::gmsh::{ElementKind, UnstructuredMesh};

/// The smallest element length h_min [m] of `mesh` (the h_min of the stable step, `UnstructuredBulk::min_length`): per
/// element 2A/ℓ_max for a T3 and A/ℓ_max for a Q4 (ℓ_max its longest edge); ∞ for a mesh without
/// elements.
pub fn min_element_length(mesh: &UnstructuredMesh) -> f64 {
    (0..mesh.elements.len())
        .map(|e| element_length(mesh, e))
        .fold(f64::INFINITY, f64::min)
}

/// The length h_e [m] of element `e` of the stable step: 2A/ℓ_max for a T3, A/ℓ_max for a Q4.
pub fn element_length(mesh: &UnstructuredMesh, e: usize) -> f64 {
    let (x, el) = (&mesh.positions, &mesh.elements[e]);
    let c = |k: usize| x[el.nodes[k]];
    let n = el.nodes.len();
    let longest = (0..n).map(|k| (c((k + 1) % n) - c(k)).norm()).fold(0.0, f64::max);
    match el.kind {
        ElementKind::T3 => (c(1) - c(0)).perp(&(c(2) - c(0))) / longest,
        ElementKind::Q4 => 0.5 * ((c(2) - c(0)).perp(&(c(3) - c(1)))) / longest,
    }
}
