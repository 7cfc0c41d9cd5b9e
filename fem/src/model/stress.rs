//! Bulk stresses sampled where the interface and the outputs need them: on either side of an
//! interface facet (insertion, paper App. A; Section 4 diagnostics) and per element (snapshots).
//! σ = D B u_e with B of the element's shape functions (docs/fem-model.md §1): the Gauss-point
//! stresses of a Q4, extrapolated bilinearly to the facet; the constant stress of a T3.

use crate::mesh::interfaces::InterfaceRow;
use crate::model::bulk;
use crate::model::face_stress::{FaceStress, face_of};
use crate::model::state::Model;
use nalgebra::Vector2;

/// Which element of a facet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    /// The element on the + side (left of the row's direction from column c to c + 1).
    Plus,
    /// The element on the − side.
    Minus,
}

/// Displacements [m] of element e's nodes (the 4th is zero on a T3).
fn element_displacements(model: &Model, e: usize, u: &[Vector2<f64>]) -> [Vector2<f64>; 4] {
    let mut out = [Vector2::zeros(); 4];
    for (o, &n) in out.iter_mut().zip(model.element_nodes(e).as_slice()) {
        *o = u[n as usize];
    }
    out
}

/// Stress [σ_xx, σ_yy, σ_xy] [Pa] of facet c's element on `side` at the facet points s ∈ [−1, 1]
/// (s = −1 at column c, +1 at column c + 1).
pub(crate) fn facet_side<const N: usize>(
    model: &Model,
    row: &InterfaceRow,
    c: usize,
    side: Side,
    u: &[Vector2<f64>],
    s: [f64; N],
) -> [[f64; 3]; N] {
    // the facet runs forwards along the + element's edge (the element lies to its left) and
    // backwards along the − element's
    let (e, face, at) = match side {
        Side::Plus => (row.elem_plus[c], &model.interface.facet_faces[c][0], s),
        Side::Minus => (
            row.elem_minus[c],
            &model.interface.facet_faces[c][1],
            s.map(|s| -s),
        ),
    };
    face.sample(
        model.d_of(e as usize),
        &element_displacements(model, e as usize, u),
        at,
    )
}

/// Reference centroid [m] of element e and its mean stress [σ_xx, σ_yy, σ_xy] [Pa]: the mean of
/// the four Gauss-point stresses of a Q4, the constant stress of a T3.
pub(crate) fn element_mean(model: &Model, e: usize, u: &[Vector2<f64>]) -> (Vector2<f64>, [f64; 3]) {
    let nodes = model.element_nodes(e);
    let nodes = nodes.as_slice();
    let centre = nodes
        .iter()
        .map(|&n| model.bulk.x0[n as usize])
        .sum::<Vector2<f64>>()
        / nodes.len() as f64;
    let ue = element_displacements(model, e, u);
    let face = face_of(&model.bulk.x0, nodes, 0);
    let sig = match face {
        FaceStress::T3 { .. } => face.sample(model.d_of(e), &ue, [0.0])[0],
        FaceStress::Q4 { grads, .. } => {
            let sig = bulk::gauss_stresses(&grads, model.d_of(e), &ue);
            sig.map(|p| p.iter().sum::<f64>() / 4.0)
        }
    };
    (centre, sig)
}
