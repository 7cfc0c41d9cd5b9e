//! Bulk internal-force kernel (Q4, shared K_e, rayon gather) on the paper's centre-crack mesh
//! (500 × 250 elements): reports time per element-step (Throughput::Elements).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fem::nalgebra::Vector2;

fn bench(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/center-crack.toml");
    let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let (model, _, _) = fem::build(&scene).unwrap();
    let n = model.num_nodes();
    let u: Vec<Vector2<f64>> = (0..n)
        .map(|i| Vector2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()) * 1e-6)
        .collect();
    let mut f = vec![Vector2::zeros(); n];
    let mut g = c.benchmark_group("bulk_forces");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function("center_crack_500x250", |b| {
        b.iter(|| fem::probe::bulk_forces(&model, &u, &mut f))
    });
    g.finish();
    mapped(c);
}

/// The mapped mesh of the sinusoidal-interface scene (750 × 250 vertical-sided quads, forces
/// computed on the fly from four numbers per element).
fn mapped(c: &mut Criterion) {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/sinusoidal-interface.toml");
    let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let (model, _, _) = fem::build(&scene).unwrap();
    let n = model.num_nodes();
    let u: Vec<Vector2<f64>> = (0..n)
        .map(|i| Vector2::new((i as f64 * 0.37).sin(), (i as f64 * 0.11).cos()) * 1e-6)
        .collect();
    let mut f = vec![Vector2::zeros(); n];
    let mut g = c.benchmark_group("bulk_forces");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function("sinusoid_mapped_750x250", |b| {
        b.iter(|| fem::probe::bulk_forces(&model, &u, &mut f))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
