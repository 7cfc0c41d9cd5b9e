//! The harness's jobs from Python: the comparison (`compare::gate::run_gate`, the function behind
//! `cargo run -p compare`) and the other jobs that run in one process, each with the tables read
//! back from the files it wrote.

use crate::run::{Progress, budget, drive};
use crate::scene::Scene;
use compare::gate::metrics::PAPER_RESOLUTION;
use compare::runner::Reporter;
use compare::study::FrictionRule;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// Sums the steps of every run of the study into one (done, total) pair, and hands the runs the
/// stop flag.
struct Sums<'a> {
    progress: &'a Progress,
    /// (done, total) per run started.
    runs: Mutex<Vec<(u64, u64)>>,
}

impl Sums<'_> {
    fn update(&self, run: usize, done: u64, total: u64) {
        let mut runs = self.runs.lock().unwrap_or_else(|e| e.into_inner());
        runs[run] = (done, total);
        let (d, t) = runs.iter().fold((0, 0), |(d, t), r| (d + r.0, t + r.1));
        self.progress.total.store(t, Ordering::Relaxed);
        self.progress.done.store(d, Ordering::Relaxed);
    }
}

impl Reporter for Sums<'_> {
    fn run_started(&self, _label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_> {
        let run = {
            let mut runs = self.runs.lock().unwrap_or_else(|e| e.into_inner());
            runs.push((0, 0));
            runs.len() - 1
        };
        Box::new(move |d, t| self.update(run, d, t))
    }

    fn stop(&self) -> &AtomicBool {
        &self.progress.stop
    }
}

/// What a job gave, before its tables are read: whether every check passed, the files written,
/// the warnings, and for the comparison and `converged` the FE h and spectral Δx [m].
struct Ran {
    passed: bool,
    files: Vec<PathBuf>,
    warnings: Vec<String>,
    failures: Vec<String>,
    spacing: Option<(f64, f64)>,
}

/// The job `name` of the harness on `study` into `dir`, as `compare [JOB]` runs it; `values`: the
/// penalty factors of `penalty`, the box factors of `boundary`.
fn run_job(
    name: &str,
    study: &compare::study::Study,
    values: Option<&[u32]>,
    dir: &std::path::Path,
    rep: &dyn Reporter,
) -> anyhow::Result<Ran> {
    let gate = |r: compare::gate::GateReport| Ran {
        passed: r.passed(),
        spacing: Some(r.spacing),
        files: r.files,
        warnings: r.warnings,
        failures: Vec::new(),
    };
    Ok(match name {
        "gate" => gate(compare::gate::run_gate(study, &PAPER_RESOLUTION, dir, rep)?),
        "converged" => gate(compare::converged::run_converged(study, dir, rep)?.gate),
        "penalty" => {
            let factors = values.unwrap_or(&compare::penalty::EPS_FACTORS);
            let r = compare::penalty::run_study(study, factors, dir, rep)?;
            Ran {
                passed: true,
                files: r.files,
                warnings: r.warnings,
                failures: Vec::new(),
                spacing: None,
            }
        }
        "boundary" => {
            let boxes = values.unwrap_or(&compare::boundary::BOX_FACTORS);
            let r = compare::boundary::run_study(study, boxes, dir, rep)?;
            Ran {
                passed: true,
                files: r.files,
                warnings: Vec::new(),
                failures: Vec::new(),
                spacing: None,
            }
        }
        // `rough` is the same study on the rough interface's scene
        "sinusoid" | "rough" => {
            let r = compare::sinusoid::run_study(study, dir, rep)?;
            Ran {
                passed: r.failures.is_empty(),
                files: r.files,
                warnings: r.warnings,
                failures: r.failures,
                spacing: None,
            }
        }
        other => anyhow::bail!(
            "job = {other:?}: one of \"gate\", \"converged\", \"penalty\", \"boundary\", \"sinusoid\", \"rough\""
        ),
    })
}

