//! Internal forces of a mapped structured mesh (paper Section 4): every element has vertical sides
//! and the same width h, only the y coordinates of its corners differ. Then x = x_a + (h/2)(1 + ξ),
//! the Jacobian is lower-triangular and B follows from four numbers per element, so f_int is
//! computed on the fly (about 200 flops per element) instead of streaming a 512-byte K_e per
//! element per step, which made the per-element path memory-bound (docs/fem-model.md §1, same 2×2 Gauss
//! rule and the same discrete operator as K_e u_e, checked to round-off by a test).

use crate::mesh::structured::Grid;
use nalgebra::Vector2;
use rayon::prelude::*;

/// Shape of one vertical-sided element: left and right heights y_d − y_a, y_c − y_b and bottom
/// and top rises y_b − y_a, y_c − y_d [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Trapezoid {
    pub v_left: f64,
    pub v_right: f64,
    pub rise_bottom: f64,
    pub rise_top: f64,
}

impl Trapezoid {
    /// The shape of the element with these corners, if its sides are vertical and its width is
    /// `width` [m] (to 1e-9 relative), else `None`.
    pub fn of(c: &[Vector2<f64>; 4], width: f64) -> Option<Trapezoid> {
        let tol = 1e-9 * width;
        let vertical = (c[3].x - c[0].x).abs() <= tol && (c[2].x - c[1].x).abs() <= tol;
        let wide = ((c[1].x - c[0].x) - width).abs() <= tol && ((c[2].x - c[3].x) - width).abs() <= tol;
        (vertical && wide).then(|| Trapezoid {
            v_left: c[3].y - c[0].y,
            v_right: c[2].y - c[1].y,
            rise_bottom: c[1].y - c[0].y,
            rise_top: c[2].y - c[3].y,
        })
    }
}

/// Mapped-mesh stiffness: element width h [m], the elasticity matrix D [Pa] and one shape per element.
#[derive(Debug, Clone)]
pub(crate) struct MappedStiffness {
    /// x_ξ = h/2 [m].
    pub half_width: f64,
    /// Plane-strain D [Pa].
    pub d: [[f64; 3]; 3],
    /// Gauss constants of each element, element order.
    pub shapes: Vec<GaussShape>,
}

/// Per-element constants of the 2×2 Gauss rule: y_η at ξ = ∓g, 1/y_η there, and y_ξ at η = ∓g
/// (g = 1/√3), with x_ξ = h/2 shared by every element [m, 1/m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GaussShape {
    y_eta: [f64; 2],
    inv_y_eta: [f64; 2],
    y_xi: [f64; 2],
}

impl GaussShape {
    /// The constants of a trapezoid.
    pub fn of(s: &Trapezoid) -> GaussShape {
        let g = 1.0 / 3f64.sqrt();
        let y_eta = [-g, g].map(|xi| 0.25 * (s.v_left * (1.0 - xi) + s.v_right * (1.0 + xi)));
        GaussShape {
            y_eta,
            inv_y_eta: y_eta.map(|v| 1.0 / v),
            y_xi: [-g, g].map(|eta| 0.25 * (s.rise_bottom * (1.0 - eta) + s.rise_top * (1.0 + eta))),
        }
    }
}

/// f_e = K_e u_e of one vertical-sided element [N/m], 2×2 Gauss. With the edge differences
/// U_ξ(η) = ¼[(1−η)(u₁−u₀) + (1+η)(u₂−u₃)] and U_η(ξ) = ¼[(1−ξ)(u₃−u₀) + (1+ξ)(u₂−u₁)]:
/// ∂u/∂y = U_η / y_η, ∂u/∂x = (U_ξ − y_ξ ∂u/∂y)/x_ξ, σ = D ε, and Bᵀσ det J (det J = x_ξ y_η)
/// is N_a,ξ P + N_a,η Q with P = y_η (σ_xx, σ_xy), Q = x_ξ (σ_xy, σ_yy) − y_ξ (σ_xx, σ_xy);
/// the sums over Gauss points are gathered per edge before the scatter (about 150 flops).
#[inline(always)]
pub(crate) fn element_forces(
    s: &GaussShape,
    x_xi: f64,
    d: &[[f64; 3]; 3],
    ue: &[Vector2<f64>; 4],
) -> [Vector2<f64>; 4] {
    let g = 1.0 / 3f64.sqrt();
    let w = [0.25 * (1.0 + g), 0.25 * (1.0 - g)]; // ¼(1 ∓ (∓g)): weight of the near / far edge
    let (db, dt) = (ue[1] - ue[0], ue[2] - ue[3]);
    let (dl, dr) = (ue[3] - ue[0], ue[2] - ue[1]);
    // index 0: η (or ξ) = −g, index 1: +g
    let u_xi = [w[0] * db + w[1] * dt, w[1] * db + w[0] * dt];
    let u_eta = [w[0] * dl + w[1] * dr, w[1] * dl + w[0] * dr];
    let inv_x_xi = 1.0 / x_xi;
    let (mut p_sum, mut q_sum) = ([Vector2::zeros(); 2], [Vector2::zeros(); 2]);
    for (je, y_xi) in s.y_xi.iter().enumerate() {
        for ix in 0..2 {
            let du_dy = u_eta[ix] * s.inv_y_eta[ix];
            let du_dx = (u_xi[je] - *y_xi * du_dy) * inv_x_xi;
            let eps = [du_dx.x, du_dy.y, du_dy.x + du_dx.y];
            let sxx = d[0][0] * eps[0] + d[0][1] * eps[1] + d[0][2] * eps[2];
            let syy = d[1][0] * eps[0] + d[1][1] * eps[1] + d[1][2] * eps[2];
            let sxy = d[2][0] * eps[0] + d[2][1] * eps[1] + d[2][2] * eps[2];
            p_sum[je] += s.y_eta[ix] * Vector2::new(sxx, sxy);
            q_sum[ix] += x_xi * Vector2::new(sxy, syy) - *y_xi * Vector2::new(sxx, sxy);
        }
    }
    // N_a,ξ = ¼ ξ_a (1 + η η_a), N_a,η = ¼ η_a (1 + ξ ξ_a)
    let pb = w[0] * p_sum[0] + w[1] * p_sum[1];
    let pt = w[1] * p_sum[0] + w[0] * p_sum[1];
    let ql = w[0] * q_sum[0] + w[1] * q_sum[1];
    let qr = w[1] * q_sum[0] + w[0] * q_sum[1];
    [-pb - ql, pb - qr, pt + qr, -pt + ql]
}

