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

/// The mapped kernel alone, on the calling thread: every element row's element forces (each
/// corner's internal force f_e [N/m], which −f_int subtracts) computed from displacements `u` [m]
/// into one row buffer in turn, neither summed into the nodes nor kept (benchmarks: the kernel
/// against its multiplies). Returns the number of elements computed, or `None` when the model is
/// not on a mapped mesh.
pub fn mapped_element_forces(model: &Model, u: &[Vector2<f64>], row: &mut Vec<f64>) -> Option<usize> {
    let BulkMesh::Grid {
        grid,
        stiffness: bulk::Stiffness::Mapped(k),
    } = &model.bulk.mesh
    else {
        return None;
    };
    let flat: &[f64] = bytemuck::cast_slice(u);
    row.resize(crate::model::mapped::row_len(grid.nx), 0.0);
    for r in 0..grid.ny {
        let (lower, upper) = crate::model::mapped::row_layers(grid, flat, r);
        crate::model::mapped::row_forces(k, r, lower, upper, row);
    }
    Some(grid.num_elements())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The probe computes the element forces of the rows the model's own pass computes: the last
    /// row's, the only forces on the top layer's nodes, sum to those nodes' −f_int to the bit. It
    /// fails if the probe reads another row's displacement layers.
    #[test]
    fn the_kernel_probe_gives_the_top_layer_the_forces_of_the_model() {
        let text = crate::test_scenes::scene_text("tiny-fem-rough-interface");
        let scene = crate::scene::Scene::from_toml_str(&text).unwrap();
        let (model, _, _) = crate::build(&scene).unwrap();
        let u: Vec<Vector2<f64>> = (0..model.num_nodes())
            .map(|i| Vector2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()) * 1e-6)
            .collect();
        let mut f = vec![Vector2::zeros(); u.len()];
        model.internal_forces(&u, &mut f);
        let mut row = Vec::new();
        let elements = mapped_element_forces(&model, &u, &mut row).expect("a mapped mesh");
        let grid = model.grid().unwrap();
        assert_eq!(elements, grid.nx * grid.ny);
        // element e's corner a, component c, in the row buffer; corners 2 and 3 act on the top
        let stride = row.len() / 8;
        let at = |e: usize, a: usize, c: usize| row[(2 * a + c) * stride + e];
        let top = grid.upper_layer[grid.ny - 1] + 1;
        for i in 0..=grid.nx {
            let mut expected = [0.0; 2];
            for (c, v) in expected.iter_mut().enumerate() {
                if i > 0 {
                    *v -= at(i - 1, 2, c);
                }
                if i < grid.nx {
                    *v -= at(i, 3, c);
                }
            }
            let n = grid.node(top, i) as usize;
            assert_eq!([f[n].x, f[n].y], expected, "top node {i}");
        }
        let plain = crate::test_scenes::scene_text("tiny-fem-plate");
        let (square, _, _) = crate::build(&crate::scene::Scene::from_toml_str(&plain).unwrap()).unwrap();
        assert!(
            mapped_element_forces(&square, &vec![Vector2::zeros(); square.num_nodes()], &mut row).is_none()
        );
    }
}
