//! Q4 plane-strain element, 2×2 Gauss (docs/fem-model.md §1): pure kernels, and the race-free rayon
//! driver of the internal forces (each node gathers from its ≤ 4 elements; no shared writes).

use crate::mesh::structured::Grid;
use crate::model::stencil::Stencil;
use nalgebra::{Matrix2, Vector2};
use rayon::prelude::*;

pub(crate) use crate::model::stencil::Ke;

/// Gauss point signs (s_k, t_k), natural coordinates (s_k, t_k)/√3, weights 1.
pub(crate) const GAUSS_SIGNS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
const CORNERS: [(f64, f64); 4] = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];

/// Stiffness storage: one shared K_e for identical rectangles (one a material where each element
/// row has one), on-the-fly forces on mapped meshes, one K_e per element otherwise.
#[derive(Debug, Clone)]
pub(crate) enum Stiffness {
    /// All elements share this matrix; its interior-node stencil is built once with it.
    Shared(Box<SharedKe>),
    /// Identical rectangles of several materials, each element row of one, and no layer touching
    /// rows of two (the grid split at its twinned row): one shared K_e and stencil a material.
    ByRow(Box<RowKe>),
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

/// The shared K_e of each material of a grid whose element rows each take one material.
#[derive(Debug, Clone)]
pub(crate) struct RowKe {
    /// One shared K_e [N/m] and its stencil per material.
    kinds: Vec<SharedKe>,
    /// The index into `kinds` of each element row, bottom to top.
    row_kind: Vec<u8>,
    /// Elements per row.
    nx: usize,
}

impl SharedKe {
    fn new(ke: Ke) -> SharedKe {
        SharedKe {
            stencil: Stencil::new(&ke),
            ke,
        }
    }
}

impl Stiffness {
    /// One K_e for every element, with its stencil.
    pub(crate) fn shared(ke: Ke) -> Stiffness {
        Stiffness::Shared(Box::new(SharedKe::new(ke)))
    }

    /// One K_e a material (`kinds`) on a grid of `grid.nx` elements a row whose element row r takes
    /// `kinds[row_kind[r]]`; `None` when a layer touches element rows of two materials (the
    /// caller then keeps one K_e per element) or an index is out of range.
    pub(crate) fn by_row(grid: &Grid, kinds: &[Ke], row_kind: Vec<u8>) -> Option<Stiffness> {
        let ok = row_kind.len() == grid.ny
            && row_kind.iter().all(|&k| (k as usize) < kinds.len())
            && (0..grid.layer_side.len()).all(|l| match grid.layer_element_rows(l) {
                (Some(b), Some(a)) => row_kind[b] == row_kind[a],
                _ => true,
            });
        ok.then(|| {
            Stiffness::ByRow(Box::new(RowKe {
                kinds: kinds.iter().map(|&k| SharedKe::new(k)).collect(),
                row_kind,
                nx: grid.nx,
            }))
        })
    }

    /// The stencil of a layer whose element rows below and above are `below`, `above` (of one
    /// material, by [`Stiffness::by_row`]), where the elements share a K_e a material.
    pub(crate) fn stencil(&self, below: Option<usize>, above: Option<usize>) -> Option<&Stencil> {
        match self {
            Stiffness::Shared(k) => Some(&k.stencil),
            Stiffness::ByRow(k) => {
                let kind = above.or(below).map_or(0, |r| k.row_kind[r] as usize);
                Some(&k.kinds[kind].stencil)
            }
            Stiffness::PerElement(_) | Stiffness::Mapped(_) => None,
        }
    }

