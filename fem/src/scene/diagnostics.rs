//! `[fem]` keys of the Section 4 diagnostics: residual stress (paper eq. 17), the KKT-violation
//! metric and stress snapshots (Figures 10-11). Each is computed only when declared.

use super::checks::check;
use super::raw::RawFem;
use crate::error::SceneError;

/// Validated Section 4 diagnostics.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Diagnostics {
    /// Reference x range [m] of the + facets integrated by eq. (17); `None`: not computed.
    pub residual_stress_x: Option<[f64; 2]>,
    /// Record the KKT conditions on the crack faces of the contact surface every sample.
    pub kkt_metric: bool,
    /// Snapshot times [s], increasing: element stresses in `snapshot_window` and the upper-face
    /// profile at the first sample at or after each.
    pub snapshot_times: Vec<f64>,
    /// Reference window [[x₀, x₁], [y₀, y₁]] [m] of the element stresses of a snapshot.
    pub snapshot_window: [[f64; 2]; 2],
}

/// Validates the diagnostics keys against the domain and the duration T [s].
pub(crate) fn diagnostics(f: &RawFem, duration: f64) -> Result<Diagnostics, SceneError> {
    let inside_x = |x: f64| x >= f.x_range[0] && x <= f.x_range[1];
    if let Some([x0, x1]) = f.residual_stress_x {
        check(
            "fem.residual_stress_x",
            x1 - x0,
            inside_x(x0) && inside_x(x1) && x1 > x0,
            "[x0, x1] with x0 < x1 inside fem.x_range [m]",
        )?;
    }
    let times = f.snapshot_times.clone().unwrap_or_default();
    for (k, &t) in times.iter().enumerate() {
        let increasing = k == 0 || t > times[k - 1];
        check(
            "fem.snapshot_times",
            t,
            t > 0.0 && t <= duration && increasing,
            "increasing times in (0, loading.duration] s",
        )?;
    }
    let window = f.snapshot_window.unwrap_or([f.x_range, f.y_range]);
    let [[x0, x1], [y0, y1]] = window;
    check(
        "fem.snapshot_window",
        x1 - x0,
        inside_x(x0) && inside_x(x1) && x1 > x0,
        "[[x0, x1], [y0, y1]] inside the domain [m]",
    )?;
    check(
        "fem.snapshot_window",
        y1 - y0,
        y0 >= f.y_range[0] && y1 <= f.y_range[1] && y1 > y0,
        "[[x0, x1], [y0, y1]] inside the domain [m]",
    )?;
    Ok(Diagnostics {
        residual_stress_x: f.residual_stress_x,
        kkt_metric: f.kkt_metric.unwrap_or(false),
        snapshot_times: times,
        snapshot_window: window,
    })
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;

    fn sinusoid() -> String {
        crate::test_scenes::scene_text("sinusoidal-interface")
    }

    #[test]
    fn the_sinusoid_scene_declares_its_diagnostics() {
        let d = Scene::from_toml_str(&sinusoid()).unwrap().fem.diagnostics;
        assert_eq!(d.residual_stress_x, Some([0.125, 0.3125]));
        assert!(d.kkt_metric);
        assert_eq!(d.snapshot_times, vec![0.03]);
    }

    #[test]
    fn bad_diagnostics_name_the_field() {
        for (from, to, field) in [
            (
                "snapshot_times = [0.03]",
                "snapshot_times = [0.07]",
                "fem.snapshot_times",
            ),
            (
                "snapshot_times = [0.03]",
                "snapshot_times = [0.03, 0.02]",
                "fem.snapshot_times",
            ),
            (
                "residual_stress_x = [0.125, 0.3125]",
                "residual_stress_x = [0.3, 0.2]",
                "fem.residual_stress_x",
            ),
            (
                "[[0.0, 0.375], [-0.0625, 0.0625]]",
                "[[0.0, 0.5], [-0.0625, 0.0625]]",
                "fem.snapshot_window",
            ),
            (
                "[[0.0, 0.375], [-0.0625, 0.0625]]",
                "[[0.0, 0.375], [-0.2, 0.0625]]",
                "fem.snapshot_window",
            ),
        ] {
            let text = sinusoid().replace(from, to);
            assert_ne!(text, sinusoid(), "{from} not found");
            let e = Scene::from_toml_str(&text).unwrap_err().to_string();
            assert!(e.contains(field), "{to}: {e}");
        }
    }
}
