//! The bulk kernel on unstructured meshes of T3 and Q4 elements ([`crate::gmsh::UnstructuredMesh`]):
//! element stiffnesses, lumped masses, the smallest element length of the stable step, and the
//! race-free rayon gather of the internal forces. Not used by the time loop yet (docs/meshes.md).
//!
//! Elements (plane strain, thickness 1 m, so forces are per metre of thickness):
//! - **T3**, the constant-strain triangle: K_e = A t Bᵀ D B with t = 1 m and the constant
//!   B = 1/(2A) [[b₀, 0, b₁, 0, b₂, 0], [0, c₀, 0, c₁, 0, c₂], [c₀, b₀, c₁, b₁, c₂, b₂]],
//!   b_i = y_j − y_k, c_i = x_k − x_j for (i, j, k) cyclic (Zienkiewicz, Taylor & Zhu, *The Finite
//!   Element Method: Its Basis and Fundamentals*, 7th ed., §6.2). Exact, 6×6. Lumped mass ρA/3 per
//!   node (the row sum of the consistent mass).
//! - **Q4**, the bilinear quadrangle with 2×2 Gauss points: `model::bulk::stiffness` and
//!   `model::bulk::lumped_mass`, the structured grid's element (docs/fem-model.md §1).
//!
//! Storage: each node a gathers f_a = −Σ_e K_e[a-rows] u_e over its elements e. The two rows of
//! K_e that belong to node a (2 × 2n values for an n-node element) are copied, at build time,
//! into one array in the order the gather reads them (node by node, element by element). A
//! triangle therefore stores 6×6 values and a quadrangle 8×8, with no padding, and the gather
//! streams through that array once per evaluation instead of jumping between elements. The total
//! is the same as one K_e per element (each row belongs to exactly one node).

use crate::gmsh::{ElementKind, UnstructuredMesh};
use crate::model::bulk;
use nalgebra::Vector2;
use rayon::prelude::*;
use thiserror::Error;

/// Nodes per rayon task of the gather: large enough that a task's cost dwarfs the scheduling,
/// small enough to balance 2 threads on meshes of a few thousand nodes.
const CHUNK: usize = 1024;

/// A mesh the unstructured kernel cannot be built on.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum UnstructuredError {
    /// An element with a non-positive (or non-finite) Jacobian determinant at a quadrature point:
    /// inverted or degenerate. The mesh reader refuses such elements; this guards meshes built by
    /// hand.
    #[error("element {element} is inverted or degenerate (det J = {det_j} m²)")]
    InvertedElement {
        /// Element tag ([`crate::gmsh::BulkElement::tag`]).
        element: u64,
        /// The offending determinant (T3: twice the signed area) [m²].
        det_j: f64,
    },
    /// A density that is not finite and positive.
    #[error("density = {0} kg/m³ must be finite and positive")]
    BadDensity(f64),
    /// More nodes or element entries than the 32-bit indices of the kernel hold.
    #[error("the mesh is too large for the kernel's 32-bit indices")]
    TooLarge,
}

/// One (element, local node) entry of a node's adjacency.
#[derive(Debug, Clone, Copy)]
struct Entry {
    /// Start of the element's nodes in `UnstructuredBulk::conn`.
    conn: u32,
    /// Number of nodes of the element (3 or 4).
    n: u32,
}

/// The bulk of an unstructured T3/Q4 mesh, ready for force evaluations.
#[derive(Debug, Clone)]
pub struct UnstructuredBulk {
    /// Node indices of every element, element after element.
    conn: Vec<u32>,
    /// CSR offsets into `entries` per node (length: nodes + 1).
    adj_start: Vec<u32>,
    /// A node's elements, in ascending element index (fixes the order of each node's sum).
    entries: Vec<Entry>,
    /// Offset of each node's stiffness rows in `rows` (length: nodes + 1).
    rows_start: Vec<usize>,
    /// For every entry in CSR order: the x row then the y row of K_e for that local node, each
    /// of 2n values in DOF order x₀, y₀, x₁, y₁, … [N/m per m].
    rows: Vec<f64>,
    /// Lumped nodal masses [kg/m].
    mass: Vec<f64>,
    /// Smallest element length of the stable step [m] (see [`UnstructuredBulk::min_length`]).
    h_min: f64,
}

