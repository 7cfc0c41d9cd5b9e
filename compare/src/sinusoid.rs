//! Paper Section 4: the sinusoidal-interface scene run with each model of `[compare].models`
//! (`standard` and `hybrid`), the full FE outputs per model, one summary row per model
//! (definitions of [`crate::sinusoid_metrics`], shared with the validation test) and the
//! figures of [`crate::sinusoid_figures`] and [`crate::sinusoid_snapshot`].

use crate::gate::Reporter;
use crate::output::write_rows;
use crate::scene::with_overrides;
use crate::sinusoid_metrics::{SinusoidSummary, summarise};
use anyhow::{Context, Result, anyhow};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;
use toml::Value;

/// Scale quantities of the scene, every one read from it.
#[derive(Debug, Clone)]
pub struct Setup {
    /// Models to run, `[compare].models`.
    pub models: Vec<String>,
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

fn compare_key<'a>(table: &'a toml::Table, key: &str) -> Option<&'a Value> {
    table.get("compare").and_then(|c| c.get(key))
}

impl Setup {
    /// Reads the setup from the scene text; errors name the missing or invalid key.
    pub fn of(text: &str) -> Result<Setup> {
        let table: toml::Table = text.parse().context("the scene is not valid TOML")?;
        let models = compare_key(&table, "models")
            .and_then(Value::as_array)
            .and_then(|a| {
                a.iter()
                    .map(|v| v.as_str().map(String::from))
                    .collect::<Option<Vec<_>>>()
            })
            .filter(|m| !m.is_empty())
            .ok_or_else(|| {
                anyhow!("compare.models: missing; expected a list such as [\"standard\", \"hybrid\"]")
            })?;
        let t_over_t = compare_key(&table, "snapshot_t_over_T")
            .and_then(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
            .ok_or_else(|| anyhow!("compare.snapshot_t_over_T: missing; expected a number in (0, 1]"))?;
        if !(t_over_t > 0.0 && t_over_t <= 1.0) {
            return Err(anyhow!(
                "compare.snapshot_t_over_T = {t_over_t} out of range; allowed (0, 1]"
            ));
        }
        let scene = fem::Scene::from_toml_str(text).context("FE model: invalid scene")?;
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
            models,
            half_length: scene.half_length(),
            center_x: scene.center_x(),
            duration: scene.duration(),
            element_size: scene.fem.element_size,
            sigma_c_strong,
            weak_right,
            snapshot_time: t_over_t * scene.duration(),
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

/// The FE scene of `text` run with `model` (`fem.model` overridden).
pub fn model_scene(text: &str, model: &str) -> Result<fem::Scene> {
    let text = with_overrides(text, &[("fem.model", Some(Value::String(model.to_string())))])?;
    fem::Scene::from_toml_str(&text).with_context(|| format!("FE model: invalid scene with model = {model}"))
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

/// What the command produced.
#[derive(Debug, Clone)]
pub struct SinusoidReport {
    /// The scene's scale quantities.
    pub setup: Setup,
    /// One row per model.
    pub rows: Vec<(SinusoidSummary, RunInfo)>,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// Runs that went unstable, with when and where.
    pub failures: Vec<String>,
}

fn run_model(text: &str, model: &str, dir: &Path, rep: &dyn Reporter) -> Result<(ModelRun, Vec<PathBuf>)> {
    let scene = model_scene(text, model)?;
    let sub = dir.join(model);
    let mut progress = rep.run_started(&format!("FE {model:<8}"));
    let start = Instant::now();
    let result = fem::run_with_progress(&scene, &mut *progress);
    let wall_s = start.elapsed().as_secs_f64();
    let (out, failure) = match result {
        Ok(out) => (out, None),
        Err(fem::RunError::Unstable {
            step,
            time_s,
            location,
            partial,
        }) => {
            let msg = format!(
                "{model}: run unstable at step {step}, t = {time_s} s ({location}); partial output in {}",
                sub.display()
            );
            (*partial, Some(msg))
        }
        Err(e) => return Err(e).context(format!("FE run with model = {model}")),
    };
    let files = fem::write_csv(&out, &sub).with_context(|| format!("writing {}", sub.display()))?;
    let run = ModelRun {
        model: model.to_string(),
        out,
        wall_s,
        failure,
    };
    Ok((run, files))
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

/// Runs every model of the scene `text`, writing outputs, summary and figures into `dir`.
/// An unstable run keeps its partial output and is listed in `failures`; any other error
/// (invalid scene, failed write) stops the command.
pub fn run_study(text: &str, dir: &Path, rep: &dyn Reporter) -> Result<SinusoidReport> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let setup = Setup::of(text)?;
    let (mut runs, mut files) = (Vec::new(), Vec::new());
    for model in &setup.models {
        let (run, written) = run_model(text, model, dir, rep)?;
        files.extend(written);
        runs.push(run);
    }
    let rows: Vec<_> = runs.iter().map(|r| row(&setup, r)).collect();
    files.push(write_rows(&dir.join("sinusoid_summary.csv"), &rows)?);
    files.extend(crate::sinusoid_snapshot::snapshot_figures(dir, &setup, &runs)?);
    let summaries: Vec<SinusoidSummary> = rows.iter().map(|r| r.0.clone()).collect();
    files.extend(crate::sinusoid_figures::time_figures(
        dir, &setup, &runs, &summaries,
    )?);
    Ok(SinusoidReport {
        setup,
        rows,
        files,
        failures: runs.iter().filter_map(|r| r.failure.clone()).collect(),
    })
}

/// The summary as a text table (for the binary to print).
pub fn table(rows: &[(SinusoidSummary, RunInfo)], setup: &Setup) -> String {
    let duration = setup.duration;
    let mut s = format!(
        "\n{:<9} {:>7} {:>8} {:>9} {:>11} {:>11} {:>10} {:>9} {:>12} {:>8} {:>10} {:>9} {:>8}\n",
        "model",
        "wall_s",
        "steps",
        "KKT max",
        "t_slip2h/T",
        "KKT min>2h",
        "T_viol kPa",
        "mismatch",
        "res. kPa ≥T/2",
        "onset/T",
        "Ek/Es max",
        "tip/a",
        "cz/a"
    );
    for (r, i) in rows {
        let _ = writeln!(
            s,
            "{:<9} {:>7.1} {:>8} {:>8.2}% {:>11.3} {:>10.2}% {:>10.3} {:>8.2}% {:>12.3} {:>8.3} {:>9.2}% {:>9.3} {:>8.3}{}",
            r.model,
            i.wall_s,
            i.steps,
            100.0 * r.max_kkt_share,
            r.t_slip_2h / duration,
            100.0 * r.min_kkt_share_after_slip,
            r.max_violating_traction / 1e3,
            100.0 * r.max_zone_mismatch_share,
            r.mean_residual_stress_second_half / 1e3,
            r.onset / duration,
            100.0 * r.max_kinetic_over_internal_after_onset,
            setup.x_over_a(r.final_tip_right),
            setup.x_over_a(r.final_cz_tip_right),
            if i.completed {
                ""
            } else {
                "  (UNSTABLE: partial run)"
            },
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene_text() -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sinusoidal-interface.toml");
        std::fs::read_to_string(path).unwrap()
    }

    #[test]
    fn setup_reads_the_scene() {
        let text = scene_text();
        let s = Setup::of(&text).unwrap();
        let scene = fem::Scene::from_toml_str(&text).unwrap();
        assert_eq!(s.models, ["standard", "hybrid"]);
        assert_eq!(s.half_length, scene.half_length());
        assert_eq!(s.sigma_c_strong, scene.interface.unwrap().sigma_c);
        // the right weak branch runs from a to 2.5a (cases.md, case 2)
        assert!((s.x_over_a(s.weak_right[0]) - 1.0).abs() < 1e-12);
        assert!((s.x_over_a(s.weak_right[1]) - 2.5).abs() < 1e-12);
        assert!(s.snapshot_time > 0.0 && s.snapshot_time <= s.duration);
        let bad: Vec<&str> = text
            .lines()
            .map(|l| {
                if l.starts_with("snapshot_t_over_T") {
                    "snapshot_t_over_T = 1.5"
                } else {
                    l
                }
            })
            .collect();
        let e = Setup::of(&bad.join("\n")).unwrap_err();
        assert!(
            e.to_string().contains("snapshot_t_over_T = 1.5 out of range"),
            "{e}"
        );
        let e = Setup::of(&text.replace("models = [", "old_models = [")).unwrap_err();
        assert!(e.to_string().contains("compare.models"), "{e}");
    }

    #[test]
    fn model_override_selects_the_model() {
        let text = scene_text();
        for (name, kind) in [
            ("standard", fem::scene::ModelKind::Standard),
            ("hybrid", fem::scene::ModelKind::Hybrid),
        ] {
            assert_eq!(model_scene(&text, name).unwrap().fem.model, kind);
        }
        assert!(model_scene(&text, "neither").is_err());
    }

    #[test]
    fn summary_csv_has_the_metric_columns_then_the_run_columns() {
        let dir = std::env::temp_dir().join(format!("compare-sinusoid-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let setup = Setup::of(&scene_text()).unwrap();
        let run = ModelRun {
            model: "hybrid".into(),
            out: fem::RunOutput {
                steps: 10,
                time_step: 1e-6,
                ..fem::RunOutput::default()
            },
            wall_s: 1.5,
            failure: Some("unstable".into()),
        };
        let r = row(&setup, &run);
        assert!(!r.1.completed);
        let p = write_rows(&dir.join("sinusoid_summary.csv"), std::slice::from_ref(&r)).unwrap();
        let text = std::fs::read_to_string(p).unwrap();
        let header = text.lines().next().unwrap();
        assert_eq!(
            header,
            "model,max_kkt_share,t_slip_2h,min_kkt_share_after_slip,max_violating_traction,\
             max_zone_mismatch_share,mean_residual_stress_second_half,final_residual_stress,onset,\
             max_kinetic_over_internal_after_onset,final_tip_right,final_cz_tip_right,\
             t_weak_cracked,t_strong_entered,wall_s,steps,time_step,completed"
        );
        assert!(text.lines().nth(1).unwrap().starts_with("hybrid,"));
        assert!(table(&[r], &setup).contains("UNSTABLE"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