/// f = −f_int(u) (overwrites `f`). Element rows are processed in two passes, those whose lower
/// node layer is even, then odd: within a pass the rows write disjoint layer pairs, so the
/// parallel scatter has no race and needs no atomics.
pub(crate) fn internal_forces(grid: &Grid, k: &MappedStiffness, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    let nx = grid.nx;
    let w = nx + 1;
    f.par_iter_mut().for_each(|v| *v = Vector2::zeros());
    for parity in [0usize, 1] {
        let (_, tail) = f.split_at_mut(parity * w);
        tail.par_chunks_mut(2 * w).enumerate().for_each(|(k2, pair)| {
            let lower = parity + 2 * k2;
            if pair.len() < 2 * w {
                return;
            }
            let Some(r) = grid.layer_element_rows(lower).1 else {
                return;
            };
            let (lo, hi) = pair.split_at_mut(w);
            let layer = grid.upper_layer[r];
            let (ul, uh) = (
                &u[layer * w..(layer + 1) * w],
                &u[(layer + 1) * w..(layer + 2) * w],
            );
            let shapes = &k.shapes[r * nx..(r + 1) * nx];
            for (c, shape) in shapes.iter().enumerate() {
                let ue = [ul[c], ul[c + 1], uh[c + 1], uh[c]];
                let fe = element_forces(shape, k.half_width, &k.d, &ue);
                lo[c] -= fe[0];
                lo[c + 1] -= fe[1];
                hi[c + 1] -= fe[2];
                hi[c] -= fe[3];
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::bulk;

    #[test]
    fn matches_k_e_times_u_on_distorted_elements() {
        let d = crate::law::elastic::PlaneStrain::new(7e6, 0.35, 1230.0).d_matrix();
        let h = 1e-3;
        // a square, a sheared parallelogram (slope π/2, the sinusoid's steepest) and a trapezoid
        let shapes = [
            [(0.0, 0.0), (h, 0.0), (h, h), (0.0, h)],
            [(0.0, 0.0), (h, 1.571 * h), (h, 2.571 * h), (0.0, h)],
            [(0.0, 0.1 * h), (h, -0.4 * h), (h, 0.35 * h), (0.0, 0.8 * h)],
        ];
        let ue = [(1.0, -2.0), (0.5, 0.25), (-1.5, 3.0), (2.0, 0.75)].map(|(x, y)| Vector2::new(x, y) * 1e-4);
        for corners in shapes {
            let c = corners.map(|(x, y)| Vector2::new(x + 0.3, y - 0.2));
            let ke = bulk::stiffness(&c, &d).unwrap();
            let shape = Trapezoid::of(&c, h).expect("vertical sides");
            let f = element_forces(&GaussShape::of(&shape), 0.5 * h, &d, &ue);
            let scale: f64 = (0..8).map(|i| ke[i][i]).fold(0.0, f64::max) * 1e-4;
            for a in 0..4 {
                for comp in 0..2 {
                    let expect: f64 = (0..4)
                        .map(|b| ke[2 * a + comp][2 * b] * ue[b].x + ke[2 * a + comp][2 * b + 1] * ue[b].y)
                        .sum();
                    let got = if comp == 0 { f[a].x } else { f[a].y };
                    assert!((got - expect).abs() <= 1e-12 * scale, "{got} vs {expect}");
                }
            }
        }
        assert!(
            Trapezoid::of(
                &[(0.0, 0.0), (h, 0.0), (1.2 * h, h), (0.0, h)].map(|(x, y)| Vector2::new(x, y)),
                h
            )
            .is_none()
        );
    }
}
