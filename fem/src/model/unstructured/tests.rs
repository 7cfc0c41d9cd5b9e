//! Tests of the unstructured bulk kernel: patch tests on the committed meshes, rigid motion,
//! masses, forces against the element-by-element sum, materials, thread independence.

use super::*;
use crate::law::elastic::PlaneStrain;
use crate::mesh::gmsh::BulkElement;
use crate::mesh::structured::{Grid, GridSpec};
use std::collections::BTreeMap;

/// The old formulation, as reference: f_a = −Σ_e K_e[a-rows] u_e in mesh element order, with
/// K_e from `cst_stiffness` and `bulk::stiffness`.
fn reference_forces(mesh: &UnstructuredMesh, d: &[[f64; 3]; 3], u: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
    reference_forces_of(mesh, &|_| *d, u)
}

/// As [`reference_forces`], element e with the Voigt matrix `d_of(e)`.
fn reference_forces_of(
    mesh: &UnstructuredMesh,
    d_of: &dyn Fn(usize) -> [[f64; 3]; 3],
    u: &[Vector2<f64>],
) -> Vec<Vector2<f64>> {
    let mut f = vec![Vector2::zeros(); u.len()];
    for (e, el) in mesh.elements.iter().enumerate() {
        let d = &d_of(e);
        let c: Vec<Vector2<f64>> = el.nodes.iter().map(|&a| mesh.positions[a]).collect();
        let k: Vec<Vec<f64>> = match el.kind {
            ElementKind::T3 => cst_stiffness(&[c[0], c[1], c[2]], d)
                .unwrap()
                .iter()
                .map(|r| r.to_vec())
                .collect(),
            ElementKind::Q4 => bulk::stiffness(&[c[0], c[1], c[2], c[3]], d)
                .unwrap()
                .iter()
                .map(|r| r.to_vec())
                .collect(),
        };
        for (i, &a) in el.nodes.iter().enumerate() {
            for (j, &b) in el.nodes.iter().enumerate() {
                for r in 0..2 {
                    f[a][r] -= k[2 * i + r][2 * j] * u[b].x + k[2 * i + r][2 * j + 1] * u[b].y;
                }
            }
        }
    }
    f
}

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

/// A distorted nx × ny grid on [0, 0.01 nx] × [0, 0.01 ny] m, no two elements alike: every
/// third square split into two T3, the others Q4. `scramble` renumbers the nodes by a
/// multiplicative permutation (neighbours far apart in the numbering).
fn distorted_mixed(nx: usize, ny: usize, scramble: bool) -> UnstructuredMesh {
    let nn = (nx + 1) * (ny + 1);
    let perm = |n: usize| if scramble { (n * 7919) % nn } else { n };
    let mut positions = vec![Vector2::zeros(); nn];
    for j in 0..=ny {
        for i in 0..=nx {
            let (x, y) = (i as f64 * 0.01, j as f64 * 0.01);
            positions[perm(j * (nx + 1) + i)] =
                Vector2::new(x + 0.002 * (7.0 * y).sin(), y + 0.002 * (5.0 * x).cos());
        }
    }
    let node = |i: usize, j: usize| perm(j * (nx + 1) + i);
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
    mesh_of(positions, elements)
}

/// A displacement field without symmetry [m].
fn wobble(n: usize) -> Vec<Vector2<f64>> {
    (0..n)
        .map(|n| Vector2::new((n as f64 * 0.37).sin(), (n as f64 * 0.11).cos()) * 1e-3)
        .collect()
}

/// The forces are the same to the bit on 1 and 2 threads (each node's sum has a fixed order),
/// on a mixed mesh large enough to be split into several tiles.
#[test]
fn forces_do_not_depend_on_the_thread_count() {
    let mesh = distorted_mixed(60, 40, false);
    let mat = material();
    let bulk = UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap();
    assert!(bulk.tiles.len() > 2, "{} tiles", bulk.tiles.len());
    let u = wobble(bulk.num_nodes());
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| forces(&bulk, &u))
    };
    let (one, two) = (run(1), run(2));
    assert!(one.iter().any(|f| f.norm() > 0.0));
    assert_same_bits(&one, &two);
}

/// Every component of `a` has the bits of the same component of `b`.
fn assert_same_bits(a: &[Vector2<f64>], b: &[Vector2<f64>]) {
    for (n, (a, b)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            (a.x.to_bits(), a.y.to_bits()),
            (b.x.to_bits(), b.y.to_bits()),
            "node {n}"
        );
    }
}

