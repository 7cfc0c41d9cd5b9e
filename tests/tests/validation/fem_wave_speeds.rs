//! Plane-strain wave speeds (paper Table 1 as corrected in docs/fem-model.md §10.1): P and S pulses
//! in a plate arrive at two probes with the speeds c_d and c_s. A smooth displacement ramp on the left
//! side; top and bottom are rollers that make the wave one-dimensional (u_y = 0 for P, u_x = 0 for S).
//! Speed = probe distance / difference of the times at which the probe displacement reaches half the
//! imposed value.

use validation::{repo_root, scene_text, with_overrides};

const TOL_SPEED_REL: f64 = 0.01; // arrival-time speeds within 1 % of c_d, c_s; not tuned

/// `[fem.boundary]` of the P pulse: an x-displacement ramp of 1e-5 m over 5e-5 s on the left side,
/// rollers (u_y = 0) on top and bottom.
pub(crate) const P_BOUNDARY: &str = r#"left = { x = { kind = "displacement", initial = 0.0, final = 1e-5, ramp_start = 0.0, ramp_end = 5e-5 } }
           top = { y = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 } }
           bottom = { y = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 } }"#;

/// `[fem.boundary]` of the S pulse: a y-displacement ramp of 1e-5 m over 1e-4 s on the left side,
/// rollers (u_x = 0) on top and bottom.
pub(crate) const S_BOUNDARY: &str = r#"left = { y = { kind = "displacement", initial = 0.0, final = 1e-5, ramp_start = 0.0, ramp_end = 1e-4 } }
           top = { x = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 } }
           bottom = { x = { kind = "displacement", initial = 0.0, final = 0.0, ramp_start = 0.0, ramp_end = 0.0 } }"#;

fn table(text: &str) -> toml::Value {
    toml::Value::Table(text.parse().expect("valid TOML table"))
}

/// First time the probe's displacement component reaches `level`, linearly interpolated.
pub(crate) fn crossing(records: &[fem::ProbeRecord], probe: usize, level: f64, component: usize) -> f64 {
    let rows: Vec<&fem::ProbeRecord> = records.iter().filter(|p| p.probe == probe).collect();
    for w in rows.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (ua, ub) = if component == 0 {
            (a.ux, b.ux)
        } else {
            (a.uy, b.uy)
        };
        if ua < level && ub >= level {
            return a.t + (level - ua) / (ub - ua) * (b.t - a.t);
        }
    }
    panic!("probe {probe} never reached {level}");
}

/// Runs `scenes/<name>.toml` with its `[fem.boundary]` replaced by `boundary` (a TOML table's
/// text) until `duration` [s]; returns the speed [m/s] between its two probes, from the times at
/// which displacement `component` (0: x, 1: y) reaches half the imposed 1e-5 m, and the
/// material's wave speeds.
pub(crate) fn measured_speed(
    name: &str,
    boundary: &str,
    duration: f64,
    component: usize,
) -> (f64, fem::WaveSpeeds) {
    let text = with_overrides(
        &scene_text(name),
        &[
            ("fem.boundary", Some(table(boundary))),
            ("loading.duration", Some(toml::Value::Float(duration))),
        ],
    );
    let scene = fem::Scene::from_toml_str_in(&text, &repo_root().join("scenes")).unwrap();
    let out = fem::run(&scene).unwrap();
    println!("{name}: {} steps of {:.4e} s", out.steps, out.time_step);
    let amplitude = 1e-5;
    let (t1, t2) = (
        crossing(&out.probes, 0, 0.5 * amplitude, component),
        crossing(&out.probes, 1, 0.5 * amplitude, component),
    );
    // the probe nodes' own positions (the nearest nodes to the scene's points)
    let x_of = |k: usize| {
        out.probes
            .iter()
            .find(|p| p.probe == k)
            .expect("probe recorded")
            .x
    };
    let (x1, x2) = (x_of(0), x_of(1));
    ((x2 - x1) / (t2 - t1), scene.wave_speeds())
}

/// Asserts a measured arrival speed against the expected plane-strain wave speed (c_d or c_s).
pub(crate) fn check(label: &str, measured: f64, expected: f64) {
    let err = (measured - expected).abs() / expected;
    println!(
        "{label}: measured {measured:.2} m/s, expected {expected:.2} m/s, rel. error {err:.2e} (tol {TOL_SPEED_REL})"
    );
    assert!(err <= TOL_SPEED_REL);
}

#[test]
fn p_wave_travels_at_cd() {
    let (c, w) = measured_speed("tiny-fem-plate", P_BOUNDARY, 7e-4, 0);
    check("P wave vs c_d", c, w.cd);
}

#[test]
fn s_wave_travels_at_cs() {
    let (c, w) = measured_speed("tiny-fem-plate", S_BOUNDARY, 1.4e-3, 1);
    check("S wave vs c_s", c, w.cs);
}
