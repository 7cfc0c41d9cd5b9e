//! How one element's stress is sampled on one of its edges (an interface facet): the data kept
//! per facet side at build (the Q4's Gauss-point gradients and local edge, or the T3's constant
//! gradients) and the sampling itself, σ = D B u_e (docs/fem-model.md §1).

use crate::model::bulk;
use nalgebra::Vector2;

/// How the stress of one of a facet's two elements is sampled on the facet.
#[derive(Debug, Clone, Copy)]
// one per side of each interface facet, read every step by the insertion check: inline data, the
// 208 bytes a T3 leaves unused are a few hundred kB on the largest meshes
#[allow(clippy::large_enum_variant)]
pub(crate) enum FaceStress {
    /// Q4: the Gauss-point stresses extrapolated bilinearly to the facet, which is the element's
    /// local edge `edge` (joining its nodes `edge` and `edge + 1`).
    Q4 {
        /// Shape-function gradients at the four Gauss points [1/m].
        grads: bulk::GaussGradients,
        /// Local edge on the facet.
        edge: u8,
    },
    /// T3: the constant stress of the element.
    T3 {
        /// Constant shape-function gradients [1/m].
        grads: [Vector2<f64>; 3],
    },
}

impl FaceStress {
    /// Stress [σ_xx, σ_yy, σ_xy] [Pa] at the points e ∈ [−1, 1] of the facet (running from the
    /// element's node `edge` to `edge + 1`) for the element displacements `ue` [m].
    pub(crate) fn sample<const N: usize>(
        &self,
        d: &[[f64; 3]; 3],
        ue: &[Vector2<f64>; 4],
        at: [f64; N],
    ) -> [[f64; 3]; N] {
        match self {
            FaceStress::Q4 { grads, edge } => {
                let sig = bulk::gauss_stresses(grads, d, ue);
                at.map(|e| {
                    // natural coordinates of the point of local edge `edge`, corners in the order
                    // (−1, −1), (1, −1), (1, 1), (−1, 1)
                    let (xi, eta) = match edge {
                        0 => (e, -1.0),
                        1 => (1.0, e),
                        2 => (-e, 1.0),
                        _ => (-1.0, -e),
                    };
                    bulk::extrapolate(&sig, xi, eta)
                })
            }
            FaceStress::T3 { grads } => {
                let mut eps = [0.0; 3];
                for a in 0..3 {
                    eps[0] += grads[a].x * ue[a].x;
                    eps[1] += grads[a].y * ue[a].y;
                    eps[2] += grads[a].y * ue[a].x + grads[a].x * ue[a].y;
                }
                let sig = [0, 1, 2].map(|p| d[p][0] * eps[0] + d[p][1] * eps[1] + d[p][2] * eps[2]);
                at.map(|_| sig)
            }
        }
    }
}

/// Constant shape-function gradients ∇N_i = (y_j − y_k, x_k − x_j)/(2A) of a counter-clockwise
/// triangle, (i, j, k) cyclic [1/m].
pub(crate) fn t3_gradients(c: &[Vector2<f64>; 3]) -> [Vector2<f64>; 3] {
    let two_a = (c[1] - c[0]).perp(&(c[2] - c[0]));
    [0, 1, 2].map(|i| {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        Vector2::new(c[j].y - c[k].y, c[k].x - c[j].x) / two_a
    })
}

/// How facet c's elements are sampled: the Q4 gradients and local edge, or the T3 gradients.
pub(crate) fn face_of(x0: &[Vector2<f64>], nodes: &[u32], edge: usize) -> FaceStress {
    let x = |k: usize| x0[nodes[k] as usize];
    match nodes.len() {
        3 => FaceStress::T3 {
            grads: t3_gradients(&[x(0), x(1), x(2)]),
        },
        _ => FaceStress::Q4 {
            grads: bulk::gauss_gradients(&[x(0), x(1), x(2), x(3)]),
            edge: edge as u8,
        },
    }
}