/// The element forces computed from the positions (ε = B u_e, σ = D ε, Bᵀσ) are those of the
/// stored-K_e formulation to round-off: 1e-12 of the largest force. The two sum the same
/// terms in another order, each force being ≲ 50 products of size |K| |u|; the distorted
/// elements make every K_e different, and the scrambled numbering gives tiles with elements
/// far apart.
#[test]
fn forces_match_the_stiffness_matrices() {
    let mat = material();
    let d = mat.d_matrix();
    for scramble in [false, true] {
        let mesh = distorted_mixed(60, 40, scramble);
        let bulk = UnstructuredBulk::new(&mesh, &d, mat.density).unwrap();
        // a grid numbered row by row keeps its order; scrambled, the kernel takes its own
        assert_eq!(bulk.order.is_empty(), !scramble);
        let u = wobble(bulk.num_nodes());
        let f = forces(&bulk, &u);
        let g = reference_forces(&mesh, &d, &u);
        let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for (n, (a, b)) in f.iter().zip(&g).enumerate() {
            assert!(
                (a - b).norm() <= 1e-12 * scale,
                "scramble {scramble}, node {n}: {a} vs {b}"
            );
        }
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

/// Two materials, (E, ν, ρ) and (8E, 0.25, 2ρ), on the elements of a distorted mixed mesh in a
/// scattered pattern: forces against Σ K_e u_e with each element's own D (round-off, 1e-12
/// of the largest force, as the one-material test), masses against ρ_e A_e summed, the same
/// bits on 1 and 2 threads, and the smallest transit time against
/// min_e h_e/c_d,e.
#[test]
fn two_materials_use_each_elements_own() {
    let mesh = distorted_mixed(60, 40, true);
    let (m0, m1) = (material(), PlaneStrain::new(560e6, 0.25, 2460.0));
    let table = [m0, m1].map(|m| BulkMaterial {
        d: m.d_matrix(),
        density: m.density,
    });
    let index: Vec<u8> = (0..mesh.elements.len())
        .map(|e| ((e * 7) % 3 == 0) as u8)
        .collect();
    let bulk = UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap();
    let u = wobble(bulk.num_nodes());
    let f = forces(&bulk, &u);
    let g = reference_forces_of(&mesh, &|e| table[index[e] as usize].d, &u);
    let scale = g.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for (n, (a, b)) in f.iter().zip(&g).enumerate() {
        assert!((a - b).norm() <= 1e-12 * scale, "node {n}: {a} vs {b}");
    }
    let one_d = reference_forces(&mesh, &table[0].d, &u);
    assert!(f.iter().zip(&one_d).any(|(a, b)| (a - b).norm() > 1e-3 * scale));
    // masses: ρ_e A_e over the elements
    let area = |e: usize| {
        let c: Vec<Vector2<f64>> = mesh.elements[e]
            .nodes
            .iter()
            .map(|&a| mesh.positions[a])
            .collect();
        0.5 * (0..c.len())
            .map(|k| c[k].perp(&c[(k + 1) % c.len()]))
            .sum::<f64>()
    };
    let total: f64 = (0..mesh.elements.len())
        .map(|e| table[index[e] as usize].density * area(e))
        .sum();
    let summed: f64 = bulk.masses().iter().sum();
    assert!((summed - total).abs() <= 1e-12 * total, "{summed} vs {total}");
    let transit = (0..mesh.elements.len())
        .map(|e| element_length(&mesh, e) / table[index[e] as usize].cd())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(bulk.min_transit_time(), transit);
    assert!(transit < bulk.min_length() / m0.wave_speeds().cd);
    let run = |threads: usize, bulk: &UnstructuredBulk| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| forces(bulk, &u))
    };
    assert_same_bits(&run(1, &bulk), &run(2, &bulk));
}

/// A table of one material repeated splits the elements into two runs of batches, which must
/// give the forces of the one-material kernel: to round-off (1e-12 of the largest force, as
/// the other kernel tests), since a node sums its elements in another order (by material
/// first).
#[test]
fn a_table_of_one_material_gives_the_single_material_forces() {
    let mesh = distorted_mixed(30, 20, false);
    let m = material();
    let one = BulkMaterial {
        d: m.d_matrix(),
        density: m.density,
    };
    let single = UnstructuredBulk::new(&mesh, &one.d, one.density).unwrap();
    let index: Vec<u8> = (0..mesh.elements.len()).map(|e| (e % 2) as u8).collect();
    let table = UnstructuredBulk::with_materials(&mesh, &[one, one], &index).unwrap();
    let u = wobble(single.num_nodes());
    let (a, b) = (forces(&table, &u), forces(&single, &u));
    let scale = b.iter().map(|v| v.norm()).fold(0.0, f64::max);
    for (n, (a, b)) in a.iter().zip(&b).enumerate() {
        assert!((a - b).norm() <= 1e-12 * scale, "node {n}: {a} vs {b}");
    }
    assert_eq!(table.masses(), single.masses());
    assert!(matches!(
        UnstructuredBulk::with_materials(&mesh, &[one], &index),
        Err(UnstructuredError::BadMaterials)
    ));
}

