//! Bulk internal-force kernels, reported per element-step (Throughput::Elements):
//! - the paper's centre-crack mesh (500 × 250 identical squares, shared K_e, rayon gather);
//! - the sinusoidal-interface mesh (750 × 250 vertical-sided quads, forces computed on the fly),
//!   and its kernel alone on one thread (`sinusoid_mapped_750x250_kernel_alone`: the element
//!   forces of every row, not summed into the nodes; `_kernel_cold`: the same after 64 MiB have
//!   been written over the caches, as the rest of a step does in a run: every cache of a 32 MiB
//!   L3); the same scene with elements five times larger (`sinusoid_mapped_150x50`), whose
//!   kernel's arrays stay in L2;
//! - the centre crack's Gmsh triangle mesh (`meshes/center-crack-tri.msh`, 43 138 T3, the
//!   unstructured kernel in its own node order, with the copies into and out of it);
//! - the unstructured kernel (`fem::model::unstructured`) on the centre-crack rectangle written
//!   as an unstructured mesh: 500 × 250 Q4, and the same squares split into 250 000 T3; and the
//!   Q4 kernel on 60 × 30 squares, whose arrays stay in a core's L2 cache.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fem::gmsh::{BulkElement, ElementKind, UnstructuredMesh};
use fem::model::unstructured::{BulkMaterial, UnstructuredBulk};
use fem::nalgebra::Vector2;
use preflight::testing::time_on_awake_pool;

/// A smooth, non-trivial displacement field of n nodes [m].
fn displacements(n: usize) -> Vec<Vector2<f64>> {
    (0..n)
        .map(|i| Vector2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()) * 1e-6)
        .collect()
}

/// Benchmarks one f_int evaluation on the mesh of `scene` (a file in scenes/).
fn bench_scene(c: &mut Criterion, name: &str, scene: &str) {
    let path = format!("{}/../scenes/{scene}", env!("CARGO_MANIFEST_DIR"));
    let scene = fem::Scene::from_file(std::path::Path::new(&path)).unwrap();
    bench_model(c, name, &scene, Kernel::AlsoCold);
}

/// Which runs of a mapped mesh's kernel alone [`bench_model`] adds to the whole evaluation.
#[derive(PartialEq)]
enum Kernel {
    /// The kernel on arrays left in the caches by the evaluation before.
    Warm,
    /// That, and the kernel after every cache has been written over.
    AlsoCold,
}

/// Bytes written over between two evaluations of `*_kernel_cold`: twice the 32 MiB last-level
/// cache of the AMD EPYC machines of docs/performance.md (less than the 300 and 480 MiB of the
/// Intel Xeons there, whose last-level cache it does not empty).
const FLUSH_BYTES: usize = 64 << 20;

/// Benchmarks one f_int evaluation on the mesh of `scene`, and on a mapped mesh its kernel alone.
fn bench_model(c: &mut Criterion, name: &str, scene: &fem::Scene, kernel: Kernel) {
    let (model, _, _) = fem::build(scene).unwrap();
    let n = model.num_nodes();
    let u = displacements(n);
    let mut f = vec![Vector2::zeros(); n];
    let mut g = c.benchmark_group("bulk_forces");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function(name, |b| {
        b.iter_custom(|iters| time_on_awake_pool(iters, || fem::probe::bulk_forces(&model, &u, &mut f)))
    });
    // On a mapped mesh, its kernel alone on one thread: the element forces of every row into one
    // row buffer, neither summed into the nodes nor zeroed, against the multiplies it must do
    // (docs/performance.md, "The mapped kernel alone against its multiplies").
    let mut row = Vec::new();
    if fem::probe::mapped_element_forces(&model, &u, &mut row).is_some() {
        g.bench_function(format!("{name}_kernel_alone"), |b| {
            b.iter_custom(|iters| {
                time_on_awake_pool(iters, || fem::probe::mapped_element_forces(&model, &u, &mut row))
            })
        });
        // The same after every cache has been written over, as in a run, where the rest of the
        // step's arrays pass through the caches between two evaluations: only the kernel is timed.
        if kernel == Kernel::AlsoCold {
            let mut flush = vec![0u64; FLUSH_BYTES / 8];
            g.bench_function(format!("{name}_kernel_cold"), |b| {
                b.iter_custom(|iters| {
                    let mut timed = std::time::Duration::ZERO;
                    for k in 0..iters {
                        flush.fill(k);
                        std::hint::black_box(&mut flush);
                        let start = std::time::Instant::now();
                        std::hint::black_box(fem::probe::mapped_element_forces(&model, &u, &mut row));
                        timed += start.elapsed();
                    }
                    timed
                })
            });
        }
    }
    g.finish();
}

