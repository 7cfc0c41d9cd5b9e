//! Criterion benchmark of the contact pass (docs/fem-model.md §5; paper Algorithm 1): bucket-grid
//! rebuild + narrow phase + normal penalty + friction return map + averaged scatter, on the two
//! faces of the centre-crack interface at paper resolution (500 + 500 segments, h = 1 mm),
//! pressed (p_N ≈ 0.05 MPa) and sliding back and forth with friction μ = 0.3.
//! Then the same on rough faces of 500, 2 500 and 5 000 segments each (up to 10 002 contact
//! nodes). Reported throughput: slaves (nodes of Γ_det) per second, i.e. ns per slave-step.
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
use preflight::testing::time_on_awake_pool;
use std::hint::black_box;

#[path = "../src/contact/mod.rs"]
mod contact;

#[path = "../src/hint.rs"]
mod hint;

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

/// Height [m] of a rough profile at x [m]: three sines of wavelengths 8 to 93.5 mm (the band of
/// `scenes/rough-interface.toml`), each of slope amplitude about 0.09 (RMS slope 0.11).
fn rough(x: f64) -> f64 {
    [
        (0.0935, 1.4e-3, 0.3),
        (0.031, 0.45e-3, 1.1),
        (0.008, 0.12e-3, 2.0),
    ]
    .iter()
    .map(|&(l, a, phase)| a * (std::f64::consts::TAU * x / l + phase).sin())
    .sum()
}

/// Lower face (top of the lower half, segments right → left) and upper face (bottom of the upper
/// half, left → right, shifted by 0.37 h), `segments` per face of length `h` [m], on the profile
/// `height`, the upper face 2.4e-6 m into the lower one.
fn faces(segments: usize, h: f64, height: impl Fn(f64) -> f64) -> (Vec<Vector2<f64>>, DetectionSurface) {
    let n = segments + 1;
    let at = |k: f64, dy: f64| {
        let x = -0.25 + k * h;
        Vector2::new(x, height(x) + dy)
    };
    let mut x: Vec<Vector2<f64>> = (0..n).map(|k| at(k as f64, 0.0)).collect();
    x.extend((0..n).map(|k| at(k as f64 + 0.37, -2.4e-6)));
    let mut surface = DetectionSurface::with_capacity(2 * n, 2 * segments);
    for k in 0..segments as u32 {
        surface.add_segment(k + 1, k);
    }
    for k in 0..segments as u32 {
        surface.add_segment(n as u32 + k, n as u32 + k + 1);
    }
    (x, surface)
}

/// One contact pass per iteration on `faces`, the upper face sliding by ±1 µm per step (slip
/// at the Coulomb limit, reversing).
fn bench_faces(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    name: &str,
    (mut x, mut surface): (Vec<Vector2<f64>>, DetectionSurface),
    h: f64,
) {
    let n = x.len();
    let params = ContactParams {
        eps_n: 2.1e10,
        eps_t: 2.1e10,
        friction_coeff: 0.3,
        max_gap: h,
        projection_tolerance: 1e-3,
        prakash_ratio: None,
    };
    let twins = vec![u32::MAX; n];
    let mut state = ContactState::new(n, surface.num_segments());
    let mut ws = ContactWorkspace::new(n, surface.num_segments());
    let mut f = vec![Vector2::zeros(); n];
    let slaves = surface.nodes().len() as u64;
    let upper = n / 2;
    let mut sign = 1.0;
    group.throughput(Throughput::Elements(slaves));
    group.bench_function(name, |b| {
        b.iter_custom(|iters| {
            time_on_awake_pool(iters, || {
                sign = -sign;
                for p in &mut x[upper..] {
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
                summary.contacts
            })
        })
    });
}

/// The centre crack's flat faces at paper resolution, then rough faces of 500, 2 500 and 5 000
/// segments each (1 002 to 10 002 contact nodes; h = 1, 0.2 and 0.1 mm over the same 0.5 m):
/// the cost per contact node as the interface grows (docs/performance.md, "Contact at scale").
fn bench_resolve(c: &mut Criterion) {
    let mut group = c.benchmark_group("contact");
    bench_faces(
        &mut group,
        "resolve_500+500_segments_sliding",
        faces(SEGMENTS, H, |_| 0.0),
        H,
    );
    for segments in [500, 2_500, 5_000] {
        let h = 0.5 / segments as f64;
        bench_faces(
            &mut group,
            &format!("resolve_rough_{segments}+{segments}_segments_sliding"),
            faces(segments, h, rough),
            h,
        );
    }
    group.finish();
}

criterion_group!(benches, bench_resolve);
criterion_main!(benches);
