//! One whole explicit step of the paper's centre crack at paper resolution (500 × 250 Q4,
//! pre-crack faces in contact, μ = 0.3): bulk forces, cohesive law, contact, boundary, the fused
//! corrector-predictor and the insertion check, reported per element-step
//! (Throughput::Elements). The state is first advanced 6000 steps (0.46 T, faces pressed and
//! slipping), and keeps advancing while measured; no step of the run is sampled.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let path = format!("{}/../scenes/center-crack.toml", env!("CARGO_MANIFEST_DIR"));
    let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let (model, mut state, mut ws) = fem::build(&scene).unwrap();
    for _ in 0..6000 {
        fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap();
    }
    let mut g = c.benchmark_group("step");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    g.bench_function("center_crack_500x250", |b| {
        b.iter(|| fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