/// The sinusoidal-interface scene with elements five times larger (150 × 50, 7 500 elements):
/// its mapped kernel's arrays (about 0.5 MB: 48 B of shapes an element, 16 B a node of u) stay in a
/// core's L2 cache.
fn small_sinusoid() -> fem::Scene {
    let text = preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), "sinusoidal-interface");
    let (from, to) = ("element_size = 1e-3 ", "element_size = 5e-3 ");
    assert!(text.contains(from), "sinusoidal-interface.toml: no `{from}`");
    fem::Scene::from_toml_str(&text.replacen(from, to, 1)).unwrap()
}

/// The centre-crack rectangle (0.5 m × 0.25 m, 1 mm squares, nx × ny) as an unstructured mesh:
/// Q4 squares, or each square split along its diagonal into two T3.
fn grid_mesh(nx: usize, ny: usize, triangles: bool) -> UnstructuredMesh {
    let h = 1e-3;
    let positions: Vec<Vector2<f64>> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| Vector2::new(i as f64 * h, j as f64 * h)))
        .collect();
    let node = |i: usize, j: usize| j * (nx + 1) + i;
    let mut elements = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let q = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
            let mut push = |kind, nodes: Vec<usize>| {
                let tag = elements.len() as u64 + 1;
                elements.push(BulkElement { tag, kind, nodes });
            };
            if triangles {
                push(ElementKind::T3, vec![q[0], q[1], q[2]]);
                push(ElementKind::T3, vec![q[0], q[2], q[3]]);
            } else {
                push(ElementKind::Q4, q.to_vec());
            }
        }
    }
    UnstructuredMesh {
        node_tags: (1..=positions.len() as u64).collect(),
        positions,
        elements,
        lines: Vec::new(),
        groups: Default::default(),
        reoriented: 0,
        warnings: Vec::new(),
    }
}

/// Benchmarks one f_int evaluation of the unstructured kernel on an nx × ny grid mesh; with
/// `two_materials`, the elements of the right half have a second material (the per-element D
/// path of `[fem.mesh.materials]`).
fn bench_unstructured(
    c: &mut Criterion,
    name: &str,
    (nx, ny): (usize, usize),
    triangles: bool,
    two_materials: bool,
) {
    let mesh = grid_mesh(nx, ny, triangles);
    let mat = fem::law::elastic::PlaneStrain::new(70e6, 0.35, 1230.0);
    let bulk = if two_materials {
        let stiff = fem::law::elastic::PlaneStrain::new(560e6, 0.35, 2460.0);
        let table = [mat, stiff].map(|m| BulkMaterial {
            d: m.d_matrix(),
            density: m.density,
        });
        let index: Vec<u8> = mesh
            .elements
            .iter()
            .map(|e| (mesh.positions[e.nodes[0]].x >= 0.25) as u8)
            .collect();
        UnstructuredBulk::with_materials(&mesh, &table, &index).unwrap()
    } else {
        UnstructuredBulk::new(&mesh, &mat.d_matrix(), mat.density).unwrap()
    };
    let n = bulk.num_nodes();
    println!(
        "{name}: kernel arrays {} B for {n} nodes, {:.1} B per node",
        bulk.memory_bytes(),
        bulk.memory_bytes() as f64 / n as f64
    );
    let u = displacements(n);
    let mut f = vec![Vector2::zeros(); n];
    let mut g = c.benchmark_group("bulk_forces");
    g.throughput(Throughput::Elements(mesh.elements.len() as u64));
    g.bench_function(name, |b| {
        b.iter_custom(|iters| time_on_awake_pool(iters, || bulk.internal_forces(&u, &mut f)))
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    bench_scene(c, "center_crack_500x250", "center-crack.toml");
    bench_scene(c, "sinusoid_mapped_750x250", "sinusoidal-interface.toml");
    // per element against the 750 × 250 mesh, whether the mapped kernel's bytes bind it
    bench_model(c, "sinusoid_mapped_150x50", &small_sinusoid(), Kernel::Warm);
    bench_scene(c, "center_crack_tri_43138", "center-crack-tri.toml");
    bench_unstructured(c, "unstructured_q4_500x250", (500, 250), false, false);
    // the same kernel on 1 800 squares, whose arrays (about 0.3 MB) stay in a core's L2 cache:
    // per element against the 500 × 250 mesh, whether its bytes bind it
    bench_unstructured(c, "unstructured_q4_60x30", (60, 30), false, false);
    bench_unstructured(c, "unstructured_t3_500x250x2", (500, 250), true, false);
    bench_unstructured(
        c,
        "unstructured_q4_500x250_two_materials",
        (500, 250),
        false,
        true,
    );
    bench_unstructured(
        c,
        "unstructured_t3_500x250x2_two_materials",
        (500, 250),
        true,
        true,
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
