//! The hot loop: one step of the elastodynamic operator (FFT + history convolution + iFFT) with
//! full history windows, for the centre-crack case at paper resolution (N = 4096, tcut = 100,
//! the FE time step c_s Δt/Δx ≈ 0.242, 13 072 steps). Throughput: (mode × history step) pairs for
//! the direct path; modes for the fast path, its states stored in double (`Fast`) and in single
//! precision (`Fast_f32`, `[spectral] fast_storage = "f32"`).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use preflight::testing::time_on_pool;
use spectral::{Convolution, FaceFields, FastStorage, HalfSpaceParams, HalfSpaces};

fn params(convolution: Convolution, fast_storage: FastStorage) -> HalfSpaceParams {
    let (e, nu, rho): (f64, f64, f64) = (70e6, 0.35, 1230.0);
    let mu = e / (2.0 * (1.0 + nu));
    HalfSpaceParams {
        shear_modulus: mu,
        cs: (mu / rho).sqrt(),
        eta: (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt(),
        grid_points: 4096,
        length: 3.75,
        cs_dt_over_dx: 1.53e-6 * (mu / rho).sqrt() / (3.75 / 4096.0),
        kernel_cutoff: 100.0,
        max_steps: 13_072,
        convolution,
        fast_tolerance: spectral::DEFAULT_FAST_TOLERANCE,
        fast_storage,
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("operator_step");
    g.sample_size(20);
    let cases = [
        (Convolution::Direct, FastStorage::F64, "Direct"),
        (Convolution::Fast, FastStorage::F64, "Fast"),
        (Convolution::Fast, FastStorage::F32, "Fast_f32"),
    ];
    for (conv, storage, name) in cases {
        let Ok(mut hs) = HalfSpaces::new(&params(conv, storage)) else {
            continue;
        };
        hs.assume_full_history();
        let stats = hs.stats();
        let elements = if conv == Convolution::Direct {
            stats.history_entries
        } else {
            2048
        };
        eprintln!("{name}: {stats:?}");
        g.throughput(Throughput::Elements(elements));
        let mut u = FaceFields::zeros(4096);
        u.top_x
            .iter_mut()
            .enumerate()
            .for_each(|(m, x)| *x = (m as f64 * 0.01).sin() * 1e-6);
        let mut f = FaceFields::zeros(4096);
        g.bench_function(name, |b| {
            b.iter_custom(|iters| time_on_pool(iters, || hs.step(&u, &mut f)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
