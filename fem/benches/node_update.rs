//! The node update of an unsampled step (`solver::node`): a = f/m, the corrector v += ½Δt a, the
//! stability guard's max |v|², and the next step's predictor, on consecutive nodes. Each build the
//! CPU runs (eight lanes with AVX-512F, four with AVX2, node by node), reported per node
//! (Throughput::Elements); and the corrector alone (a sampled step) and the predictor alone (the
//! step after it), the CPU's widest build against node by node. On two sizes:
//! - `row_499`: the interior nodes of one layer of the centre crack's grid, as the one-pass sweep
//!   hands them over, all in the L1 cache;
//! - `mesh_126000`: about the 125 751 nodes of that grid in one span, 7 MB of u, v, f and m, which
//!   the L2 cache cannot hold.
//!
//! Every build gives the same bits (`solver::node` tests); only their speed differs.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Vector2;
use std::hint::black_box;

#[allow(dead_code, unused_imports)]
#[path = "../src/solver/node.rs"]
mod node;

use node::Span;

/// A build of the update: the span, the accelerations out (x, y pairs; the fused update leaves
/// them), Δt, the running max |v|².
type Build = fn(Span<'_>, &mut [f64], f64, &mut f64);

/// The fused update (corrector and next predictor) of an unsampled step, in every build the CPU
/// runs, and the corrector alone of a sampled step (a stored), node by node and in the CPU's
/// widest build.
fn builds() -> Vec<(&'static str, Build)> {
    let mut out: Vec<(&'static str, Build)> = vec![
        ("node_by_node", |s, _, dt, x| node::advance_from(s, dt, x, 0)),
        ("correct_node_by_node", |s, a, dt, x| {
            node::correct_from(s, a, dt, x, 0)
        }),
        ("correct_all", |s, a, dt, x| {
            node::correct_all(s, bytemuck::cast_slice_mut(a), dt, x)
        }),
    ];
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU reported AVX2 at run time.
            out.push(("avx2", |s, _, dt, x| unsafe {
                node::update_avx2::<true>(s, &mut [], dt, x)
            }));
        }
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU reported AVX-512F at run time.
            out.push(("avx512", |s, _, dt, x| unsafe {
                node::update_avx512::<true>(s, &mut [], dt, x)
            }));
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    // masses of 1 mm steel squares [kg/m], forces [N/m] and a step [s] of the centre crack's
    // order: over 10⁸ calls v and u stay below 1e7, normal numbers
    let dt = 1.5e-7;
    for (size, n) in [("row_499", 499usize), ("mesh_126000", 126_000)] {
        let m: Vec<f64> = (0..n)
            .map(|k| 7.85e-3 * (1.0 + 0.25 * ((k % 3) as f64)))
            .collect();
        let f: Vec<f64> = (0..2 * n).map(|k| (k as f64 * 0.37).sin() * 1e3).collect();
        let mut group = c.benchmark_group(format!("node_update/{size}"));
        group.throughput(Throughput::Elements(n as u64));
        let (mut u, mut v) = (vec![Vector2::zeros(); n], vec![Vector2::zeros(); n]);
        let mut a = vec![0.0; 2 * n];
        for (name, build) in builds() {
            group.bench_function(name, |b| {
                b.iter(|| {
                    let mut vmax2 = 0.0;
                    let nodes = Span {
                        u: &mut u,
                        v: &mut v,
                        f: &f,
                        m: &m,
                    };
                    build(nodes, &mut a, dt, &mut vmax2);
                    black_box(vmax2)
                })
            });
        }
        // the predictor alone, of the step after a sampled one
        let a: Vec<Vector2<f64>> = bytemuck::cast_slice(&a).to_vec();
        group.bench_function("predict_node_by_node", |b| {
            b.iter(|| {
                for ((u, v), a) in u.iter_mut().zip(v.iter_mut()).zip(&a) {
                    node::predict(u, v, a, dt);
                }
            })
        });
        group.bench_function("predict_all", |b| {
            b.iter(|| node::predict_all(&mut u, &mut v, &a, dt))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
