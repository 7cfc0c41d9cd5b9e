//! Q4 plane-strain element, 2×2 Gauss (fem-method §1): pure kernels, and the race-free rayon
//! driver of the internal forces (each node gathers from its ≤ 4 elements; no shared writes).

use crate::mesh::structured::Grid;
use nalgebra::{Matrix2, Vector2};
use rayon::prelude::*;

/// Element stiffness K_e [N/m per m] (8×8, DOF order x₀, y₀, x₁, y₁, …).
pub(crate) type Ke = [[f64; 8]; 8];

/// Gauss point signs (s_k, t_k), natural coordinates (s_k, t_k)/√3, weights 1.
pub(crate) const GAUSS_SIGNS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// Stiffness storage: one shared K_e for identical rectangles, one per element otherwise.
#[derive(Debug, Clone)]
pub(crate) enum Stiffness {
    /// All elements share this matrix.
    Shared(Box<Ke>),
    /// One matrix per element.
    PerElement(Vec<Ke>),
}

impl Stiffness {
    #[inline]
    fn get(&self, e: usize) -> &Ke {
        match self {
            Stiffness::Shared(k) => k,
            Stiffness::PerElement(v) => &v[e],
        }
    }
}

/// Shape-function gradients ∇_X N_a and det J at natural point (ξ, η).
pub(crate) fn shape_gradients(c: &[Vector2<f64>; 4], xi: f64, eta: f64) -> ([Vector2<f64>; 4], f64) {
    let mut dn = [Vector2::zeros(); 4];
    let mut j = Matrix2::zeros();
    for (a, &(xa, ea)) in CORNERS.iter().enumerate() {
        dn[a] = Vector2::new(0.25 * xa * (1.0 + eta * ea), 0.25 * ea * (1.0 + xi * xa));
        // J_ij = ∂X_i/∂ξ_j
        j += c[a] * dn[a].transpose();
    }
    let det = j.determinant();
    let jinv_t = j.try_inverse().unwrap_or_else(Matrix2::zeros).transpose();
    (dn.map(|g| jinv_t * g), det)
}

/// K_e = Σ_q B_qᵀ D B_q det J_q; Err(det J) if an element is inverted.
pub(crate) fn stiffness(c: &[Vector2<f64>; 4], d: &[[f64; 3]; 3]) -> Result<Ke, f64> {
    let g = 1.0 / 3f64.sqrt();
    let mut k = [[0.0; 8]; 8];
    for &(s, t) in &GAUSS_SIGNS {
        let (grads, det) = shape_gradients(c, s * g, t * g);
        if det <= 0.0 || !det.is_finite() {
            return Err(det);
        }
        let b = b_matrix(&grads);
        for i in 0..8 {
            for jj in 0..8 {
                let mut sum = 0.0;
                for p in 0..3 {
                    for q in 0..3 {
                        sum += b[p][i] * d[p][q] * b[q][jj];
                    }
                }
                k[i][jj] += sum * det;
            }
        }
    }
    Ok(k)
}

fn b_matrix(grads: &[Vector2<f64>; 4]) -> [[f64; 8]; 3] {
    let mut b = [[0.0; 8]; 3];
    for (a, g) in grads.iter().enumerate() {
        b[0][2 * a] = g.x;
        b[1][2 * a + 1] = g.y;
        b[2][2 * a] = g.y;
        b[2][2 * a + 1] = g.x;
    }
    b
}

/// Lumped (row-sum) masses m_a = Σ_q ρ N_a(ξ_q) det J_q [kg/m].
pub(crate) fn lumped_mass(c: &[Vector2<f64>; 4], density: f64) -> [f64; 4] {
    let g = 1.0 / 3f64.sqrt();
    let mut m = [0.0; 4];
    for &(s, t) in &GAUSS_SIGNS {
        let (_, det) = shape_gradients(c, s * g, t * g);
        for (a, &(xa, ea)) in CORNERS.iter().enumerate() {
            m[a] += density * 0.25 * (1.0 + s * g * xa) * (1.0 + t * g * ea) * det;
        }
    }
    m
}

/// Shape-function gradients at the four Gauss points (GAUSS_SIGNS order) [1/m].
pub(crate) type GaussGradients = [[Vector2<f64>; 4]; 4];

/// ∇_X N_a at the four Gauss points of an element.
pub(crate) fn gauss_gradients(c: &[Vector2<f64>; 4]) -> GaussGradients {
    let g = 1.0 / 3f64.sqrt();
    GAUSS_SIGNS.map(|(s, t)| shape_gradients(c, s * g, t * g).0)
}

/// Gauss-point stresses σ_q = D B_q u_e, as [σ_xx, σ_yy, σ_xy] [Pa], in GAUSS_SIGNS order.
pub(crate) fn gauss_stresses(
    grads: &GaussGradients,
    d: &[[f64; 3]; 3],
    ue: &[Vector2<f64>; 4],
) -> [[f64; 3]; 4] {
    grads.map(|grads| {
        let mut eps = [0.0; 3];
        for a in 0..4 {
            eps[0] += grads[a].x * ue[a].x;
            eps[1] += grads[a].y * ue[a].y;
            eps[2] += grads[a].y * ue[a].x + grads[a].x * ue[a].y;
        }
        [0, 1, 2].map(|p| d[p][0] * eps[0] + d[p][1] * eps[1] + d[p][2] * eps[2])
    })
}

