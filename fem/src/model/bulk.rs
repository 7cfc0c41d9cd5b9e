//! Q4 plane-strain element, 2×2 Gauss (docs/fem-model.md §1): pure kernels, and the race-free rayon
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
    /// All elements share this matrix; its interior-node stencil is built once with it.
    Shared(Box<SharedKe>),
    /// One matrix per element.
    PerElement(Vec<Ke>),
    /// Vertical-sided elements of a mapped mesh: forces computed on the fly (`model::mapped`).
    Mapped(Box<crate::model::mapped::MappedStiffness>),
}

/// A shared K_e and the stencil derived from it.
#[derive(Debug, Clone)]
pub(crate) struct SharedKe {
    ke: Ke,
    stencil: Stencil,
}

impl Stiffness {
    /// One K_e for every element, with its stencil.
    pub(crate) fn shared(ke: Ke) -> Stiffness {
        Stiffness::Shared(Box::new(SharedKe {
            stencil: Stencil::new(&ke),
            ke,
        }))
    }

    #[inline]
    fn get(&self, e: usize) -> &Ke {
        match self {
            Stiffness::Shared(k) => &k.ke,
            Stiffness::PerElement(v) => &v[e],
            Stiffness::Mapped(_) => unreachable!("invariant: mapped meshes never read K_e"),
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

/// Bilinear extrapolation of Gauss values to natural point (ξ, η), docs/fem-model.md §1:
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
/// elements: f_a −= Σ_e K_e[a-rows] u_e. Parallel over layers; each task writes only its own
/// layer, so there is no race and the result does not depend on the number of threads. With a
/// shared K_e the interior nodes of a layer use the precomputed stencil ([`Stencil`]).
pub(crate) fn internal_forces(grid: &Grid, k: &Stiffness, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    let nx = grid.nx;
    let w = nx + 1;
    let stencil = match k {
        Stiffness::Shared(k) => Some(&k.stencil),
        Stiffness::PerElement(_) => None,
        Stiffness::Mapped(m) => return crate::model::mapped::internal_forces(grid, m, u, f),
    };
    let flat: &[f64] = bytemuck::cast_slice(u);
    f.par_chunks_mut(w).enumerate().for_each(|(layer, fl)| {
        let (below, above) = grid.layer_element_rows(layer);
        let generic = |i: usize| node_force(grid, k, below, above, i, u);
        match stencil {
            Some(st) if nx >= 2 => {
                fl[0] = generic(0);
                fl[nx] = generic(nx);
                let row = |l: usize| &flat[2 * l * w..2 * (l + 1) * w];
                let out: &mut [f64] = bytemuck::cast_slice_mut(fl);
                match (below, above) {
                    (Some(_), Some(_)) => {
                        st.apply([row(layer - 1), row(layer), row(layer + 1)], &st.both, out)
                    }
                    (Some(_), None) => st.apply([row(layer - 1), row(layer)], &st.below, out),
                    (None, Some(_)) => st.apply([row(layer), row(layer + 1)], &st.above, out),
                    (None, None) => out[2..2 * nx].fill(0.0),
                }
            }
            _ => {
                for (i, fi) in fl.iter_mut().enumerate() {
                    *fi = generic(i);
                }
            }
        }
    });
}

/// −Σ_e K_e[a-rows] u_e for the node of column i of a layer touching element rows (below, above).
fn node_force(
    grid: &Grid,
    k: &Stiffness,
    below: Option<usize>,
    above: Option<usize>,
    i: usize,
    u: &[Vector2<f64>],
) -> Vector2<f64> {
    let nx = grid.nx;
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
    -acc
}

/// A 2×2 block of K multiplying the displacement of one neighbour, as the two lane patterns of
/// a pair of nodes: f_x, f_y, f_x, f_y += `xs` · (u_x, u_x, u_x', u_x') + `ys` · (u_y, u_y, u_y', u_y').
type Block = [[f64; 4]; 2];

/// Interior-node stencil of a shared K_e: f_a = −Σ_rows Σ_{dc = −1, 0, 1} B[row][dc] u(row, i + dc),
/// one 2×2 block per neighbour node, for a node with element rows on both sides (3 node rows,
/// the middle row's blocks summed over the two element rows), below only, or above only.
#[derive(Debug, Clone)]
struct Stencil {
    both: [[Block; 3]; 3],
    below: [[Block; 3]; 2],
    above: [[Block; 3]; 2],
    /// The CPU has AVX2 / AVX-512F (checked once at build): the same lane code compiled for
    /// 4- and 8-wide vectors.
    avx2: bool,
    avx512: bool,
}

impl Stencil {
    fn new(k: &Ke) -> Stencil {
        let block = |a: usize, b: usize| {
            [
                k[2 * a][2 * b],
                k[2 * a][2 * b + 1],
                k[2 * a + 1][2 * b],
                k[2 * a + 1][2 * b + 1],
            ]
        };
        // per element row: blocks[node row offset][column offset + 1], row-major 2×2
        let mut below = [[[0.0; 4]; 3]; 2];
        let mut above = [[[0.0; 4]; 3]; 2];
        // element nodes b = 0..3 at (node row offset, column offset + 1) relative to the node, per (element, local a)
        let below_elems = [
            (2usize, [(0usize, 0usize), (0, 1), (1, 1), (1, 0)]),
            (3, [(0, 1), (0, 2), (1, 2), (1, 1)]),
        ];
        let above_elems = [
            (1usize, [(0usize, 0usize), (0, 1), (1, 1), (1, 0)]),
            (0, [(0, 1), (0, 2), (1, 2), (1, 1)]),
        ];
        for (target, elems) in [(&mut below, below_elems), (&mut above, above_elems)] {
            for (a, nodes) in elems {
                for (b, (lo, col)) in nodes.iter().enumerate() {
                    for (t, v) in target[*lo][*col].iter_mut().zip(block(a, b)) {
                        *t += v;
                    }
                }
            }
        }
        let mut both = [below[0], [[0.0; 4]; 3], above[1]];
        for dc in 0..3 {
            for q in 0..4 {
                both[1][dc][q] = below[1][dc][q] + above[0][dc][q];
            }
        }
        let lanes = |m: [f64; 4]| -> Block { [[m[0], m[2], m[0], m[2]], [m[1], m[3], m[1], m[3]]] };
        #[cfg(target_arch = "x86_64")]
        let (avx2, avx512) = (
            std::arch::is_x86_feature_detected!("avx2"),
            std::arch::is_x86_feature_detected!("avx512f"),
        );
        #[cfg(not(target_arch = "x86_64"))]
        let (avx2, avx512) = (false, false);
        Stencil {
            both: both.map(|r| r.map(lanes)),
            below: below.map(|r| r.map(lanes)),
            above: above.map(|r| r.map(lanes)),
            avx2,
            avx512,
        }
    }

    /// Forces of the interior nodes 1..nx−1 of one layer into `out` (the layer's x, y pairs).
    #[inline]
    fn apply<const R: usize>(&self, rows: [&[f64]; R], blocks: &[[Block; 3]; R], out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx512 {
            // SAFETY: `avx512` is true only if the CPU reported AVX-512F at run time (`Stencil::new`).
            return unsafe { stencil_layer_avx512(rows, blocks, out) };
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only if the CPU reported AVX2 at run time (`Stencil::new`).
            return unsafe { stencil_layer_avx2(rows, blocks, out) };
        }
        stencil_layer::<R, 4>(rows, blocks, out)
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn stencil_layer_avx2<const R: usize>(rows: [&[f64]; R], blocks: &[[Block; 3]; R], out: &mut [f64]) {
    stencil_layer::<R, 4>(rows, blocks, out)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn stencil_layer_avx512<const R: usize>(rows: [&[f64]; R], blocks: &[[Block; 3]; R], out: &mut [f64]) {
    stencil_layer::<R, 8>(rows, blocks, out)
}

/// L/2 nodes per iteration in L lanes (f_x, f_y of node i, then of node i + 1, …); the nodes left
/// over take one at a time the first two lanes of the same arithmetic, so every node's force is
/// the same sequence of IEEE operations whatever the vector width or the grouping.
#[inline(always)]
fn stencil_layer<const R: usize, const L: usize>(
    rows: [&[f64]; R],
    blocks: &[[Block; 3]; R],
    out: &mut [f64],
) {
    let nx = out.len() / 2 - 1;
    let p = L / 2;
    let mut i = 1;
    while i + p <= nx {
        let mut acc = [0.0f64; L];
        for (row, blk) in rows.iter().zip(blocks) {
            let u = &row[2 * (i - 1)..2 * (i - 1) + L + 4];
            for (dc, [xs, ys]) in blk.iter().enumerate() {
                let w = &u[2 * dc..2 * dc + L];
                for l in 0..L {
                    let pair = l & !1;
                    acc[l] += xs[l % 4] * w[pair] + ys[l % 4] * w[pair + 1];
                }
            }
        }
        for (o, a) in out[2 * i..2 * i + L].iter_mut().zip(acc) {
            *o = -a;
        }
        i += p;
    }
    while i < nx {
        let mut acc = [0.0f64; 2];
        for (row, blk) in rows.iter().zip(blocks) {
            for (dc, [xs, ys]) in blk.iter().enumerate() {
                let j = 2 * (i + dc - 1);
                for l in 0..2 {
                    acc[l] += xs[l] * row[j] + ys[l] * row[j + 1];
                }
            }
        }
        out[2 * i] = -acc[0];
        out[2 * i + 1] = -acc[1];
        i += 1;
    }
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
    -0.5 * crate::model::reduce::ordered_sum(u.len(), |i| u[i].dot(&f_neg_int[i]))
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

    /// The stencil (vector lanes, node groups and the one-node tail) against the element-by-element
    /// gather, on widths that leave every possible tail after groups of 2 and 4 nodes, and on
    /// layers with element rows on both sides, below only (under the twinned row) and above only.
    /// 1e-12 relative: the two sum the same products in a different order.
    #[test]
    fn shared_stencil_equals_per_element_path() {
        use crate::mesh::structured::GridSpec;
        for nx in [2, 5, 6, 7, 8, 13] {
            let grid = Grid::new(&GridSpec {
                x_range: [0.0, nx as f64],
                y_range: [-2.0, 2.0],
                nx,
                ny: 4,
                twinned_row: Some(2),
                upper_shift: 0.0,
                row_map: None,
            });
            let d = crate::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0).d_matrix();
            let k = stiffness(&grid.element_coords(0), &d).unwrap();
            let u: Vec<Vector2<f64>> = (0..grid.num_nodes())
                .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
                .collect();
            let (mut f1, mut f2) = (vec![Vector2::zeros(); u.len()], vec![Vector2::zeros(); u.len()]);
            internal_forces(&grid, &Stiffness::shared(k), &u, &mut f1);
            internal_forces(
                &grid,
                &Stiffness::PerElement(vec![k; grid.num_elements()]),
                &u,
                &mut f2,
            );
            for (a, b) in f1.iter().zip(&f2) {
                assert!(
                    (a - b).norm() <= 1e-12 * b.norm().max(1.0),
                    "nx = {nx}: {a} vs {b}"
                );
            }
        }
    }

    /// Every vector width gives the same bits as the portable code (the run's output must not
    /// depend on the CPU it runs on).
    #[test]
    fn stencil_widths_agree_bit_for_bit() {
        let d = crate::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0).d_matrix();
        let st = Stencil::new(&stiffness(&rect(), &d).unwrap());
        let w = 23;
        let rows: Vec<Vec<f64>> = (0..3)
            .map(|r| (0..2 * w).map(|k| ((k + 7 * r) as f64 * 0.731).sin()).collect())
            .collect();
        let rows = [rows[0].as_slice(), rows[1].as_slice(), rows[2].as_slice()];
        let mut reference = vec![0.0; 2 * w];
        stencil_layer::<3, 2>(rows, &st.both, &mut reference);
        let mut four = vec![0.0; 2 * w];
        stencil_layer::<3, 4>(rows, &st.both, &mut four);
        let mut eight = vec![0.0; 2 * w];
        stencil_layer::<3, 8>(rows, &st.both, &mut eight);
        let mut dispatched = vec![0.0; 2 * w];
        st.apply(rows, &st.both, &mut dispatched);
        assert_eq!(reference, four);
        assert_eq!(reference, eight);
        assert_eq!(reference, dispatched);
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