/// The static patch across two materials (`meshes/bimaterial.msh`, "soft" for x < 1 m,
/// "stiff" beyond): under a uniform σ_xx = p with u_y = 0 (rollers on top and bottom), the
/// exact field is u_x = p x/M₁ for x ≤ 1 m and p/M₁ + p (x − 1)/M₂ beyond (M = λ + 2G, each
/// part's own compliance). Bilinear elements hold it exactly, so every node off the two ends
/// is in equilibrium in x (and off the rollers in y) to round-off: 1e-10 of the end forces.
/// The end forces sum to p times the bar's height, on the right end as on the left.
#[test]
fn a_uniform_stress_crosses_two_materials_exactly() {
    let mesh = committed("bimaterial.msh");
    let (soft, stiff) = (material(), PlaneStrain::new(560e6, 0.35, 2460.0));
    let table = [soft, stiff].map(|m| BulkMaterial {
        d: m.d_matrix(),
        density: m.density,
    });
    let mut index = vec![0u8; mesh.elements.len()];
    for &e in &mesh.groups["stiff"].elements {
        index[e] = 1;
    }
    let bulk = UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap();
    let p = 1e5;
    let (m1, m2) = (table[0].d[0][0], table[1].d[0][0]);
    let u: Vec<Vector2<f64>> = mesh
        .positions
        .iter()
        .map(|x| {
            let ux = if x.x <= 1.0 {
                p * x.x / m1
            } else {
                p / m1 + p * (x.x - 1.0) / m2
            };
            Vector2::new(ux, 0.0)
        })
        .collect();
    let f = forces(&bulk, &u);
    let tol = 1e-10 * p * 0.06;
    let (mut left, mut right) = (0.0, 0.0);
    for (n, (x, fa)) in mesh.positions.iter().zip(&f).enumerate() {
        let end = x.x.abs() < 1e-9 || (x.x - 2.5).abs() < 1e-9;
        let roller = x.y.abs() < 1e-9 || (x.y - 0.06).abs() < 1e-9;
        if x.x.abs() < 1e-9 {
            left += fa.x;
        } else if (x.x - 2.5).abs() < 1e-9 {
            right += fa.x;
        }
        assert!(end || fa.x.abs() <= tol, "node {n} at {x}: f_x = {}", fa.x);
        assert!(roller || fa.y.abs() <= tol, "node {n} at {x}: f_y = {}", fa.y);
    }
    // f = −f_int: the left end's nodes need +p h to be held, the right end's −p h
    assert!((left - p * 0.06).abs() <= tol, "{left}");
    assert!((right + p * 0.06).abs() <= tol, "{right}");
}

/// The node pairs of a grid of `nx` × `ny` Q4 numbered row by row, with node row `ny / 2` split
/// as an interface is: the elements above it take twins of its nodes, numbered after all others.
fn twinned_grid_pairs(nx: usize, ny: usize) -> (usize, Vec<EdgeBlock>) {
    let w = nx + 1;
    let grid_nodes = w * (ny + 1);
    let (j0, twin) = (ny / 2, |i: usize| (grid_nodes + i) as u32);
    let mut pairs = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let node = |i: usize, jj: usize| {
                if jj == j0 && j == j0 {
                    twin(i)
                } else {
                    (jj * w + i) as u32
                }
            };
            let c = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
            for a in 0..4 {
                for b in a + 1..4 {
                    pairs.push((c[a].min(c[b]), c[a].max(c[b]), [0.0; 4]));
                }
            }
        }
    }
    pairs.sort_by_key(|&(a, b, _)| (a, b));
    pairs.dedup_by_key(|p| (p.0, p.1));
    (grid_nodes + w, pairs)
}

/// A grid numbered row by row keeps its order even with an interface's twins numbered last (a
/// few far edges: the copies into another order would cost more than they save); the same grid
/// numbered at random takes reverse Cuthill–McKee, whose edges are then all near.
#[test]
fn a_row_numbered_grid_keeps_its_order_and_a_scrambled_one_is_reordered() {
    let (nn, mut pairs) = twinned_grid_pairs(200, 100);
    let far = pairs.iter().filter(|p| p.1 - p.0 > FAR_EDGE).count();
    assert!(
        far > 0 && far as f64 <= FAR_EDGE_SHARE * pairs.len() as f64,
        "{far} far edges"
    );
    let (order, rank) = kernel_order(nn, &mut pairs);
    assert!(order.is_empty() && rank.is_empty());
    // the same graph under a scrambled numbering (a multiplicative permutation of 0..nn)
    let (nn, pairs) = twinned_grid_pairs(200, 100);
    let step = 7919; // prime, not a factor of nn
    assert_ne!(nn % step, 0);
    let scramble = |n: u32| ((n as usize * step) % nn) as u32;
    let mut scrambled: Vec<EdgeBlock> = pairs
        .iter()
        .map(|&(a, b, k)| {
            let (a, b) = (scramble(a), scramble(b));
            (a.min(b), a.max(b), k)
        })
        .collect();
    scrambled.sort_by_key(|&(a, b, _)| (a, b));
    let (order, rank) = kernel_order(nn, &mut scrambled);
    assert_eq!(order.len(), nn);
    for (new, &old) in order.iter().enumerate() {
        assert_eq!(rank[old as usize], new as u32);
    }
    assert!(scrambled.iter().all(|p| p.0 < p.1 && p.1 - p.0 <= FAR_EDGE));
}
