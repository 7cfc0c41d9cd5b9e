//! Contact at scale: one whole explicit step of two blocks pressed and sliding against each other
//! along a rough interface of 10 002 contact nodes (h = 0.1 mm over 0.5 m, 5 000 segments a face),
//! for three block heights: 10, 50 and 250 element rows a block, i.e. 10, 50 and 250 bulk elements
//! behind each contact node (docs/performance.md, "Contact at scale").
//!
//! The interface is a self-affine profile (Hurst 0.8, RMS slope 0.2, wavelengths 0.8 to 4 mm:
//! `fem.interface_rough`), pre-cracked over its whole width, μ = 0.3. The top edge is pressed
//! down and the bottom up by 10⁻³ of the block height over two transit times of the dilatational
//! wave through a block, then sheared apart; each state is advanced to the middle of the shear
//! ramp (faces pressed and slipping) before it is measured, and keeps advancing while measured.
//!
//! Criterion reports the whole step per element-step. After each height the benchmark prints,
//! from the model's own phase clock over the measured steps only, where the step went: the
//! contact phase (resolution after the join), the contact detection that ran beside the bulk
//! sweep on the other thread, and their share of the step's work (bulk + contact, summed over
//! threads) and of its wall time.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use fem::profile::PhaseTime;
use preflight::testing::time_on_awake_pool;

/// Element size [m] and interface width [m]: 5 000 segments a face.
const H: f64 = 1e-4;
const WIDTH: f64 = 0.5;

/// The scene for blocks of `rows` element rows each, and the time [s] by which the faces are
/// pressed and slipping.
fn scene(rows: usize) -> (String, f64) {
    let (e, nu, rho): (f64, f64, f64) = (70e6, 0.35, 1230.0); // Pa, -, kg/m³
    let c_d = (e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * rho)).sqrt(); // plane strain [m/s]
    let height = rows as f64 * H; // of one block [m]
    let press = 2.0 * height / c_d; // two transit times [s]
    let (squeeze, shear) = (1e-3 * height, 2e-3 * height); // m
    let toml = format!(
        r#"name = "contact-scale-{rows}"
[material]
youngs_modulus = {e}
poisson_ratio = {nu}
density = {rho}
[interface]
sigma_c = 4e6
delta_c = 1e-4
beta = 1.0
kappa = 1.0
[crack]
half_length = 1.0
center_x = 0.0
[friction]
friction_coeff = 0.3
[loading]
duration = {duration}
[fem]
x_range = [{x0}, {x1}]
y_range = [{y0}, {height}]
element_size = {H}
model = "hybrid"
time_step_safety = 0.5
eps_n = 2.1e10
eps_t = 2.1e10
output_interval = {duration}
interface_rough = {{ hurst = 0.8, rms_slope = 0.2, seed = 1, from = 0.0, to = {half}, wavelength_min = 8e-4, wavelength_max = 4e-3 }}
[fem.boundary.top]
x = {{ kind = "displacement", initial = 0.0, final = {shear}, ramp_start = {press}, ramp_end = {ramp_end} }}
y = {{ kind = "displacement", initial = 0.0, final = -{squeeze}, ramp_start = 0.0, ramp_end = {press} }}
[fem.boundary.bottom]
x = {{ kind = "displacement", initial = 0.0, final = -{shear}, ramp_start = {press}, ramp_end = {ramp_end} }}
y = {{ kind = "displacement", initial = 0.0, final = {squeeze}, ramp_start = 0.0, ramp_end = {press} }}
"#,
        duration = 10.0 * press,
        x0 = -0.5 * WIDTH,
        x1 = 0.5 * WIDTH,
        y0 = -height,
        half = 0.5 * WIDTH,
        ramp_end = 3.0 * press,
    );
    (toml, 2.0 * press)
}

/// Elements of the two blocks of `rows` element rows each: the throughput criterion reports, set
/// before the model is built (checked against the model's own count once it is).
fn scene_elements(rows: usize) -> u64 {
    2 * rows as u64 * (WIDTH / H).round() as u64
}

/// Seconds of the phase times that `keep` selects, in `after` minus `before`.
fn seconds(before: &[PhaseTime], after: &[PhaseTime], keep: impl Fn(&PhaseTime) -> bool) -> f64 {
    let of = |p: &[PhaseTime]| p.iter().filter(|t| keep(t)).map(|t| t.seconds).sum::<f64>();
    of(after) - of(before)
}

fn bench_height(c: &mut Criterion, rows: usize) {
    let (text, warm_to) = scene(rows);
    let scene = fem::Scene::from_toml_str(&text).unwrap();
    let mut g = c.benchmark_group("contact_scale");
    if rows > 50 {
        g.sample_size(20);
    }
    // Built and advanced into slip the first time criterion runs the routine: a height its filter
    // leaves out is never built (before, `-- rows_10` took 70 s, most of it advancing the 50- and
    // 250-row states, which it then did not measure).
    let mut built: Option<(fem::Model, fem::State, fem::Workspace, Vec<PhaseTime>, u64)> = None;
    g.throughput(Throughput::Elements(scene_elements(rows)));
    g.bench_function(format!("rows_{rows}"), |b| {
        let (model, state, ws, _, _) = built.get_or_insert_with(|| {
            let (model, mut state, mut ws) = fem::build(&scene).unwrap();
            while state.time() < warm_to {
                fem::step(&model, &mut state, &mut ws, false).unwrap();
            }
            let (before, steps_before) = (ws.profile(), state.step_count());
            (model, state, ws, before, steps_before)
        });
        b.iter_custom(|iters| time_on_awake_pool(iters, || fem::step(model, state, ws, false).unwrap()))
    });
    g.finish();
    let Some((model, state, ws, before, steps_before)) = built else {
        eprintln!("contact_scale/rows_{rows}: not measured (left out by the filter)");
        return;
    };
    let after = ws.profile();
    assert_eq!(
        model.num_elements() as u64,
        scene_elements(rows),
        "the throughput's element count"
    );
    let steps = (state.step_count() - steps_before) as f64;
    let total = seconds(&before, &after, |t| !t.beside);
    let lap = seconds(&before, &after, |t| t.phase == "contact" && !t.beside);
    let beside = seconds(&before, &after, |t| t.phase == "contact" && t.beside);
    let bulk = seconds(&before, &after, |t| t.phase == "bulk forces" && !t.beside);
    let (nodes, touching) = state.contact_nodes();
    let us = |s: f64| 1e6 * s / steps;
    // The bulk phase's wall time holds the sweep and the detection beside it (rayon::join), and
    // after the detection, on its thread, the insertion check and the cohesive law (none on this
    // pre-cracked interface): the work of the step, summed over threads, counts all of them once
    // more. On one thread they run inline, inside that wall time: they are counted once.
    let all_beside = seconds(&before, &after, |t| t.beside);
    let work = if rayon::current_num_threads() > 1 {
        total + all_beside
    } else {
        total
    };
    eprintln!(
        "contact_scale/rows_{rows}: {} elements, {nodes} contact nodes ({touching} touching), {steps} steps: \
         step {:.1} us, bulk phase {:.1} us, detection beside the sweep {:.1} us, contact phase {:.1} us; \
         contact {:.1} % of the step's work, detection {:.0} ns and resolution {:.0} ns per contact node",
        model.num_elements(),
        us(total),
        us(bulk),
        us(beside),
        us(lap),
        100.0 * (beside + lap) / work,
        1e9 * beside / steps / nodes as f64,
        1e9 * lap / steps / nodes as f64,
    );
}

fn bench(c: &mut Criterion) {
    for rows in [10, 50, 250] {
        bench_height(c, rows);
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
