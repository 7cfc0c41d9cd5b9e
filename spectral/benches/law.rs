//! The other hot loop of a spectral step: the interface law at every grid point
//! (`spectral::law::solve_points`), one point at a time and four at a time (AVX2, where the CPU
//! has it), on one thread. The interface is the centre crack's (N = 4 096, its material, strength,
//! impedances and time step) in the middle of a run: a quarter of the points broken, pressed
//! together and sliding (μ = 0.3, Prakash regularisation), an eighth softening in the two process
//! zones, the rest intact and stuck with zero jumps. Throughput: grid points.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spectral::law::cohesive::{CohesiveParams, Strength};
use spectral::law::point::{ContactFriction, Point, PointLaw};
use spectral::law::{Drives, Impedances, LawBuild, solve_points};

const N: usize = 4096;

fn bench(c: &mut Criterion) {
    let (e, nu, rho): (f64, f64, f64) = (70e6, 0.35, 1230.0);
    let mu = e / (2.0 * (1.0 + nu));
    let cs = (mu / rho).sqrt();
    let cd = cs * (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt();
    let dt = 1.26e-6;
    let cohesive = CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0);
    let law = PointLaw {
        cohesive,
        z_shear: Impedances::equal(rho * cs),
        z_normal: Impedances::equal(rho * cd),
        dt,
        friction_coeff: 0.3,
        relax: Some(dt / 2e-5),
        contact: true,
        rule: ContactFriction::AllFaces,
    };
    let crack = 3 * N / 8..5 * N / 8;
    let zone = |m: usize| (5 * N / 16..crack.start).contains(&m) || (crack.end..11 * N / 16).contains(&m);
    let wave = |m: usize, k: f64| (k * m as f64).sin();
    let mut f = [vec![0.0; N], vec![0.0; N], vec![0.0; N], vec![0.0; N]];
    let mut u = [vec![0.0; N], vec![0.0; N], vec![0.0; N], vec![0.0; N]];
    let mut points = Vec::with_capacity(N);
    for m in 0..N {
        // dynamic stresses of a few 10 kPa on every face (top x, bottom x, top y, bottom y)
        f[0][m] = 3e4 * wave(m, 0.013);
        f[1][m] = -2e4 * wave(m, 0.007);
        f[2][m] = 2e4 * wave(m, 0.011);
        f[3][m] = -1e4 * wave(m, 0.005);
        let strength = if crack.contains(&m) {
            // slid by tens of µm, faces 0.1 µm into each other
            (u[0][m], u[2][m]) = (4e-5 + 1e-5 * wave(m, 0.02), -1e-7);
            Strength::precut(&cohesive)
        } else if zone(m) {
            // softening: jumps of a fraction of δ_c
            (u[0][m], u[2][m]) = (3e-5 + 1e-5 * wave(m, 0.05), 1e-6 * wave(m, 0.03));
            Strength::intact(&cohesive)
        } else {
            Strength::intact(&cohesive)
        };
        points.push(Point::at_rest(strength));
    }
    let nucleation = vec![0.0; N];
    let drives = Drives {
        load: (0.1e6, -0.05e6),
        nucleation: &nucleation,
        f_top_x: &f[0],
        f_bottom_x: &f[1],
        f_top_y: &f[2],
        f_bottom_y: &f[3],
        u_top_x: &u[0],
        u_bottom_x: &u[1],
        u_top_y: &u[2],
        u_bottom_y: &u[3],
    };
    let mut g = c.benchmark_group("interface_law");
    g.throughput(Throughput::Elements(N as u64));
    let mut builds = vec![("scalar", LawBuild::Scalar)];
    if LawBuild::detect() == LawBuild::Avx2 {
        builds.push(("avx2", LawBuild::Avx2));
    }
    for (name, build) in builds {
        let mut p = points.clone();
        g.bench_function(name, |b| {
            b.iter(|| solve_points(build, &law, 1e3, &drives, &mut p));
        });
        let closed = p.iter().filter(|q| q.in_contact).count();
        let slipping = p.iter().filter(|q| q.slipping).count();
        eprintln!("{name}: {closed} of {N} points in contact, {slipping} slipping");
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