/// Bilinear extrapolation of Gauss values to natural point (ξ, η), fem-method §1:
/// value = Σ_k σ_k ¼(1 + √3 s_k ξ)(1 + √3 t_k η).
pub(crate) fn extrapolate(sig: &[[f64; 3]; 4], xi: f64, eta: f64) -> [f64; 3] {
    let r3 = 3f64.sqrt();
    let mut out = [0.0; 3];
    for (k, &(s, t)) in GAUSS_SIGNS.iter().enumerate() {
        let w = 0.25 * (1.0 + r3 * s * xi) * (1.0 + r3 * t * eta);
        for p in 0..3 {
            out[p] += w * sig[k][p];
        }
    }
    out
}

/// f = −f_int(u) for every node (overwrites `f`), gathering per node from the ≤ 4 adjacent
/// elements: f_a −= Σ_e K_e[a-rows] u_e. Parallel over layers; each task writes only its own layer.
pub(crate) fn internal_forces(grid: &Grid, k: &Stiffness, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    let nx = grid.nx;
    f.par_chunks_mut(nx + 1).enumerate().for_each(|(layer, fl)| {
        let (below, above) = grid.layer_element_rows(layer);
        for (i, fi) in fl.iter_mut().enumerate() {
            let mut acc = Vector2::zeros();
            // (element row, local index of this node for element column i−1, for column i)
            for (row, locals) in [(below, [2usize, 3usize]), (above, [1, 0])] {
                let Some(r) = row else { continue };
                for (col, la) in [(i.wrapping_sub(1), locals[0]), (i, locals[1])] {
                    if col >= nx {
                        continue;
                    }
                    let e = r * nx + col;
                    acc += element_row_force(k.get(e), la, &grid.element_nodes(e), u);
                }
            }
            *fi = -acc;
        }
    });
}

#[inline(always)]
fn element_row_force(k: &Ke, la: usize, nodes: &[u32; 4], u: &[Vector2<f64>]) -> Vector2<f64> {
    let (kx, ky) = (&k[2 * la], &k[2 * la + 1]);
    let (mut fx, mut fy) = (0.0, 0.0);
    for b in 0..4 {
        let ub = u[nodes[b] as usize];
        fx += kx[2 * b] * ub.x + kx[2 * b + 1] * ub.y;
        fy += ky[2 * b] * ub.x + ky[2 * b + 1] * ub.y;
    }
    Vector2::new(fx, fy)
}

/// Strain energy ½ Σ_a u_a · f_int,a [J/m] from the assembled f = −f_int.
pub(crate) fn strain_energy(u: &[Vector2<f64>], f_neg_int: &[Vector2<f64>]) -> f64 {
    -0.5 * u
        .par_iter()
        .zip(f_neg_int.par_iter())
        .map(|(a, b)| a.dot(b))
        .sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect() -> [Vector2<f64>; 4] {
        [
            Vector2::new(0.0, 0.0),
            Vector2::new(2.0, 0.0),
            Vector2::new(2.0, 1.0),
            Vector2::new(0.0, 1.0),
        ]
    }

    #[test]
    fn rectangle_mass_is_quarter_each() {
        let m = lumped_mass(&rect(), 1000.0);
        for mi in m {
            assert!((mi - 500.0).abs() < 1e-9);
        }
    }

    #[test]
    fn rigid_motion_has_no_force_and_stiffness_is_symmetric() {
        let d = crate::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0).d_matrix();
        let c = [
            Vector2::new(0.0, 0.0),
            Vector2::new(1.1, 0.1),
            Vector2::new(1.3, 0.9),
            Vector2::new(-0.1, 1.2),
        ];
        let k = stiffness(&c, &d).unwrap();
        let rot: Vec<f64> = c.iter().flat_map(|p| [-p.y, p.x]).collect();
        for row in &k {
            let f: f64 = row.iter().zip(&rot).map(|(a, b)| a * b).sum();
            assert!(f.abs() < 1e-6 * 70e6);
        }
        for (i, row) in k.iter().enumerate() {
            for (j, kij) in row.iter().enumerate() {
                assert!((kij - k[j][i]).abs() < 1e-9 * 70e6);
            }
        }
        let bad = [c[0], c[3], c[2], c[1]];
        assert!(stiffness(&bad, &d).is_err());
    }

    #[test]
    fn extrapolation_reproduces_bilinear_field() {
        let f = |x: f64, y: f64| 1.0 + 2.0 * x - 3.0 * y + 0.5 * x * y;
        let g = 1.0 / 3f64.sqrt();
        let sig = GAUSS_SIGNS.map(|(s, t)| [f(s * g, t * g), 0.0, 0.0]);
        let v = extrapolate(&sig, 1.0, -0.4);
        assert!((v[0] - f(1.0, -0.4)).abs() < 1e-12);
    }
}
