//! One whole explicit step, reported per element-step (Throughput::Elements), on the three kinds
//! of bulk mesh, side by side:
//! - the paper's centre crack at paper resolution (500 × 250 identical Q4: the stencil), pre-crack
//!   faces in contact, μ = 0.3;
//! - the sinusoidal interface (750 × 250 vertical-sided Q4 of a mapped mesh: forces on the fly);
//! - the centre crack on the Gmsh triangle mesh (43 138 T3: the unstructured edge kernel).
//!
//! Bulk forces, cohesive law, contact, boundary, the corrector (fused with the next predictor on
//! the grids) and the insertion check. Each state is first advanced through 0.46 T (faces pressed
//! and slipping, the crack running), and keeps advancing while measured; no step of the run is
//! sampled.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn bench_scene(c: &mut Criterion, name: &str, file: &str) {
    let path = format!("{}/../scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    let scene = fem::Scene::from_file(std::path::Path::new(&path)).unwrap();
    let (model, mut state, mut ws) = fem::build(&scene).unwrap();
    let warm = (0.46 * scene.duration() / model.time_step()) as usize;
    for _ in 0..warm {
        fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap();
    }
    let mut g = c.benchmark_group("step");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function(name, |b| {
        b.iter(|| fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap())
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    bench_scene(c, "center_crack_500x250", "center-crack.toml");
    bench_scene(c, "sinusoid_mapped_750x250", "sinusoidal-interface.toml");
    bench_scene(c, "center_crack_tri_43138", "center-crack-tri.toml");
}

criterion_group!(benches, bench);
criterion_main!(benches);
