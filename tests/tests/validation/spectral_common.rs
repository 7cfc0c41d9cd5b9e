//! Shared helpers of the spectral claims: reference tables, dimensionless scenes (§7.7), and runs
//! shared between claims (one centre-crack run per friction value for the whole test binary).

use std::sync::OnceLock;

use compare::series::{Series, least_squares_slope, onset};
use spectral::{RunOutput, Scene, TipRecord};
use validation::{scene_text, with_overrides};

/// Rows of a reference CSV with a header line (numbers only).
pub fn reference_rows(name: &str) -> Vec<Vec<f64>> {
    validation::reference_rows(name)
}

/// η for ν = 0.35 [-].
pub fn eta_035() -> f64 {
    (2.0f64 * (1.0 - 0.35) / (1.0 - 2.0 * 0.35)).sqrt()
}

/// Scene from a named scene file with overrides.
pub fn scene(name: &str, overrides: &[(&str, Option<toml::Value>)]) -> Scene {
    let text = with_overrides(&scene_text(name), overrides);
    Scene::from_toml_str(&text).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// Float override.
pub fn f(key: &str, v: f64) -> (&str, Option<toml::Value>) {
    (key, Some(toml::Value::Float(v)))
}

/// Runs a scene, panicking with the error (tests only).
pub fn run(scene: &Scene) -> RunOutput {
    spectral::run(scene).unwrap_or_else(|e| panic!("run failed: {e}"))
}

/// Centre-crack run at paper resolution with friction `mu` (0 or 0.3), computed once per test
/// binary and shared by the claims that read it (friction, onset, resolution).
pub fn center_crack(mu: f64) -> &'static RunOutput {
    static MU0: OnceLock<RunOutput> = OnceLock::new();
    static MU03: OnceLock<RunOutput> = OnceLock::new();
    let cell = if mu == 0.0 { &MU0 } else { &MU03 };
    cell.get_or_init(|| run(&scene("center-crack", &[f("friction.friction_coeff", mu)])))
}

/// The §7.7 mode-II crack with S = 2.5 (scenes/tiny-spectral-andrews.toml), shared by the
/// Rayleigh-limit and supershear claims.
pub fn andrews_s25() -> &'static RunOutput {
    static RUN: OnceLock<RunOutput> = OnceLock::new();
    RUN.get_or_init(|| run(&scene("tiny-spectral-andrews", &[])))
}

/// The §7.7 set-up with S = 1.0: τ_0 = 0.5, pre-crack 1.2 a_c = 2.351 (a_c = 1/(π 0.65 τ_0²)), T = 45.
pub fn andrews_s10() -> RunOutput {
    run(&scene(
        "tiny-spectral-andrews",
        &[
            f("loading.shear.final", 0.5),
            f("crack.half_length", 2.351),
            f("loading.duration", 45.0),
        ],
    ))
}

/// Least-squares speed of the right tip over t ∈ [t0, t1] [m/s].
pub fn speed_between(tips: &[TipRecord], t0: f64, t1: f64) -> f64 {
    let pts: Vec<(f64, f64)> = tips
        .iter()
        .filter(|r| r.t >= t0 && r.t <= t1)
        .map(|r| (r.t, r.tip_right))
        .collect();
    slope(&pts)
}

/// Runs a scene (used for centre-crack variants that are not shared).
pub fn center_crack_with(scene: &Scene) -> RunOutput {
    run(scene)
}

/// Mean speed [m/s] of the right tip between the times it passes center + 2a and center + 6a
/// (a fixed distance window of 4a, inside the propagation phase of the centre-crack case).
pub fn mean_tip_speed(out: &RunOutput) -> f64 {
    let (c, a) = (0.0, 0.125);
    let t2 = crossing_time(&out.tips, c + 2.0 * a).expect("tip reaches 2a");
    let t6 = crossing_time(&out.tips, c + 6.0 * a).expect("tip reaches 6a");
    let x2 = out
        .tips
        .iter()
        .find(|r| r.t >= t2)
        .map(|r| r.tip_right)
        .unwrap_or(0.0);
    let x6 = out
        .tips
        .iter()
        .find(|r| r.t >= t6)
        .map(|r| r.tip_right)
        .unwrap_or(0.0);
    (x6 - x2) / (t6 - t2)
}

/// Half-length a [m] of the repository's centre crack.
pub fn center_crack_a() -> f64 {
    scene("center-crack", &[]).half_length
}

/// Onset time [s] of a run: the shared definition (`compare::series::onset`), the crack
/// half-length exceeding its initial value by 0.05 a.
pub fn onset_time(out: &RunOutput, a: f64) -> Option<f64> {
    onset(&Series::half_length(&compare::runner::spectral_tips(out)), a)
}

/// First time [s] the right tip reaches x ≥ `x` [m].
pub fn crossing_time(tips: &[TipRecord], x: f64) -> Option<f64> {
    tips.iter().find(|r| r.tip_right >= x).map(|r| r.t)
}

/// Least-squares slope of (t, x) pairs [m/s].
pub fn slope(points: &[(f64, f64)]) -> f64 {
    let (t, x): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
    least_squares_slope(&t, &x)
}

/// Windowed least-squares speed of the right tip: (t_mid, half_length, speed) for windows of
/// length `window` [s] advanced by `window/4`.
pub fn windowed_speeds(tips: &[TipRecord], center: f64, window: f64) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    let t_end = tips.last().map_or(0.0, |r| r.t);
    let mut t0 = 0.0;
    while t0 + window <= t_end {
        let pts: Vec<(f64, f64)> = tips
            .iter()
            .filter(|r| r.t >= t0 && r.t <= t0 + window)
            .map(|r| (r.t, r.tip_right))
            .collect();
        let mid = pts[pts.len() / 2];
        out.push((mid.0, mid.1 - center, slope(&pts)));
        t0 += 0.25 * window;
    }
    out
}
