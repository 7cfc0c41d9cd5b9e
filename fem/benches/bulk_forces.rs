//! Bulk internal-force kernels, reported per element-step (Throughput::Elements):
//! - the paper's centre-crack mesh (500 × 250 identical squares, shared K_e, rayon gather);
//! - the sinusoidal-interface mesh (750 × 250 vertical-sided quads, forces computed on the fly).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fem::nalgebra::Vector2;

/// Benchmarks one f_int evaluation on the mesh of `scene` (a file in scenes/).
fn bench_scene(c: &mut Criterion, name: &str, scene: &str) {
    let path = format!("{}/../scenes/{scene}", env!("CARGO_MANIFEST_DIR"));
    let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let (model, _, _) = fem::build(&scene).unwrap();
    let n = model.num_nodes();
    let u: Vec<Vector2<f64>> = (0..n)
        .map(|i| Vector2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()) * 1e-6)
        .collect();
    let mut f = vec![Vector2::zeros(); n];
    let mut g = c.benchmark_group("bulk_forces");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function(name, |b| b.iter(|| fem::probe::bulk_forces(&model, &u, &mut f)));
    g.finish();
}

fn bench(c: &mut Criterion) {
    bench_scene(c, "center_crack_500x250", "center-crack.toml");
    bench_scene(c, "sinusoid_mapped_750x250", "sinusoidal-interface.toml");
}

criterion_group!(benches, bench);
criterion_main!(benches);