/// Runs the job ``job`` of the harness on ``scene``, as ``cargo run --release -p compare -- [JOB]
/// --scene FILE`` does: "gate" (the comparison, paper-resolution tolerances), "converged",
/// "penalty" (``values``: the factors), "boundary" (``values``: the box factors), "sinusoid" or
/// "rough". Returns a dict: ``passed`` (every metric within its tolerance; for the sinusoid
/// studies, no run unstable); ``tables`` (every CSV file the job wrote at the top of its folder,
/// ``{file stem: {column: array}}``); ``files`` (none without ``out``); ``warnings``;
/// ``failures`` (unstable runs, when and where); ``spacing`` (FE h and spectral Δx [m], or None).
/// Writes into ``out``, or into a temporary folder removed before it returns.
#[pyfunction]
#[pyo3(signature = (scene, job, *, out = None, friction_rule = None, concurrent_runs = None,
                    max_memory_gib = 8.0, max_steps = preflight::budget::DEFAULT_MAX_STEPS, progress = None,
                    values = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn job(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    job: &str,
    out: Option<PathBuf>,
    friction_rule: Option<&str>,
    concurrent_runs: Option<usize>,
    max_memory_gib: f64,
    max_steps: u64,
    progress: Option<Py<PyAny>>,
    values: Option<Vec<u32>>,
) -> PyResult<Py<PyDict>> {
    if !["gate", "converged", "penalty", "boundary", "sinusoid", "rough"].contains(&job) {
        return Err(PyValueError::new_err(format!(
            "job = {job:?}: one of \"gate\", \"converged\", \"penalty\", \"boundary\", \"sinusoid\", \"rough\""
        )));
    }
    let limits = budget(max_memory_gib, max_steps)?;
    if let Some(v) = &values {
        let key = if job == "penalty" { "factors" } else { "boxes" };
        if !matches!(job, "penalty" | "boundary") {
            return Err(PyValueError::new_err(format!(
                "values: taken by penalty and boundary only, not {job}"
            )));
        }
        if v.is_empty() || v.contains(&0) {
            return Err(PyValueError::new_err(format!(
                "{key} = {v:?}: whole numbers >= 1, at least one"
            )));
        }
    }
    let mut study = scene.borrow().study()?;
    if let Some(rule) = friction_rule {
        if !matches!(job, "gate" | "converged") {
            return Err(PyValueError::new_err(format!(
                "friction_rule: taken by gate and converged only; for {job} set [friction] \
                 contact_friction in the scene"
            )));
        }
        let rule = match rule {
            "all_faces" => FrictionRule::AllFaces,
            "failed_only" => FrictionRule::FailedOnly,
            other => {
                return Err(PyValueError::new_err(format!(
                    "friction_rule = {other:?}: allowed \"all_faces\" or \"failed_only\""
                )));
            }
        };
        study = study
            .with_friction_rule(rule)
            .map_err(|e| crate::SceneError::new_err(format!("{e:#}")))?;
    }
    // the [compare] keys the harness reads only when a job runs: refused here, as scene errors
    let scene_error = |e: anyhow::Error| crate::SceneError::new_err(format!("{e:#}"));
    if matches!(job, "gate" | "converged" | "boundary") {
        study.friction_coeffs().map_err(scene_error)?;
    }
    if matches!(job, "sinusoid" | "rough") {
        study.models().map_err(scene_error)?;
        study.snapshot_t_over_t().map_err(scene_error)?;
    }
    if concurrent_runs == Some(0) {
        return Err(PyValueError::new_err("concurrent_runs = 0: at least 1"));
    }
    study.concurrent_runs = concurrent_runs;
    study.budget = limits;
    let keep = out.is_some();
    let tmp;
    let dir = match out {
        Some(d) => d,
        None => {
            tmp =
                tempfile::tempdir().map_err(|e| PyRuntimeError::new_err(format!("temporary folder: {e}")))?;
            tmp.path().to_path_buf()
        }
    };
    let (ran, stopped_by) = drive(py, progress.as_ref(), |p| {
        let sums = Sums {
            progress: p,
            runs: Mutex::new(Vec::new()),
        };
        run_job(job, &study, values.as_deref(), &dir, &sums)
    })?;
    if let Some(e) = stopped_by {
        return Err(e);
    }
    let ran = ran.map_err(|e| PyRuntimeError::new_err(format!("{e:#}")))?;
    let d = PyDict::new(py);
    d.set_item("passed", ran.passed)?;
    let top: Vec<PathBuf> = ran
        .files
        .iter()
        .filter(|f| f.parent() == Some(dir.as_path()) && f.extension().is_some_and(|x| x == "csv"))
        .cloned()
        .collect();
    d.set_item("tables", crate::tables::read_tables(py, &top)?)?;
    d.set_item("files", if keep { ran.files.clone() } else { Vec::new() })?;
    d.set_item("warnings", ran.warnings)?;
    d.set_item("failures", ran.failures)?;
    d.set_item("spacing", ran.spacing)?;
    Ok(d.unbind())
}
