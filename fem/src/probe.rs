//! Read-only probes of a built model for validation tests (patch test, energies): they expose
//! assembled quantities, never a verdict.

use crate::model::bulk;
use crate::model::state::{BulkMesh, Model, State, Workspace};
use nalgebra::Vector2;

/// Nodal internal forces −f_int(u) [N/m] for the displacement field `field(X)` [m] evaluated at
/// every node's reference position, plus each node's reference position and whether it lies on
/// the outer boundary.
pub fn internal_forces_for(
    model: &Model,
    field: &dyn Fn(Vector2<f64>) -> Vector2<f64>,
) -> Vec<(Vector2<f64>, bool, Vector2<f64>)> {
    let u: Vec<Vector2<f64>> = model.bulk.x0.iter().map(|&x| field(x)).collect();
    let mut f = vec![Vector2::zeros(); u.len()];
    model.internal_forces(&u, &mut f);
    let grid = model
        .grid()
        .expect("the patch-test probe reads the structured grid's outer boundary");
    (0..u.len())
        .map(|n| (model.bulk.x0[n], grid.on_outer_boundary(n), f[n]))
        .collect()
}

/// Reference positions of the nodes [m].
pub fn reference_positions(model: &Model) -> &[Vector2<f64>] {
    &model.bulk.x0
}

/// Kinetic energy ½ Σ m |v|² [J/m] of a state.
pub fn kinetic_energy(model: &Model, state: &State) -> f64 {
    crate::diag::energy::kinetic(model, state)
}

/// Strain energy [J/m] of the last step run with `sample = true`.
pub fn strain_energy(ws: &Workspace) -> f64 {
    ws.strain_energy
}

/// Whether the model uses one shared element stiffness (identical rectangles).
pub fn shares_stiffness(model: &Model) -> bool {
    matches!(
        model.bulk.mesh,
        BulkMesh::Grid {
            stiffness: bulk::Stiffness::Shared(_),
            ..
        }
    )
}

/// The bulk kernel alone: f = −f_int(u) [N/m] for displacements `u` [m] (benchmarks).
pub fn bulk_forces(model: &Model, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    model.internal_forces(u, f);
}
