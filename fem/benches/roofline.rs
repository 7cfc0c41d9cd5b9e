//! The machine's ceilings for the FE step (its roofline), measured here:
//! - `fma_peak`: fused multiply-adds per second on one core, from independent chains x ← x·a + b
//!   (16 of 8 lanes with AVX-512; 12 of 4 lanes with AVX2, whose 16 registers hold no more
//!   beside the two constants; 16 of one lane in the portable build). Throughput is reported in
//!   FMA lanes (elements): flops = 2 × elements.
//! - `fma_peak_all_cores`: the same chains on every thread of the pool at once, counted over all
//!   of them: divided by its rate on one thread (`RAYON_NUM_THREADS=1`), the number of cores whose
//!   arithmetic the machine gives.
//! - `mul_peak`: multiplies per second on one core, from as many chains x ← (x·a)·b, reported in
//!   multiply lanes: the ceiling of the mapped kernel's multiplies, fused or not.
//! - `div_peak`: divisions per second on one core, from as many chains x ← x / a, reported in
//!   division lanes: the ceiling of the node update, whose a = f/m takes two divisions a node.
//! - `core_to_core_round_trip`: one round trip of a cache line between two threads, which every
//!   hand-over of data from one core to the other pays.
//! - `triad`: a[i] = b[i] + s c[i] (the STREAM triad, 3 × 8 B per element moved, reported in
//!   bytes) on 24 MiB, the size of a paper-resolution step's working set (u, v, f, m and the
//!   mesh's small tables, which a large last-level cache can hold), and on 1 GiB (main memory);
//!   on one thread and on all of the pool's threads, timed on a pool thread as the kernels are.
//!
//! The step needs about 95 flops and moves about 136 B per element (docs/performance.md gives the
//! count), 0.7 flop/B: far below any machine's balance, so its bound is the bandwidth.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use preflight::testing::time_on_awake_pool;
use rayon::prelude::*;
use std::hint::black_box;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Independent chains of the AVX-512 and portable builds: enough to keep two pipes of a
/// four-cycle latency busy, and held in registers (AVX-512 has 32).
const CHAINS: usize = 16;
/// Independent chains of the AVX2 builds: AVX2 has 16 registers, and 16 chains with their two
/// constants sent two or three chains through the stack each round (seen in the disassembly),
/// which timed the stack's round trips, not the arithmetic. Twelve chains and two constants fit;
/// twelve still exceed the eight a four-cycle latency needs on two pipes.
const CHAINS_AVX2: usize = 12;
const ROUNDS: usize = 4096;

/// FMA lanes one call of [`fma`] executes: independent chains ([`CHAINS`], or [`CHAINS_AVX2`]) of
/// `ROUNDS` x ← x·a + b each, on the widest vectors the CPU has (8, 4 or 1 lanes).
fn fma_lanes() -> usize {
    lanes(true)
}

/// Vector lanes of all chains of one round-trip-free call, `ROUNDS` steps each: the builds chosen
/// as [`fma`] chooses them (`fused`) or as [`mul`] and [`div`] do (AVX2 without FMA).
fn lanes(fused: bool) -> usize {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            return CHAINS * ROUNDS * 8;
        }
        if std::arch::is_x86_feature_detected!("avx2")
            && (!fused || std::arch::is_x86_feature_detected!("fma"))
        {
            return CHAINS_AVX2 * ROUNDS * 4;
        }
    }
    let _ = fused;
    CHAINS * ROUNDS
}

/// `$chains` independent chains of `ROUNDS` steps x ← `$step` (x the chain's vector, starting at
/// 1), summed: the SIMD builds of the peaks below.
#[cfg(target_arch = "x86_64")]
macro_rules! chains {
    ($features:literal, $chains:expr, $name:ident($($arg:ident),*), $one:expr, |$x:ident| $step:expr, $sum:expr) => {
        #[target_feature(enable = $features)]
        fn $name($($arg: f64),*) -> f64 {
            use std::arch::x86_64::*;
            let mut x = [$one; $chains];
            for _ in 0..ROUNDS {
                for $x in x.iter_mut() {
                    *$x = $step;
                }
            }
            x.iter().map($sum).sum()
        }
    };
}

