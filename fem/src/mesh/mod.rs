//! The meshes the solver runs on: the structured Q4 grid with its twinned interface row, and Gmsh
//! meshes (read, their interface chains split into twins, prepared with their roles).

use nalgebra::Vector2;

pub mod gmsh;

pub(crate) mod interfaces;
pub mod lengths;
pub mod prepared;
pub(crate) mod structured;

/// Index of the node of `positions` [m] nearest to `p` [m] (the smallest index on a tie; 0 for no
/// nodes): where a probe point records.
pub(crate) fn nearest_node(positions: &[Vector2<f64>], p: Vector2<f64>) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (n, x) in positions.iter().enumerate() {
        let d = (x - p).norm_squared();
        if d < best.0 {
            best = (d, n);
        }
    }
    best.1
}
