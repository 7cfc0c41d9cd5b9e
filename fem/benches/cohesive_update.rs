//! Cohesive element update (mid-line normal, 2 Gauss points of the linear coupled law, nodal
//! forces) for 500 elements in the process zone: time per element update (Throughput::Elements).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fem::law::cohesive::{ClosingTreatment, CohesiveState, LinearCohesive};
use fem::model::cohesive::{FacetGeometry, element_forces};
use fem::nalgebra::Vector2;

fn bench(c: &mut Criterion) {
    let law = LinearCohesive {
        sigma_c: 0.4e6,
        delta_c: 1e-4,
        beta: 1.0,
        kappa: 1.0,
    };
    let h = 1e-3;
    let n = 500;
    let geometry = FacetGeometry { length: h, sign: 1.0 };
    let x0: Vec<[Vector2<f64>; 4]> = (0..n)
        .map(|i| {
            let (xa, xb) = (i as f64 * h, (i + 1) as f64 * h);
            [
                Vector2::new(xa, 0.0),
                Vector2::new(xb, 0.0),
                Vector2::new(xa, 0.0),
                Vector2::new(xb, 0.0),
            ]
        })
        .collect();
    let u: Vec<[Vector2<f64>; 4]> = (0..n)
        .map(|i| {
            let o = Vector2::new(
                2e-5 * (i as f64 * 0.1).sin(),
                3e-5 + 1e-6 * (i as f64 * 0.3).cos(),
            );
            [o, o * 1.01, Vector2::zeros(), Vector2::zeros()]
        })
        .collect();
    let base = CohesiveState {
        delta_max: 1e-5,
        damage: 0.1,
        ..CohesiveState::inserted(&law, law.sigma_c, Vector2::new(0.0, law.sigma_c))
    };
    let mut states = vec![[base; 2]; n];
    let mut g = c.benchmark_group("cohesive_update");
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("hybrid_500_elements", |b| {
        b.iter(|| {
            let mut sum = Vector2::zeros();
            for i in 0..n {
                let x = [0, 1, 2, 3].map(|k| x0[i][k] + u[i][k]);
                let out = element_forces(
                    &law,
                    ClosingTreatment::Hybrid,
                    &geometry,
                    &x,
                    &u[i],
                    &mut states[i],
                );
                sum += out.force[0];
            }
            sum
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