    #[inline]
    fn get(&self, e: usize) -> &Ke {
        match self {
            Stiffness::Shared(k) => &k.ke,
            Stiffness::ByRow(k) => &k.kinds[k.row_kind[e / k.nx] as usize].ke,
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

/// Shape-function gradients at the four Gauss points [1/m], by node a and component, the Gauss
/// points (GAUSS_SIGNS order) side by side: `[a][0][k]` = ∂N_a/∂x and `[a][1][k]` = ∂N_a/∂y at
/// point k, so that the four points' stresses take the lanes of one register
/// ([`gauss_stresses`]).
pub(crate) type GaussGradients = [[[f64; 4]; 2]; 4];

/// ∇_X N_a at the four Gauss points of an element.
pub(crate) fn gauss_gradients(c: &[Vector2<f64>; 4]) -> GaussGradients {
    let g = 1.0 / 3f64.sqrt();
    let at = GAUSS_SIGNS.map(|(s, t)| shape_gradients(c, s * g, t * g).0);
    std::array::from_fn(|a| {
        [
            std::array::from_fn(|k| at[k][a].x),
            std::array::from_fn(|k| at[k][a].y),
        ]
    })
}

/// Gauss-point stresses σ = D B_k u_e [Pa], as σ_p at the four points (GAUSS_SIGNS order) for
/// p = xx, yy, xy. Each point's operations come in the same order, written on arrays of four
/// points so that the compiler may put them in the lanes of a register.
pub(crate) fn gauss_stresses(
    grads: &GaussGradients,
    d: &[[f64; 3]; 3],
    ue: &[Vector2<f64>; 4],
) -> [[f64; 4]; 3] {
    let mut eps = [[0.0; 4]; 3];
    for (g, u) in grads.iter().zip(ue) {
        for k in 0..4 {
            eps[0][k] += g[0][k] * u.x;
            eps[1][k] += g[1][k] * u.y;
            eps[2][k] += g[1][k] * u.x + g[0][k] * u.y;
        }
    }
    [0, 1, 2]
        .map(|p| std::array::from_fn(|k| d[p][0] * eps[0][k] + d[p][1] * eps[1][k] + d[p][2] * eps[2][k]))
}

/// Bilinear extrapolation of Gauss-point values to the natural point (ξ, η), docs/fem-model.md
/// §1: value = Σ_k w_k v_k with w_k = ¼(1 + √3 s_k ξ)(1 + √3 t_k η), summed from k = 0 on, for
/// each of the three components of `sig` ([`gauss_stresses`]' order).
pub(crate) fn extrapolate(sig: &[[f64; 4]; 3], xi: f64, eta: f64) -> [f64; 3] {
    let r3 = 3f64.sqrt();
    let w = GAUSS_SIGNS.map(|(s, t)| 0.25 * (1.0 + r3 * s * xi) * (1.0 + r3 * t * eta));
    sig.map(|v| {
        let mut out = 0.0;
        for k in 0..4 {
            out += w[k] * v[k];
        }
        out
    })
}

/// f = −f_int(u) for every node (overwrites `f`), gathering per node from the ≤ 4 adjacent
/// elements: f_a −= Σ_e K_e[a-rows] u_e. Parallel over layers; each task writes only its own
/// layer, so there is no race and the result does not depend on the number of threads. With a
/// shared K_e (one a material, [`Stiffness::ByRow`]) the nodes of a layer use the precomputed stencil
/// ([`Stencil`]).
pub(crate) fn internal_forces(grid: &Grid, k: &Stiffness, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    let nx = grid.nx;
    let w = nx + 1;
    if let Stiffness::Mapped(m) = k {
        return crate::model::mapped::internal_forces(grid, m, u, f);
    }
    let flat: &[f64] = bytemuck::cast_slice(u);
    f.par_chunks_mut(w).enumerate().for_each(|(layer, fl)| {
        let (below, above) = grid.layer_element_rows(layer);
        match k.stencil(below, above) {
            Some(st) if nx >= 2 => {
                let row = |l: usize| &flat[2 * l * w..2 * (l + 1) * w];
                st.layer(
                    below.map(|_| row(layer - 1)),
                    row(layer),
                    above.map(|_| row(layer + 1)),
                    bytemuck::cast_slice_mut(fl),
                );
            }
            _ => {
                for (i, fi) in fl.iter_mut().enumerate() {
                    *fi = node_force(grid, k, below, above, i, u);
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

    /// A grid of `nx` × 4 unit elements twinned at row 2.
    fn twinned_grid(nx: usize) -> Grid {
        Grid::new(&crate::mesh::structured::GridSpec {
            x_range: [0.0, nx as f64],
            y_range: [-2.0, 2.0],
            nx,
            ny: 4,
            twinned_row: Some(2),
            upper_shift: 0.0,
            row_map: None,
        })
    }

    /// A displacement [m] that differs at every node.
    fn wavy_u(grid: &Grid) -> Vec<Vector2<f64>> {
        (0..grid.num_nodes())
            .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
            .collect()
    }

    /// 1e-12 relative: the two paths sum the same products in a different order.
    fn assert_same_forces(f1: &[Vector2<f64>], f2: &[Vector2<f64>], nx: usize) {
        for (a, b) in f1.iter().zip(f2) {
            assert!(
                (a - b).norm() <= 1e-12 * b.norm().max(1.0),
                "nx = {nx}: {a} vs {b}"
            );
        }
    }

    /// The stencil (vector lanes, node groups and the one-node tail) against the element-by-element
    /// gather, on widths that leave every possible tail after groups of 2 and 4 nodes, and on
    /// layers with element rows on both sides, below only (under the twinned row) and above only.
    /// 1e-12 relative: the two sum the same products in a different order.
    #[test]
    fn shared_stencil_equals_per_element_path() {
        for nx in [2, 5, 6, 7, 8, 13] {
            let grid = twinned_grid(nx);
            let d = crate::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0).d_matrix();
            let k = stiffness(&grid.element_coords(0), &d).unwrap();
            let u = wavy_u(&grid);
            let (mut f1, mut f2) = (vec![Vector2::zeros(); u.len()], vec![Vector2::zeros(); u.len()]);
            internal_forces(&grid, &Stiffness::shared(k), &u, &mut f1);
            internal_forces(
                &grid,
                &Stiffness::PerElement(vec![k; grid.num_elements()]),
                &u,
                &mut f2,
            );
            assert_same_forces(&f1, &f2, nx);
        }
    }

    /// Two materials split at the twinned row (lower rows stiff, upper rows soft): the stencil a
    /// material against the element-by-element gather of each element's own K_e, 1e-12 relative
    /// as above. Fails if a layer takes the other material's stencil (the two K_e differ by a
    /// factor 3). A split elsewhere, where one layer touches both materials, gives `None`.
    #[test]
    fn stencil_a_material_equals_per_element_path() {
        for nx in [2, 7, 8] {
            let grid = twinned_grid(nx);
            let c = grid.element_coords(0);
            let kinds = [210e6, 70e6].map(|e| {
                let d = crate::law::elastic::PlaneStrain::new(e, 0.3, 1000.0).d_matrix();
                stiffness(&c, &d).unwrap()
            });
            let rows = vec![0u8, 0, 1, 1];
            let per_element: Vec<Ke> = (0..grid.num_elements())
                .map(|e| kinds[rows[e / nx] as usize])
                .collect();
            let by_row = Stiffness::by_row(&grid, &kinds, rows).expect("split at the twinned row");
            assert!(matches!(by_row, Stiffness::ByRow(_)));
            let u = wavy_u(&grid);
            let (mut f1, mut f2) = (vec![Vector2::zeros(); u.len()], vec![Vector2::zeros(); u.len()]);
            internal_forces(&grid, &by_row, &u, &mut f1);
            internal_forces(&grid, &Stiffness::PerElement(per_element), &u, &mut f2);
            assert_same_forces(&f1, &f2, nx);
            assert!(Stiffness::by_row(&grid, &kinds, vec![0, 1, 1, 1]).is_none());
        }
    }

    /// Each Gauss point's stress, computed in its lane of [`gauss_stresses`], is σ = D ε with ε
    /// from that point's own shape-function gradients, on a distorted quadrilateral under a
    /// bilinear displacement (so the strain differs from point to point) and a D whose nine
    /// entries all differ. Fails if a point takes another's gradients, if the x and y gradients
    /// are swapped in the shear strain, or if D is read transposed.
    #[test]
    fn each_gauss_point_gets_d_times_its_own_strain() {
        let c = [(0.0, 0.0), (1.2, 0.1), (1.0, 0.9), (-0.1, 1.1)].map(|(x, y)| Vector2::new(x, y));
        let field = |x: Vector2<f64>| {
            Vector2::new(
                1e-3 * x.x + 2e-3 * x.y + 4e-3 * x.x * x.y,
                -5e-4 * x.x + 3e-3 * x.y - 2e-3 * x.x * x.y,
            )
        };
        let ue = c.map(field);
        let d = [[3.0, 1.0, 0.5], [1.1, 2.5, 0.2], [0.3, 0.4, 1.7]].map(|r| r.map(|v| v * 1e9));
        let sig = gauss_stresses(&gauss_gradients(&c), &d, &ue);
        let g = 1.0 / 3f64.sqrt();
        for (k, &(s, t)) in GAUSS_SIGNS.iter().enumerate() {
            let (grads, _) = shape_gradients(&c, s * g, t * g);
            let mut eps = [0.0; 3];
            for (n, u) in grads.iter().zip(&ue) {
                eps[0] += n.x * u.x;
                eps[1] += n.y * u.y;
                eps[2] += n.y * u.x + n.x * u.y;
            }
            for p in 0..3 {
                let expected = d[p][0] * eps[0] + d[p][1] * eps[1] + d[p][2] * eps[2];
                // the same operations in the same order: equal to the last bit
                assert_eq!(
                    sig[p][k].to_bits(),
                    expected.to_bits(),
                    "σ_{p} at Gauss point {k}"
                );
            }
        }
    }

    #[test]
    fn extrapolation_reproduces_bilinear_field() {
        let f = |x: f64, y: f64| 1.0 + 2.0 * x - 3.0 * y + 0.5 * x * y;
        let g = 1.0 / 3f64.sqrt();
        let sig = [GAUSS_SIGNS.map(|(s, t)| f(s * g, t * g)), [0.0; 4], [0.0; 4]];
        let v = extrapolate(&sig, 1.0, -0.4);
        assert!((v[0] - f(1.0, -0.4)).abs() < 1e-12);
    }
}
