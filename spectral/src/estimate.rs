//! What a run will cost, from its validated scene and before the model is built: the number of
//! time steps and the memory of the grid state, the history convolution and the records kept for
//! output (tips every step, contact means and space-time fields at their intervals). For the fast
//! convolution the kernel fit is computed here (and kept for the run), so a fit that cannot reach
//! `spectral.fast_tolerance` is reported before any work too.

use crate::error::BuildError;
use crate::history::Entry;
use crate::kernels::Kernels;
use crate::modes::Modes;
use crate::output::{ContactMeanRecord, FieldRecord, TipRecord};
use crate::scene::{Convolution, Scene};
use crate::soe::SoeFit;
use preflight::budget::bytes_of;
use preflight::{Estimate, Part};
use std::mem::size_of;

/// Memory of the grid per point outside the convolution (fields, point states, FFT buffers) [B].
/// Measured peak resident memory of the centre crack minus the process's baseline and the fast
/// convolution: about 430 B per point at N = 16 384 and 65 536 (docs/outputs.md); rounded up.
const BYTES_PER_POINT: usize = 512;

/// Wall time per grid point and step of the fast path on 2 cores [s]. Measured on the centre
/// crack (`compare sweep`): 6.8e-8 at N = 2048, 7.6e-8 at 4096, 7.2e-8 at 8192.
const SECONDS_PER_POINT_STEP: f64 = 8e-8;

/// Bytes of history the direct path streams per second on 2 cores [B/s] (it is bound by memory
/// bandwidth; spectral/README.md, "Direct versus fast convolution").
const DIRECT_BYTES_PER_SECOND: f64 = 5e9;

/// Steps and memory of a run of `scene` (docs/outputs.md, "Budgets").
pub fn estimate(scene: &Scene) -> Result<Estimate, BuildError> {
    let n = scene.grid_points;
    let steps = scene.last_step().saturating_add(1);
    // two materials: one operator per half-space (docs/spectral-model.md §2.1), each priced as
    // the slower one, whose smaller β gives the longer windows
    let operators = if scene.is_split() { 2.0 } else { 1.0 };
    let slowest = scene.top().wave_speeds().cs.min(scene.bottom().wave_speeds().cs);
    let modes = Modes::new(
        n,
        scene.length,
        scene.cs_dt_over_dx * (slowest / scene.fastest_shear_speed()),
        scene.kernel_cutoff,
        usize::try_from(steps).unwrap_or(usize::MAX),
    );
    let per_step = n as f64 * SECONDS_PER_POINT_STEP;
    let (history, seconds_per_step) = match scene.convolution {
        Convolution::Direct => {
            let streamed =
                operators * modes.total as f64 * (size_of::<Entry>() + size_of::<[f64; 3]>()) as f64;
            let part = Part {
                what: format!("history ({} stored steps over all modes)", modes.total),
                bytes: bytes_of(
                    operators * modes.total as f64,
                    size_of::<Entry>() + size_of::<[f64; 3]>(),
                )
                .saturating_add(bytes_of(
                    operators * (modes.max_sample() as f64 + 1.0),
                    size_of::<[f64; 3]>(),
                )),
                key: "spectral.convolution",
            };
            (part, per_step + streamed / DIRECT_BYTES_PER_SECOND)
        }
        Convolution::Fast => {
            let mut poles = 0.0;
            let mut terms = 0;
            for solid in [scene.top(), scene.bottom()].iter().take(operators as usize) {
                let fit = SoeFit::shared(
                    &Kernels::new(solid.eta(), scene.kernel_cutoff),
                    scene.kernel_cutoff,
                    scene.fast_tolerance,
                )?;
                poles += fit.poles.len() as f64;
                terms += fit.terms();
            }
            let part = Part {
                what: format!("convolution ({terms} exponential terms per mode)"),
                bytes: bytes_of(
                    (n / 2 + 1) as f64 * poles,
                    crate::fast::bytes_per_pole(scene.fast_storage),
                ),
                key: "spectral.grid_points",
            };
            (part, per_step)
        }
    };
    let samples = |interval: f64| (scene.duration / interval).floor() + 2.0;
    let fields = scene
        .field_output_interval
        .map_or(0, |fi| bytes_of(samples(fi) * n as f64, size_of::<FieldRecord>()));
    Ok(Estimate {
        steps,
        steps_keys: "loading.duration, spectral.grid_points or spectral.cs_dt_over_dx",
        seconds: steps as f64 * seconds_per_step,
        parts: vec![
            Part {
                what: format!("grid ({n} points)"),
                bytes: bytes_of(n as f64, BYTES_PER_POINT),
                key: "spectral.grid_points",
            },
            history,
            Part {
                what: "tips (every step)".to_string(),
                bytes: bytes_of(steps as f64, size_of::<TipRecord>()),
                key: "loading.duration",
            },
            Part {
                what: "contact means".to_string(),
                bytes: bytes_of(samples(scene.output_interval), size_of::<ContactMeanRecord>()),
                key: "spectral.output_interval",
            },
            Part {
                what: "space-time fields".to_string(),
                bytes: fields,
                key: "spectral.field_output_interval",
            },
        ],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use preflight::Budget;

    fn scene(edit: &[(&str, &str)]) -> Scene {
        let mut text = include_str!("../../scenes/center-crack.toml").to_string();
        for (from, to) in edit {
            assert!(text.contains(from), "{from}");
            text = text.replacen(from, to, 1);
        }
        Scene::from_toml_str(&text).unwrap()
    }

    #[test]
    fn the_centre_crack_fits_the_default_budget() {
        let e = estimate(&scene(&[])).unwrap();
        assert!(e.bytes() < 1 << 30, "{}", e.summary());
        assert!(Budget::default().check(&e).is_ok());
    }

    #[test]
    fn the_largest_grid_is_refused_with_its_key() {
        let e = estimate(&scene(&[("grid_points = 4096", "grid_points = 16777216")])).unwrap();
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(
            msg.contains("spectral.grid_points") || msg.contains("spectral.field_output_interval"),
            "{msg}"
        );
    }

    #[test]
    fn dense_field_output_is_priced() {
        let e = estimate(&scene(&[(
            "field_output_interval = 1e-3",
            "field_output_interval = 1e-7",
        )]))
        .unwrap();
        let msg = Budget::default().check(&e).unwrap_err();
        assert!(msg.contains("spectral.field_output_interval"), "{msg}");
    }
}
