//! Internal forces of a mapped structured mesh (paper Section 4): every element has vertical sides
//! and the same width h, only the y coordinates of its corners differ. Then x = x_a + (h/2)(1 + ξ),
//! the Jacobian is lower-triangular and B follows from four numbers per element, so f_int is
//! computed on the fly (about 200 flops per element) instead of streaming a 512-byte K_e per
//! element per step, which made the per-element path memory-bound (fem-method §1, same 2×2 Gauss
//! rule and the same discrete operator as K_e u_e, checked to round-off by a test).

use crate::mesh::structured::Grid;
use nalgebra::Vector2;
use rayon::prelude::*;

/// Corner signs (ξ_a, η_a) counter-clockwise from the bottom-left corner.
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

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
    /// Element shapes, element order.
    pub shapes: Vec<Trapezoid>,
}

/// f_e = K_e u_e of one vertical-sided element [N/m], 2×2 Gauss:
/// with U_ξ = Σ N_a,ξ u_a and U_η = Σ N_a,η u_a, ∂u/∂y = U_η / y_η and ∂u/∂x = (U_ξ − y_ξ ∂u/∂y)/x_ξ;
/// then f_a += N_a,ξ P + N_a,η Q, P = y_η (σ_xx, σ_xy), Q = x_ξ (σ_xy, σ_yy) − y_ξ (σ_xx, σ_xy)
/// (that is Bᵀσ det J with det J = x_ξ y_η).
#[inline(always)]
pub(crate) fn element_forces(
    s: &Trapezoid,
    x_xi: f64,
    d: &[[f64; 3]; 3],
    ue: &[Vector2<f64>; 4],
) -> [Vector2<f64>; 4] {
    let g = 1.0 / 3f64.sqrt();
    let mut f = [Vector2::zeros(); 4];
    for (s_k, t_k) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let (xi, eta) = (s_k * g, t_k * g);
        let y_xi = 0.25 * (s.rise_bottom * (1.0 - eta) + s.rise_top * (1.0 + eta));
        let y_eta = 0.25 * (s.v_left * (1.0 - xi) + s.v_right * (1.0 + xi));
        let mut dn = [(0.0, 0.0); 4];
        let (mut u_xi, mut u_eta) = (Vector2::zeros(), Vector2::zeros());
        for (a, &(xa, ea)) in CORNERS.iter().enumerate() {
            dn[a] = (0.25 * xa * (1.0 + eta * ea), 0.25 * ea * (1.0 + xi * xa));
            u_xi += dn[a].0 * ue[a];
            u_eta += dn[a].1 * ue[a];
        }
        let du_dy = u_eta / y_eta;
        let du_dx = (u_xi - y_xi * du_dy) / x_xi;
        let eps = [du_dx.x, du_dy.y, du_dy.x + du_dx.y];
        let sig = [0, 1, 2].map(|p| d[p][0] * eps[0] + d[p][1] * eps[1] + d[p][2] * eps[2]);
        let p = y_eta * Vector2::new(sig[0], sig[2]);
        let q = x_xi * Vector2::new(sig[2], sig[1]) - y_xi * Vector2::new(sig[0], sig[2]);
        for a in 0..4 {
            f[a] += dn[a].0 * p + dn[a].1 * q;
        }
    }
    f
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
            for c in 0..nx {
                let e = r * nx + c;
                let ue = grid.element_nodes(e).map(|n| u[n as usize]);
                let fe = element_forces(&k.shapes[e], k.half_width, &k.d, &ue);
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
            let f = element_forces(&shape, 0.5 * h, &d, &ue);
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
