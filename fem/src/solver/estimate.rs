//! What a run will cost, from its validated scene and before anything is allocated: the number of
//! time steps and the memory of the model and of the records kept for output. The run's records
//! are held in memory until it ends (they are written as CSV afterwards), so a tiny
//! `fem.output_interval` costs as much as a fine mesh.

use crate::output::{
    ContactMeanRecord, EnergyRecord, FaceRecord, FieldRecord, InterfaceRecord, KktRecord, ProbeRecord,
    ProfileRecord, TipRecord,
};
use crate::scene::Scene;
use preflight::budget::bytes_of;
use preflight::{Estimate, Part};
use std::mem::size_of;

/// Memory of the model per bulk element (nodes, element operators, state, workspace, contact and
/// cohesive arrays) [B]. Measured peak resident memory of the centre crack minus the process's
/// baseline: 221 B at 500 × 250 elements, 212 B at 1000 × 500, 209 B at 2000 × 1000
/// (docs/outputs.md); rounded up.
const BYTES_PER_ELEMENT: usize = 256;

/// Wall time per element and step on 2 cores, contact and cohesive work included [s]. Measured on
/// the centre crack (`compare sweep`): 1.3e-8 at h = 2 mm, 1.06e-8 at 1 mm, 0.90e-8 at 0.5 mm.
const SECONDS_PER_ELEMENT_STEP: f64 = 1.2e-8;

/// Steps and memory of a run of `scene` (docs/outputs.md, "Budgets").
pub fn estimate(scene: &Scene) -> Estimate {
    let f = &scene.fem;
    let h = f.element_size;
    let nx = ((f.x_range[1] - f.x_range[0]) / h).round();
    let ny = ((f.y_range[1] - f.y_range[0]) / h).round();
    let dt = scene.time_step();
    let steps_f = (scene.duration() / dt).ceil();
    let every = (f.output_interval / dt).round().max(1.0);
    let samples = (steps_f / every).floor() + 2.0;
    let interface = scene.interface.is_some() || scene.crack.is_some();
    // per sample: damage at 2 Gauss points per facet, face tractions per node of the row
    let row = if interface {
        2.0 * nx * size_of::<InterfaceRecord>() as f64 + (nx + 1.0) * size_of::<FaceRecord>() as f64
    } else {
        0.0
    };
    let d = &f.diagnostics;
    let per_sample = row
        + (size_of::<TipRecord>() + size_of::<EnergyRecord>() + size_of::<ContactMeanRecord>()) as f64
        + f.probes.len() as f64 * size_of::<ProbeRecord>() as f64
        + if d.kkt_metric {
            size_of::<KktRecord>() as f64
        } else {
            0.0
        };
    let [[x0, x1], [y0, y1]] = d.snapshot_window;
    let window_elements = ((x1 - x0).max(0.0) / h).ceil().min(nx) * ((y1 - y0).max(0.0) / h).ceil().min(ny);
    let snapshots = d.snapshot_times.len() as f64
        * (window_elements * size_of::<FieldRecord>() as f64
            + (nx + 1.0) * size_of::<ProfileRecord>() as f64);
    Estimate {
        steps: if steps_f.is_finite() {
            steps_f as u64
        } else {
            u64::MAX
        },
        steps_keys: "loading.duration, fem.element_size or fem.time_step_safety",
        seconds: steps_f * nx * ny * SECONDS_PER_ELEMENT_STEP,
        parts: vec![
            Part {
                what: format!("model ({nx} × {ny} elements)"),
                bytes: bytes_of(nx * ny, BYTES_PER_ELEMENT),
                key: "fem.element_size",
            },
            Part {
                what: format!("records ({samples} samples)"),
                bytes: bytes_of(samples, 1).saturating_mul(per_sample as u64),
                key: "fem.output_interval",
            },
            Part {
                what: "stress snapshots".to_string(),
                bytes: bytes_of(snapshots, 1),
                key: "fem.diagnostics.snapshot_times",
            },
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use preflight::Budget;

    fn scene(edit: &[(&str, &str)]) -> Scene {
        let mut text = include_str!("../../../scenes/center-crack.toml").to_string();
        for (from, to) in edit {
            assert!(text.contains(from), "{from}");
            text = text.replace(from, to);
        }
        Scene::from_toml_str(&text).unwrap()
    }

    #[test]
    fn the_centre_crack_fits_the_default_budget() {
        let e = estimate(&scene(&[]));
        // 500 × 250 elements at 256 B, 1001 samples of a 500-facet row
        assert!(e.bytes() > 30 << 20 && e.bytes() < 1 << 30, "{}", e.summary());
        assert!((10_000..20_000).contains(&e.steps), "{}", e.steps);
        assert!(Budget::default().check(&e).is_ok());
    }

    #[test]
    fn a_tiny_output_interval_is_priced_and_refused() {
        // a sample every step (the interval is rounded to whole steps) for 20 T: 262 000 samples, 14 GB
        let e = estimate(&scene(&[
            (
                "output_interval = 2e-5          # s\n",
                "output_interval = 1e-15\n",
            ),
            ("duration = 0.02 ", "duration = 0.4 "),
        ]));
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(msg.contains("fem.output_interval"), "{msg}");
    }

    #[test]
    fn a_fine_mesh_is_priced_and_refused() {
        let e = estimate(&scene(&[("element_size = 1e-3", "element_size = 1e-5")]));
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(
            msg.contains("fem.element_size") || msg.contains("--max-steps"),
            "{msg}"
        );
    }
}