impl UnstructuredBulk {
    /// Builds the kernel on `mesh` with the plane-strain Voigt matrix `d` [Pa]
    /// ([`crate::law::elastic::PlaneStrain::d_matrix`]) and the density `density` [kg/m³].
    pub fn new(mesh: &UnstructuredMesh, d: &[[f64; 3]; 3], density: f64) -> Result<Self, UnstructuredError> {
        if !(density.is_finite() && density > 0.0) {
            return Err(UnstructuredError::BadDensity(density));
        }
        let nn = mesh.positions.len();
        let total: usize = mesh.elements.iter().map(|e| e.nodes.len()).sum();
        if nn >= u32::MAX as usize || total >= u32::MAX as usize {
            return Err(UnstructuredError::TooLarge);
        }
        let x = &mesh.positions;

        // element stiffnesses (flat, (2n)² values each), masses, connectivity, h_min
        let mut ke = Vec::with_capacity(total * 4 * 4);
        let mut ke_start = Vec::with_capacity(mesh.elements.len() + 1);
        let mut conn = Vec::with_capacity(total);
        let mut conn_start = Vec::with_capacity(mesh.elements.len() + 1);
        let mut mass = vec![0.0; nn];
        let mut h_min = f64::INFINITY;
        for el in &mesh.elements {
            ke_start.push(ke.len());
            conn_start.push(conn.len());
            conn.extend(el.nodes.iter().map(|&a| a as u32));
            let inverted = |det_j: f64| UnstructuredError::InvertedElement {
                element: el.tag,
                det_j,
            };
            let (area, m) = match el.kind {
                ElementKind::T3 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]]];
                    let k = cst_stiffness(&c, d).map_err(inverted)?;
                    ke.extend(k.iter().flatten());
                    let area = 0.5 * (c[1] - c[0]).perp(&(c[2] - c[0]));
                    (area, vec![density * area / 3.0; 3])
                }
                ElementKind::Q4 => {
                    let c = [x[el.nodes[0]], x[el.nodes[1]], x[el.nodes[2]], x[el.nodes[3]]];
                    let k = bulk::stiffness(&c, d).map_err(inverted)?;
                    ke.extend(k.iter().flatten());
                    let area = 0.5 * ((c[2] - c[0]).perp(&(c[3] - c[1])));
                    (area, bulk::lumped_mass(&c, density).to_vec())
                }
            };
            for (&a, ma) in el.nodes.iter().zip(m) {
                mass[a] += ma;
            }
            h_min = h_min.min(element_length(el.kind, area, &el.nodes, x));
        }
        ke_start.push(ke.len());
        conn_start.push(conn.len());

        // node → (element, local) in CSR form; elements are visited in ascending index, so each
        // node's list is sorted by element index
        let mut adj_start = vec![0u32; nn + 1];
        for &a in &conn {
            adj_start[a as usize + 1] += 1;
        }
        for a in 0..nn {
            adj_start[a + 1] += adj_start[a];
        }
        let mut fill: Vec<u32> = adj_start[..nn].to_vec();
        let mut adj = vec![(0usize, 0usize); total];
        for (e, el) in mesh.elements.iter().enumerate() {
            for (la, &a) in el.nodes.iter().enumerate() {
                adj[fill[a] as usize] = (e, la);
                fill[a] += 1;
            }
        }

        // each node's rows of K_e, in CSR order
        let mut entries = Vec::with_capacity(total);
        let mut rows = Vec::with_capacity(ke.len());
        let mut rows_start = Vec::with_capacity(nn + 1);
        for a in 0..nn {
            rows_start.push(rows.len());
            for &(e, la) in &adj[adj_start[a] as usize..adj_start[a + 1] as usize] {
                let n = conn_start[e + 1] - conn_start[e];
                let k = &ke[ke_start[e]..ke_start[e + 1]];
                rows.extend_from_slice(&k[2 * la * 2 * n..(2 * la + 2) * 2 * n]);
                entries.push(Entry {
                    conn: conn_start[e] as u32,
                    n: n as u32,
                });
            }
        }
        rows_start.push(rows.len());

        Ok(Self {
            conn,
            adj_start,
            entries,
            rows_start,
            rows,
            mass,
            h_min,
        })
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.mass.len()
    }

    /// Lumped nodal masses [kg/m] (T3: ρA/3 per node; Q4: the row sums of
    /// `model::bulk::lumped_mass`).
    pub fn masses(&self) -> &[f64] {
        &self.mass
    }

    /// Smallest element length h_min [m] of the stable step Δt = α h_min/c_d · f(β_p)
    /// (docs/fem-model.md §2, [`crate::law::elastic::stable_time_step`]). Per element:
    /// - T3: its smallest altitude, 2A/ℓ_max with ℓ_max its longest edge (the characteristic
    ///   length of explicit codes for triangles);
    /// - Q4: A/ℓ_max. On a rectangle h × h that is h, and on the vertical-sided elements of a
    ///   mapped grid (width h, height v, top edge of slope s) it is v/√(1 + s²): the structured
    ///   model's rule ([`crate::scene::FemSpec::min_edge`]) on the meshes it covers.
    pub fn min_length(&self) -> f64 {
        self.h_min
    }

    /// Stable time step Δt = α h_min/c_d [s] without a penalty (β_p = 0), with c_d [m/s] the
    /// plane-strain dilatational speed ([`crate::law::elastic::PlaneStrain::wave_speeds`]).
    pub fn stable_time_step(&self, alpha: f64, cd: f64) -> f64 {
        crate::law::elastic::stable_time_step(alpha, self.h_min, cd, 0.0)
    }

    /// f = −f_int(u) [N/m] for displacements `u` [m] (overwrites `f`): every node gathers
    /// f_a = −Σ_e K_e[a-rows] u_e over its elements in ascending element index. Parallel over
    /// blocks of nodes; each task writes only its own nodes and each node's sum has a fixed
    /// order, so the result is the same to the bit for any number of threads. Allocates nothing.
    pub fn internal_forces(&self, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
        assert_eq!(u.len(), self.num_nodes(), "one displacement per node");
        assert_eq!(f.len(), self.num_nodes(), "one force per node");
        f.par_chunks_mut(CHUNK).enumerate().for_each(|(c, fc)| {
            let first = c * CHUNK;
            for (i, fa) in fc.iter_mut().enumerate() {
                *fa = self.node_force(first + i, u);
            }
        });
    }

    /// −Σ_e K_e[a-rows] u_e for node a, in CSR order.
    #[inline]
    fn node_force(&self, a: usize, u: &[Vector2<f64>]) -> Vector2<f64> {
        let entries = &self.entries[self.adj_start[a] as usize..self.adj_start[a + 1] as usize];
        let mut r = self.rows_start[a];
        let (mut fx, mut fy) = (0.0, 0.0);
        for ent in entries {
            let n = ent.n as usize;
            let nodes = &self.conn[ent.conn as usize..ent.conn as usize + n];
            let k = &self.rows[r..r + 4 * n];
            let (gx, gy) = if n == 4 {
                row_force::<4>(k, nodes, u)
            } else {
                row_force::<3>(k, nodes, u)
            };
            fx += gx;
            fy += gy;
            r += 4 * n;
        }
        -Vector2::new(fx, fy)
    }
}

