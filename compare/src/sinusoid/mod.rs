//! Paper Section 4: the sinusoidal-interface scene run with each model of `[compare].models`
//! (`standard` and `hybrid`), the full FE outputs per model, one summary row per model
//! (definitions of [`metrics`], shared with the validation test) and the figures of
//! [`figures`] and [`snapshot`].

pub mod contact;
pub mod figures;
pub mod metrics;
pub mod setup;
pub mod snapshot;

use crate::concurrent::Lanes;
use crate::output::write_rows;
use crate::runner::{Keep, Reporter, preflight, run_fems};
use crate::study::Study;
use anyhow::{Context, Result};
use metrics::SinusoidSummary;
use setup::{ModelRun, RunInfo, Setup, row};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The study's scene in scenes/ (the default of `compare sinusoid`).
pub const SCENE: &str = "sinusoidal-interface.toml";

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
    /// What the runs did that the user should know.
    pub warnings: Vec<String>,
}

/// Runs every model of `study`, writing outputs, summary and figures into `dir`. Every model's
/// scene is validated before the first run. An unstable run keeps its partial output and is
/// listed in `failures`; any other error (invalid scene, failed write) stops the study.
pub fn run_study(study: &Study, dir: &Path, rep: &dyn Reporter) -> Result<SinusoidReport> {
    let setup = Setup::of(study)?;
    let scenes = setup
        .models
        .iter()
        .map(|m| {
            let scene = study
                .fem
                .with_model(m.kind())
                .with_context(|| format!("compare.models: \"{}\"", m.tag()))?;
            Ok((m.tag(), scene))
        })
        .collect::<Result<Vec<_>>>()?;
    let fems: Vec<(&str, &fem::Scene)> = scenes.iter().map(|(l, s)| (*l, s)).collect();
    let lanes = Lanes::for_fe(
        scenes.iter().map(|(_, s)| s),
        rayon::current_num_threads(),
        study.concurrent_runs,
    );
    // the folder stays locked against other runs until the study returns, its files written
    let (plan, _held) = preflight(study, &fems, &[], dir)?;
    rep.planned(&plan.with_lanes(lanes));
    let jobs: Vec<_> = scenes
        .iter()
        .map(|(model, scene)| (scene, format!("FE {model:<8}"), dir.join(model)))
        .collect();
    let (mut runs, mut warnings) = (Vec::new(), Vec::new());
    for ((model, _), f) in scenes.iter().zip(run_fems(&jobs, Keep::Everything, lanes, rep)?) {
        warnings.extend(f.warnings.iter().cloned());
        runs.push(ModelRun {
            model: model.to_string(),
            out: f.out,
            wall_s: f.wall_s,
            failure: f.failure,
        });
    }
    let rows: Vec<_> = runs.iter().map(|r| row(&setup, r)).collect();
    let mut files = vec![write_rows(&dir.join("sinusoid_summary.csv"), &rows)?];
    files.extend(snapshot::snapshot_figures(dir, &setup, &runs)?);
    let summaries: Vec<SinusoidSummary> = rows.iter().map(|r| r.0.clone()).collect();
    files.extend(figures::time_figures(dir, &setup, &scenes, &runs, &summaries)?);
    Ok(SinusoidReport {
        setup,
        rows,
        files,
        failures: runs.iter().filter_map(|r| r.failure.clone()).collect(),
        warnings,
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
        "Ek/Es qs",
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
            100.0 * r.max_kinetic_over_internal_quasi_static,
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

/// Runs every model of `study` into `dir` ([`run_study`]) and prints its end ([`print_report`]);
/// true when no run went unstable (an unstable run's output is kept).
pub fn run(study: &Study, dir: &Path, rep: &dyn Reporter) -> Result<bool> {
    let report = run_study(study, dir, rep)?;
    Ok(print_report(&report, dir))
}

/// Prints the study's table, where its files went (`dir`), the runs' warnings and the runs
/// that went unstable; true when none did.
pub fn print_report(report: &SinusoidReport, dir: &Path) -> bool {
    print!("{}", table(&report.rows, &report.setup));
    println!("\n{} files written to {}", report.files.len(), dir.display());
    crate::runner::print_warnings(&report.warnings);
    for f in &report.failures {
        println!("FAILED: {f}");
    }
    report.failures.is_empty()
}

#[cfg(test)]
mod tests {
    use super::setup::tests::setup;
    use super::*;

    #[test]
    fn summary_csv_has_the_metric_columns_then_the_run_columns() {
        let dir = std::env::temp_dir().join(format!("compare-sinusoid-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let setup = setup();
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
             max_kinetic_over_internal_quasi_static,max_kinetic_over_internal,final_tip_right,final_cz_tip_right,\
             t_weak_cracked,t_strong_entered,wall_s,steps,time_step,completed"
        );
        assert!(text.lines().nth(1).unwrap().starts_with("hybrid,"));
        assert!(table(&[r], &setup).contains("UNSTABLE"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