/// The sum of an AVX register's four lanes (called by the AVX2 builds only).
#[cfg(target_arch = "x86_64")]
fn sum256(v: &std::arch::x86_64::__m256d) -> f64 {
    let mut out = [0.0; 4];
    // SAFETY: `out` holds 4 f64, the width of one AVX register, and only the AVX2 builds, run
    // where the CPU reported AVX2, hold such a register.
    unsafe { std::arch::x86_64::_mm256_storeu_pd(out.as_mut_ptr(), *v) };
    out.iter().sum()
}

#[cfg(target_arch = "x86_64")]
chains!(
    "avx512f",
    CHAINS,
    fma_avx512(a, b),
    _mm512_set1_pd(1.0),
    |x| _mm512_fmadd_pd(*x, _mm512_set1_pd(a), _mm512_set1_pd(b)),
    |v| _mm512_reduce_add_pd(*v)
);
#[cfg(target_arch = "x86_64")]
chains!(
    "avx2,fma",
    CHAINS_AVX2,
    fma_avx2(a, b),
    _mm256_set1_pd(1.0),
    |x| _mm256_fmadd_pd(*x, _mm256_set1_pd(a), _mm256_set1_pd(b)),
    sum256
);
#[cfg(target_arch = "x86_64")]
chains!(
    "avx512f",
    CHAINS,
    mul_avx512(a, b),
    _mm512_set1_pd(1.0),
    |x| _mm512_mul_pd(_mm512_mul_pd(*x, _mm512_set1_pd(a)), _mm512_set1_pd(b)),
    |v| _mm512_reduce_add_pd(*v)
);
#[cfg(target_arch = "x86_64")]
chains!(
    "avx2",
    CHAINS_AVX2,
    mul_avx2(a, b),
    _mm256_set1_pd(1.0),
    |x| _mm256_mul_pd(_mm256_mul_pd(*x, _mm256_set1_pd(a)), _mm256_set1_pd(b)),
    sum256
);
#[cfg(target_arch = "x86_64")]
chains!(
    "avx512f",
    CHAINS,
    div_avx512(a),
    _mm512_set1_pd(1.0),
    |x| _mm512_div_pd(*x, _mm512_set1_pd(a)),
    |v| _mm512_reduce_add_pd(*v)
);
#[cfg(target_arch = "x86_64")]
chains!(
    "avx2",
    CHAINS_AVX2,
    div_avx2(a),
    _mm256_set1_pd(1.0),
    |x| _mm256_div_pd(*x, _mm256_set1_pd(a)),
    sum256
);

/// The chains of the peaks on one f64 each, for a CPU with neither AVX-512F nor AVX2.
fn portable(step: impl Fn(f64) -> f64) -> f64 {
    let mut x = [1.0f64; CHAINS];
    for _ in 0..ROUNDS {
        for v in x.iter_mut() {
            *v = step(*v);
        }
    }
    x.iter().sum()
}

fn fma(a: f64, b: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU reported AVX-512F at run time.
            return unsafe { fma_avx512(a, b) };
        }
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU reported AVX2 and FMA at run time.
            return unsafe { fma_avx2(a, b) };
        }
    }
    portable(|v| v.mul_add(a, b))
}

/// Independent chains of `ROUNDS` steps x ← (x · a) · b on the widest vectors the CPU has:
/// 2 [`lanes`]`(false)` multiply lanes. Two multiplies a step: with one, the compiler rotated the
/// chains through registers and the stack, and timed that instead.
fn mul(a: f64, b: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU reported AVX-512F at run time.
            return unsafe { mul_avx512(a, b) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU reported AVX2 at run time.
            return unsafe { mul_avx2(a, b) };
        }
    }
    portable(|v| v * a * b)
}

/// Independent chains of `ROUNDS` divisions x ← x / a on the widest vectors the CPU has:
/// [`lanes`]`(false)` division lanes.
fn div(a: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU reported AVX-512F at run time.
            return unsafe { div_avx512(a) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU reported AVX2 at run time.
            return unsafe { div_avx2(a) };
        }
    }
    portable(|v| v / a)
}

