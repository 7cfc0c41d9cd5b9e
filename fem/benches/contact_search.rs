//! Criterion benchmark of the contact pass (docs/fem-model.md §5; paper Algorithm 1): bucket-grid
//! rebuild + narrow phase + normal penalty + friction return map + averaged scatter, on the two
//! faces of the centre-crack interface at paper resolution (500 + 500 segments, h = 1 mm),
//! pressed (p_N ≈ 0.05 MPa) and sliding back and forth with friction μ = 0.3.
//! Reported throughput: slaves (nodes of Γ_det) per second, i.e. ns per slave-step.
//!
//! The contact module is `pub(crate)` (docs/fem-contact-api.md), so the benchmark compiles the
//! module's own source files into this target instead of going through a public re-export.
#![allow(dead_code)]
// the included modules carry items the benchmark does not call
// `clippy --all-targets` builds this target with cfg(test) but without the test harness: the included
// modules' unit-test modules then compile with their #[test] functions stripped.
#![cfg_attr(test, allow(unused_imports))]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Vector2;
use std::hint::black_box;

#[path = "../src/contact/mod.rs"]
mod contact;

#[path = "../src/law/friction.rs"]
mod friction;
#[path = "../src/law/penalty.rs"]
mod penalty;

/// The `crate::law::{friction, penalty}` paths the contact module uses.
mod law {
    pub(crate) use super::{friction, penalty};
}

use contact::{ContactParams, ContactState, ContactWorkspace, DetectionSurface, resolve};

const H: f64 = 1e-3; // m
const SEGMENTS: usize = 500; // per face

/// Lower face (top of the lower half, segments right → left) and upper face (bottom of the upper
/// half, left → right, shifted by 0.37 h), penetration 2.4e-6 m.
fn faces() -> (Vec<Vector2<f64>>, DetectionSurface) {
    let n = SEGMENTS + 1;
    let mut x: Vec<Vector2<f64>> = (0..n).map(|k| Vector2::new(-0.25 + k as f64 * H, 0.0)).collect();
    x.extend((0..n).map(|k| Vector2::new(-0.25 + (k as f64 + 0.37) * H, -2.4e-6)));
    let mut surface = DetectionSurface::with_capacity(2 * n, 2 * SEGMENTS);
    for k in 0..SEGMENTS as u32 {
        surface.add_segment(k + 1, k);
    }
    for k in 0..SEGMENTS as u32 {
        surface.add_segment(n as u32 + k, n as u32 + k + 1);
    }
    (x, surface)
}

fn bench_resolve(c: &mut Criterion) {
    let (mut x, mut surface) = faces();
    let n = x.len();
    let params = ContactParams {
        eps_n: 2.1e10,
        eps_t: 2.1e10,
        friction_coeff: 0.3,
        max_gap: H,
        projection_tolerance: 1e-3,
        prakash_ratio: None,
    };
    let twins = vec![u32::MAX; n];
    let mut state = ContactState::new(n);
    let mut ws = ContactWorkspace::new(n, surface.num_segments());
    let mut f = vec![Vector2::zeros(); n];
    let slaves = surface.nodes().len() as u64;
    let mut sign = 1.0;
    let mut group = c.benchmark_group("contact");
    group.throughput(Throughput::Elements(slaves));
    group.bench_function("resolve_500+500_segments_sliding", |b| {
        b.iter(|| {
            // The upper face slides by ±1 µm per step (slip at the Coulomb limit, reversing).
            sign = -sign;
            for p in &mut x[SEGMENTS + 1..] {
                p.x += sign * 1e-6;
            }
            let summary = resolve(
                &params,
                &mut surface,
                &x,
                &twins,
                &[],
                &mut state,
                &mut ws,
                &mut f,
            );
            black_box(summary.contacts)
        })
    });
    group.finish();
}

criterion_group!(benches, bench_resolve);
criterion_main!(benches);
