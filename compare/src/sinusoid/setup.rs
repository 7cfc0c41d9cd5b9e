//! What every part of the Section 4 study shares: the scene's scale quantities, one model's run,
//! a snapshot of it, and the summary row of a run.

use super::metrics::{SinusoidSummary, summarise};
use crate::study::{ModelName, Study};
use anyhow::{Result, anyhow};
use serde::Serialize;

/// Scale quantities of the scene, every one read from it.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Models to run, `[compare].models`.
    pub models: Vec<ModelName>,
    /// Pre-crack half-length a [m].
    pub half_length: f64,
    /// Pre-crack centre x_c [m].
    pub center_x: f64,
    /// Run duration T [s].
    pub duration: f64,
    /// Element size h [m].
    pub element_size: f64,
    /// σ_c of the strong interface, `[interface].sigma_c` [Pa].
    pub sigma_c_strong: f64,
    /// Reference x range of the right weak branch [m] (its end is the weak/strong junction).
    pub weak_right: [f64; 2],
    /// Time of the maps and profiles, `[compare].snapshot_t_over_T` · T [s].
    pub snapshot_time: f64,
    /// Far-field shear history σ_xy^∞(t) [Pa].
    pub shear: fem::scene::Ramp,
    /// Reference positions (x, y) of the interface row at every node column [m].
    pub interface: Vec<[f64; 2]>,
}

impl Setup {
    /// The setup of `study`; errors name the missing or invalid key.
    pub fn of(study: &Study) -> Result<Setup> {
        let scene = &study.fem;
        let sigma_c_strong = scene
            .interface
            .map(|i| i.sigma_c)
            .ok_or_else(|| anyhow!("[interface]: missing; its sigma_c (strong interface) scales the maps"))?;
        let weak_right = scene
            .fem
            .interface_zones
            .iter()
            .map(|z| z.x_range)
            .filter(|r| r[0] >= scene.center_x())
            .min_by(|a, b| a[0].total_cmp(&b[0]))
            .ok_or_else(|| {
                anyhow!("fem.interface_zones: no zone right of the crack centre (the weak branch)")
            })?;
        Ok(Setup {
            models: study.models()?,
            half_length: scene.half_length(),
            center_x: scene.center_x(),
            duration: scene.duration(),
            element_size: scene.fem.element_size,
            sigma_c_strong,
            weak_right,
            snapshot_time: study.snapshot_t_over_t()? * scene.duration(),
            shear: scene.loading.shear,
            interface: interface_row(&scene.fem),
        })
    }

    /// (x − x_c)/a [-].
    pub fn x_over_a(&self, x: f64) -> f64 {
        (x - self.center_x) / self.half_length
    }
}

/// The interface row y(x) [m] sampled at the node columns x₀ + i h.
fn interface_row(f: &fem::scene::FemSpec) -> Vec<[f64; 2]> {
    let [x0, x1] = f.x_range;
    let n = ((x1 - x0) / f.element_size).round() as usize;
    (0..=n)
        .map(|i| {
            let x = x0 + i as f64 * f.element_size;
            [x, f.interface_y(x)]
        })
        .collect()
}

/// One model's run: its output (partial if it went unstable) and how it ended.
#[derive(Debug, Clone)]
pub struct ModelRun {
    /// Model name.
    pub model: String,
    /// Output (up to the failure if `failure` is set).
    pub out: fem::RunOutput,
    /// Wall time of the run [s].
    pub wall_s: f64,
    /// Why the run stopped early (`None`: it reached T).
    pub failure: Option<String>,
}

/// One run's snapshot: its index in the run's snapshots and its time t/T [-].
#[derive(Debug, Clone, Copy)]
pub struct Snapshot<'a> {
    /// The run.
    pub run: &'a ModelRun,
    /// Snapshot index.
    pub k: usize,
    /// t/T of the snapshot [-].
    pub t_over_t: f64,
}

/// Run facts written next to the summary (`sinusoid_summary.csv`, after its columns).
#[derive(Debug, Clone, Serialize)]
pub struct RunInfo {
    /// Wall time of the run [s].
    pub wall_s: f64,
    /// Time steps done [-].
    pub steps: u64,
    /// Time step Δt [s].
    pub time_step: f64,
    /// The run reached T (false: it went unstable; the summary covers the partial output).
    pub completed: bool,
}

/// The summary row of one run.
pub fn row(setup: &Setup, run: &ModelRun) -> (SinusoidSummary, RunInfo) {
    let s = summarise(
        &run.model,
        &run.out,
        setup.half_length,
        setup.element_size,
        setup.duration,
    );
    let info = RunInfo {
        wall_s: run.wall_s,
        steps: run.out.steps,
        time_step: run.out.time_step,
        completed: run.failure.is_none(),
    };
    (s, info)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::path::Path;

    /// The setup of the repository's Section 4 scene.
    pub(crate) fn setup() -> Setup {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sinusoidal-interface.toml");
        Setup::of(&Study::load(&path).unwrap()).unwrap()
    }

    #[test]
    fn setup_reads_the_scene() {
        let s = setup();
        assert_eq!(s.models, [ModelName::Standard, ModelName::Hybrid]);
        // the right weak branch runs from a to 2.5a (docs/cases.md, case 2)
        assert!((s.x_over_a(s.weak_right[0]) - 1.0).abs() < 1e-12);
        assert!((s.x_over_a(s.weak_right[1]) - 2.5).abs() < 1e-12);
        assert!(s.snapshot_time > 0.0 && s.snapshot_time <= s.duration);
        assert_eq!(s.sigma_c_strong, 0.4e6);
    }
}