/// (K[x-row] · u_e, K[y-row] · u_e) for one local node of an N-node element; `k` holds the x row
/// then the y row (2N values each).
#[inline(always)]
fn row_force<const N: usize>(k: &[f64], nodes: &[u32], u: &[Vector2<f64>]) -> (f64, f64) {
    let (kx, ky) = k.split_at(2 * N);
    let (mut fx, mut fy) = (0.0, 0.0);
    for b in 0..N {
        let ub = u[nodes[b] as usize];
        fx += kx[2 * b] * ub.x + kx[2 * b + 1] * ub.y;
        fy += ky[2 * b] * ub.x + ky[2 * b + 1] * ub.y;
    }
    (fx, fy)
}

/// Constant-strain triangle K_e = A t Bᵀ D B (t = 1 m) [N/m per m], DOF order x₀, y₀, x₁, y₁,
/// x₂, y₂; Err(2A) [m²] for a clockwise or degenerate triangle.
fn cst_stiffness(c: &[Vector2<f64>; 3], d: &[[f64; 3]; 3]) -> Result<[[f64; 6]; 6], f64> {
    let two_a = (c[1] - c[0]).perp(&(c[2] - c[0]));
    if two_a <= 0.0 || !two_a.is_finite() {
        return Err(two_a);
    }
    let mut b = [[0.0; 6]; 3];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        // ∂N_i/∂x = b_i/(2A), ∂N_i/∂y = c_i/(2A)
        let (bi, ci) = ((c[j].y - c[k].y) / two_a, (c[k].x - c[j].x) / two_a);
        b[0][2 * i] = bi;
        b[1][2 * i + 1] = ci;
        b[2][2 * i] = ci;
        b[2][2 * i + 1] = bi;
    }
    let area = 0.5 * two_a;
    let mut k = [[0.0; 6]; 6];
    for (i, ki) in k.iter_mut().enumerate() {
        for (j, kij) in ki.iter_mut().enumerate() {
            let mut sum = 0.0;
            for p in 0..3 {
                for q in 0..3 {
                    sum += b[p][i] * d[p][q] * b[q][j];
                }
            }
            *kij = area * sum;
        }
    }
    Ok(k)
}