fn bench_fma(c: &mut Criterion) {
    let mut g = c.benchmark_group("roofline");
    g.throughput(Throughput::Elements(fma_lanes() as u64));
    g.bench_function("fma_peak_one_core", |bch| {
        bch.iter(|| fma(black_box(0.999_999), black_box(1e-9)))
    });
    g.throughput(Throughput::Elements(2 * lanes(false) as u64));
    g.bench_function("mul_peak_one_core", |bch| {
        bch.iter(|| mul(black_box(0.999_999), black_box(1.000_001)))
    });
    g.throughput(Throughput::Elements(lanes(false) as u64));
    g.bench_function("div_peak_one_core", |bch| {
        bch.iter(|| div(black_box(1.000_000_1)))
    });
    // The same chains on every thread of the pool at once, `SPELLS` times a call (so that waking
    // the threads is a small part of it), counted over all of them: against the rate of one
    // thread (this benchmark with `RAYON_NUM_THREADS=1`), how many cores' arithmetic the machine
    // gives (docs/performance.md, "Two threads on cores that share no cache, at times").
    const SPELLS: usize = 16;
    g.throughput(Throughput::Elements(
        (fma_lanes() * SPELLS * rayon::current_num_threads()) as u64,
    ));
    g.bench_function("fma_peak_all_cores", |bch| {
        bch.iter(|| {
            rayon::broadcast(|_| {
                (0..SPELLS)
                    .map(|_| fma(black_box(0.999_999), black_box(1e-9)))
                    .sum::<f64>()
            })
        })
    });
    g.finish();
}

fn triad(a: &mut [f64], b: &[f64], c: &[f64], s: f64, threads: bool) {
    if threads {
        a.par_chunks_mut(1 << 14)
            .zip(b.par_chunks(1 << 14).zip(c.par_chunks(1 << 14)))
            .for_each(|(a, (b, c))| {
                for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
                    *a = b + s * c;
                }
            });
    } else {
        for ((a, b), c) in a.iter_mut().zip(b).zip(c) {
            *a = b + s * c;
        }
    }
}

fn bench_triad(c: &mut Criterion) {
    let mut g = c.benchmark_group("roofline");
    for (name, bytes) in [("24MiB", 24usize << 20), ("1GiB", 1usize << 30)] {
        let n = bytes / 24;
        let (mut a, b, cc) = (vec![0.0; n], vec![1.0; n], vec![2.0; n]);
        g.throughput(Throughput::Bytes((24 * n) as u64));
        for (label, threads) in [("one_thread", false), ("all_threads", true)] {
            g.bench_function(format!("triad_{name}_{label}"), |bch| {
                bch.iter_custom(|iters| {
                    time_on_awake_pool(iters, || triad(&mut a, &b, &cc, black_box(3.0), threads))
                })
            });
        }
    }
    g.finish();
}

/// `trips` round trips of one cache line between two threads, timed from the moment both run: each
/// waits until the other has written the next value of a shared counter, then writes the one after.
fn round_trips(trips: u64) -> Duration {
    let (line, ready) = (AtomicU64::new(0), AtomicBool::new(false));
    let wait_for = |value: u64| {
        while line.load(Ordering::Acquire) != value {
            std::hint::spin_loop();
        }
    };
    std::thread::scope(|s| {
        s.spawn(|| {
            ready.store(true, Ordering::Release);
            for i in 0..trips {
                wait_for(2 * i + 1);
                line.store(2 * i + 2, Ordering::Release);
            }
        });
        while !ready.load(Ordering::Acquire) {
            std::hint::spin_loop();
        }
        let start = Instant::now();
        for i in 0..trips {
            wait_for(2 * i);
            line.store(2 * i + 1, Ordering::Release);
        }
        wait_for(2 * trips);
        start.elapsed()
    })
}

/// One round trip of a cache line between two threads: tens of nanoseconds between cores that
/// share a last-level cache, a few hundred between cores that do not (on a virtual machine the
/// host may move its virtual CPUs between such placements while it runs: docs/performance.md,
/// "Two threads on cores that share no cache, at times").
fn bench_core_to_core(c: &mut Criterion) {
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        // two spinning threads on one CPU would pass the line once a time slice
        println!("roofline/core_to_core_round_trip: not measured (one CPU)");
        return;
    }
    let mut g = c.benchmark_group("roofline");
    g.bench_function("core_to_core_round_trip", |bch| bch.iter_custom(round_trips));
    g.finish();
}

criterion_group!(benches, bench_fma, bench_triad, bench_core_to_core);
criterion_main!(benches);
