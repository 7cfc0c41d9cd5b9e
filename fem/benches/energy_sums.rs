//! The sums of a record step (`model::reduce::ordered_sum`): the kinetic energy ½ Σ m |v|² and the
//! strain energy ½ Σ u · f_int over every node, in an order that depends only on the node count,
//! so that a record has the same bits whatever the number of threads. Reported per node
//! (Throughput::Elements), on about the 125 751 nodes of the centre crack's grid (2 MB of v and
//! 1 MB of m for the kinetic sum, 4 MB of u and f for the strain energy), on one thread and on
//! the global pool; and the plain sum in index order on one thread, which has the bits of no
//! thread count but costs what one pass over the data costs, as the floor to compare with.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Vector2;
use std::hint::black_box;

#[allow(dead_code, unused_imports)]
#[path = "../src/model/reduce.rs"]
mod reduce;

fn bench(c: &mut Criterion) {
    let n = 125_751usize;
    // masses of 1 mm steel squares [kg/m], velocities [m/s], displacements [m], forces [N/m] of
    // the centre crack's order
    let m: Vec<f64> = (0..n)
        .map(|k| 7.85e-3 * (1.0 + 0.25 * ((k % 3) as f64)))
        .collect();
    let wave = |k: usize, s: f64| Vector2::new((k as f64 * s).sin(), (k as f64 * s).cos());
    let v: Vec<Vector2<f64>> = (0..n).map(|k| wave(k, 0.37) * 3.0).collect();
    let u: Vec<Vector2<f64>> = (0..n).map(|k| wave(k, 0.11) * 1e-6).collect();
    let f: Vec<Vector2<f64>> = (0..n).map(|k| wave(k, 0.23) * 1e3).collect();
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let mut group = c.benchmark_group("energy_sums/mesh_125751");
    group.throughput(Throughput::Elements(n as u64));
    let kinetic = |i: usize| m[i] * v[i].norm_squared();
    let strain = |i: usize| u[i].dot(&f[i]);
    group.bench_function("kinetic_ordered_one_thread", |b| {
        b.iter(|| one.install(|| black_box(0.5 * reduce::ordered_sum(n, kinetic))))
    });
    group.bench_function("kinetic_ordered_pool", |b| {
        b.iter(|| black_box(0.5 * reduce::ordered_sum(n, kinetic)))
    });
    group.bench_function("kinetic_plain_one_thread", |b| {
        b.iter(|| black_box(0.5 * (0..n).map(kinetic).sum::<f64>()))
    });
    group.bench_function("strain_ordered_one_thread", |b| {
        b.iter(|| one.install(|| black_box(-0.5 * reduce::ordered_sum(n, strain))))
    });
    group.bench_function("strain_ordered_pool", |b| {
        b.iter(|| black_box(-0.5 * reduce::ordered_sum(n, strain)))
    });
    group.bench_function("strain_plain_one_thread", |b| {
        b.iter(|| black_box(-0.5 * (0..n).map(strain).sum::<f64>()))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