/// The element's length of the stable step [m]: T3 2A/ℓ_max, Q4 A/ℓ_max (see
/// [`UnstructuredBulk::min_length`]).
fn element_length(kind: ElementKind, area: f64, nodes: &[usize], x: &[Vector2<f64>]) -> f64 {
    let n = nodes.len();
    let longest = (0..n)
        .map(|k| (x[nodes[(k + 1) % n]] - x[nodes[k]]).norm())
        .fold(0.0, f64::max);
    match kind {
        ElementKind::T3 => 2.0 * area / longest,
        ElementKind::Q4 => area / longest,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gmsh::BulkElement;
    use crate::law::elastic::PlaneStrain;
    use crate::mesh::structured::{Grid, GridSpec};
    use std::collections::BTreeMap;

    /// The paper's material (E = 70 MPa, ν = 0.35, ρ = 1230 kg/m³).
    fn material() -> PlaneStrain {
        PlaneStrain::new(70e6, 0.35, 1230.0)
    }

    fn committed(name: &str) -> UnstructuredMesh {
        let path = format!("{}/../meshes/{name}", env!("CARGO_MANIFEST_DIR"));
        UnstructuredMesh::read(std::path::Path::new(&path)).unwrap()
    }

    /// A mesh with the given nodes and elements and nothing else.
    fn mesh_of(positions: Vec<Vector2<f64>>, elements: Vec<(ElementKind, Vec<usize>)>) -> UnstructuredMesh {
        UnstructuredMesh {
            node_tags: (1..=positions.len() as u64).collect(),
            positions,
            elements: elements
                .into_iter()
                .enumerate()
                .map(|(e, (kind, nodes))| BulkElement {
                    tag: e as u64 + 1,
                    kind,
                    nodes,
                })
                .collect(),
            lines: Vec::new(),
            groups: BTreeMap::new(),
            reoriented: 0,
            warnings: Vec::new(),
        }
    }

    /// Nodes on the outer boundary of the committed rectangles: the `bottom`, `top`, `left` and
    /// `right` groups.
    fn boundary_nodes(mesh: &UnstructuredMesh) -> Vec<bool> {
        let mut on = vec![false; mesh.positions.len()];
        for g in ["bottom", "top", "left", "right"] {
            for &a in &mesh.group(g).unwrap().nodes {
                on[a] = true;
            }
        }
        on
    }

    fn longest_edge(mesh: &UnstructuredMesh) -> f64 {
        mesh.elements
            .iter()
            .flat_map(|el| {
                let n = el.nodes.len();
                (0..n).map(move |k| (el.nodes[k], el.nodes[(k + 1) % n]))
            })
            .map(|(a, b)| (mesh.positions[a] - mesh.positions[b]).norm())
            .fold(0.0, f64::max)
    }

    fn forces(bulk: &UnstructuredBulk, u: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
        let mut f = vec![Vector2::zeros(); u.len()];
        bulk.internal_forces(u, &mut f);
        f
    }

    /// Patch test: u = A x + b is a state of constant stress σ = D ε(A), so every interior node
    /// is in equilibrium and the boundary forces balance. Scale: the force a single element
    /// carries, |σ| × ℓ_max [N/m]. Round-off: each nodal force sums ≲ 50 products of size
    /// |K| |u| ≈ |D| (|A| L + |b|) with L = 2 m the domain, i.e. ≈ 100 × (L/ℓ_max) × 1e-16 of the
    /// scale ≈ 1e-13 on these meshes (ℓ_max ≈ 0.1 m); 1e-10 leaves three orders of margin.
    #[test]
    fn linear_field_passes_the_patch_test_on_committed_meshes() {
        let mat = material();
        let d = mat.d_matrix();
        let a = [[1.3e-3, -0.4e-3], [0.7e-3, -2.1e-3]];
        let b = Vector2::new(2e-4, -3e-4);
        let eps = [a[0][0], a[1][1], a[0][1] + a[1][0]];
        let sigma = [0, 1, 2].map(|p| (0..3).map(|q| d[p][q] * eps[q]).sum::<f64>());
        let sigma_norm = sigma.iter().map(|s| s * s).sum::<f64>().sqrt();
        for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"] {
            let mesh = committed(name);
            let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
            let u: Vec<Vector2<f64>> = mesh
                .positions
                .iter()
                .map(|x| Vector2::new(a[0][0] * x.x + a[0][1] * x.y, a[1][0] * x.x + a[1][1] * x.y) + b)
                .collect();
            let f = forces(&bulk, &u);
            let scale = sigma_norm * longest_edge(&mesh);
            let on_boundary = boundary_nodes(&mesh);
            let mut interior = 0;
            for (n, fa) in f.iter().enumerate() {
                if !on_boundary[n] {
                    interior += 1;
                    assert!(
                        fa.norm() <= 1e-10 * scale,
                        "{name}: node {n} f = {fa}, scale {scale}"
                    );
                }
            }
            assert!(interior > 10, "{name}: {interior} interior nodes");
            // the boundary tractions balance; they also carry σ: the right edge (x = 2 m, height
            // 1 m) takes −(σ_xx, σ_xy) × 1 m in f = −f_int
            let total: Vector2<f64> = f.iter().sum();
            let magnitude: f64 = f.iter().map(|fa| fa.norm()).sum();
            assert!(total.norm() <= 1e-10 * magnitude, "{name}: Σf = {total}");
            let right: Vector2<f64> = mesh.group("right").unwrap().nodes.iter().map(|&n| f[n]).sum();
            let expect = -Vector2::new(sigma[0], sigma[2]);
            assert!(
                (right - expect).norm() <= 1e-10 * sigma_norm,
                "{name}: {right} vs {expect}"
            );
        }
    }

    /// A small rotation θ (−y, x) plus a translation is a rigid motion of the linear kernel:
    /// zero force, against the scale |D| θ ℓ_max of a stretch of the same size (the same
    /// round-off budget as the patch test). The masses add up to ρ × area of the rectangle
    /// [0, 2] × [0, 1] m: both lumpings integrate the element's area exactly, so only the
    /// round-off of some hundred additions remains, far below 1e-12.
    #[test]
    fn rigid_motion_has_no_force_and_masses_sum_to_rho_area() {
        let mat = material();
        let d = mat.d_matrix();
        let theta = 1e-4;
        for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"] {
            let mesh = committed(name);
            let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
            let u: Vec<Vector2<f64>> = mesh
                .positions
                .iter()
                .map(|x| theta * Vector2::new(-x.y, x.x) + Vector2::new(3e-5, -1e-5))
                .collect();
            let f = forces(&bulk, &u);
            let scale = d[0][0] * theta * longest_edge(&mesh);
            for (n, fa) in f.iter().enumerate() {
                assert!(fa.norm() <= 1e-10 * scale, "{name}: node {n} f = {fa}");
            }
            let total: f64 = bulk.masses().iter().sum();
            let expect = mat.density * 2.0;
            assert!(
                (total - expect).abs() <= 1e-12 * expect,
                "{name}: {total} vs {expect}"
            );
            assert!(bulk.masses().iter().all(|&m| m > 0.0));
        }
    }

    /// A structured rectangle with a twinned row, written as an unstructured Q4 mesh, gives the
    /// forces of the structured driver (the shared-K_e stencil and the per-element gather). The
    /// two sum the same products in a different order (the stencil sums a node row's blocks of
    /// the two element rows first), so they agree to round-off, 1e-12 of the largest force.
    #[test]
    fn q4_grid_matches_the_structured_driver() {
        let d = material().d_matrix();
        for (nx, ny, twinned) in [(7, 4, Some(2)), (12, 6, None)] {
            let grid = Grid::new(&GridSpec {
                x_range: [-0.3, 0.4],
                y_range: [-0.2, 0.2],
                nx,
                ny,
                twinned_row: twinned,
                upper_shift: 0.0,
                row_map: None,
            });
            let mesh = mesh_of(
                grid.x0.clone(),
                (0..grid.num_elements())
                    .map(|e| {
                        (
                            ElementKind::Q4,
                            grid.element_nodes(e).map(|a| a as usize).to_vec(),
                        )
                    })
                    .collect(),
            );
            let bulk = UnstructuredBulk::new(&mesh, &d, 1230.0).unwrap();
            let u: Vec<Vector2<f64>> = (0..grid.num_nodes())
                .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
                .collect();
            let f = forces(&bulk, &u);
            let k = bulk::stiffness(&grid.element_coords(0), &d).unwrap();
            for stiffness in [
                bulk::Stiffness::shared(k),
                bulk::Stiffness::PerElement(
                    (0..grid.num_elements())
                        .map(|e| bulk::stiffness(&grid.element_coords(e), &d).unwrap())
                        .collect(),
                ),
            ] {
                let mut g = vec![Vector2::zeros(); u.len()];
                bulk::internal_forces(&grid, &stiffness, &u, &mut g);
                let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
                for (n, (a, b)) in f.iter().zip(&g).enumerate() {
                    assert!((a - b).norm() <= 1e-12 * scale, "{nx}×{ny} node {n}: {a} vs {b}");
                }
            }
            // masses: the structured grid's ρ h_x h_y / 4 per element corner
            let (hx, hy) = (0.7 / nx as f64, 0.4 / ny as f64);
            let corner = 1230.0 * hx * hy / 4.0;
            for (n, &m) in bulk.masses().iter().enumerate() {
                let count = (m / corner).round();
                assert!((m - count * corner).abs() <= 1e-12 * m, "node {n}: {m}");
            }
            assert!((bulk.min_length() - hx.min(hy)).abs() <= 1e-12 * hx);
        }
    }

    /// The forces are the same to the bit on 1 and 2 threads (each node's sum has a fixed order),
    /// on a mixed mesh large enough to be split into several tasks.
    #[test]
    fn forces_do_not_depend_on_the_thread_count() {
        let (nx, ny) = (60, 40);
        let positions: Vec<Vector2<f64>> = (0..=ny)
            .flat_map(|j| {
                (0..=nx).map(move |i| {
                    // a distorted grid: no two elements alike
                    let (x, y) = (i as f64 * 0.01, j as f64 * 0.01);
                    Vector2::new(x + 0.002 * (7.0 * y).sin(), y + 0.002 * (5.0 * x).cos())
                })
            })
            .collect();
        let node = |i: usize, j: usize| j * (nx + 1) + i;
        let mut elements = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let q = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
                if (i + j) % 3 == 0 {
                    elements.push((ElementKind::T3, vec![q[0], q[1], q[2]]));
                    elements.push((ElementKind::T3, vec![q[0], q[2], q[3]]));
                } else {
                    elements.push((ElementKind::Q4, q.to_vec()));
                }
            }
        }
        let mesh = mesh_of(positions, elements);
        let mat = material();
        let bulk = UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
        assert!(bulk.num_nodes() > 2 * CHUNK);
        let u: Vec<Vector2<f64>> = (0..bulk.num_nodes())
            .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
            .collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| forces(&bulk, &u))
        };
        let (one, two) = (run(1), run(2));
        assert!(one.iter().any(|f| f.norm() > 0.0));
        for (n, (a, b)) in one.iter().zip(&two).enumerate() {
            assert_eq!(
                (a.x.to_bits(), a.y.to_bits()),
                (b.x.to_bits(), b.y.to_bits()),
                "node {n}"
            );
        }
    }

    /// The CST against a hand value: the right triangle (0,0), (1,0), (0,1) has B with rows
    /// (−1, 0, 1, 0, 0, 0), (0, −1, 0, 0, 0, 1), (−1, −1, 0, 1, 1, 0) and A = ½, so
    /// K₀₀ = ½ (D₀₀ + D₂₂) and K₀₁ = ½ (D₀₁ + D₂₂); its smallest altitude is 1/√2. A clockwise
    /// triangle is refused with its tag.
    #[test]
    fn cst_hand_values_length_and_inversion() {
        let d = material().d_matrix();
        let c = [
            Vector2::new(0.0, 0.0),
            Vector2::new(1.0, 0.0),
            Vector2::new(0.0, 1.0),
        ];
        let k = cst_stiffness(&c, &d).unwrap();
        assert!((k[0][0] - 0.5 * (d[0][0] + d[2][2])).abs() <= 1e-12 * d[0][0]);
        assert!((k[0][1] - 0.5 * (d[0][1] + d[2][2])).abs() <= 1e-12 * d[0][0]);
        let mesh = mesh_of(c.to_vec(), vec![(ElementKind::T3, vec![0, 1, 2])]);
        let bulk = UnstructuredBulk::new(&mesh, &d, 1230.0).unwrap();
        assert!((bulk.min_length() - 0.5f64.sqrt()).abs() < 1e-15);
        let bad = mesh_of(c.to_vec(), vec![(ElementKind::T3, vec![0, 2, 1])]);
        assert!(matches!(
            UnstructuredBulk::new(&bad, &d, 1230.0),
            Err(UnstructuredError::InvertedElement { element: 1, .. })
        ));
        assert!(UnstructuredBulk::new(&mesh, &d, 0.0).is_err());
    }
}
