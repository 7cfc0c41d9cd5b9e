//! The FE-versus-spectral comparison from Python: `compare::gate::run_gate`, the function behind
//! `cargo run -p compare`, with its tables read back from the files it wrote.

use crate::run::{Progress, drive};
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

/// Runs both models on ``scene`` and compares them, as ``cargo run -p compare -- --scene FILE``
/// does (paper-resolution tolerances). Returns a dict: ``passed``; ``metrics`` (metrics.csv as
/// ``{column: array}``); ``tips`` (``{"fem_mu0": {column: array}, "spectral_mu0": ...}``, the tip
/// histories, the spectral ones shifted); ``files`` (every file written; none without ``out``); ``warnings``;
/// ``spacing`` (FE h and spectral Δx [m]). Writes into ``out``, or into a temporary folder
/// removed before it returns.
#[pyfunction]
#[pyo3(signature = (scene, *, out = None, friction_rule = None, concurrent_runs = None,
                    max_memory_gib = 8.0, max_steps = preflight::budget::DEFAULT_MAX_STEPS, progress = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn gate(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    out: Option<PathBuf>,
    friction_rule: Option<&str>,
    concurrent_runs: Option<usize>,
    max_memory_gib: f64,
    max_steps: u64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Py<PyDict>> {
    if !(max_memory_gib.is_finite() && max_memory_gib > 0.0) {
        return Err(PyValueError::new_err(format!(
            "max_memory_gib = {max_memory_gib}: a memory budget is a finite number of GiB > 0"
        )));
    }
    let mut study = scene.borrow().study()?;
    if let Some(rule) = friction_rule {
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
    // keys the harness reads only when the comparison runs: refused here, as scene errors
    study
        .friction_coeffs()
        .map_err(|e| crate::SceneError::new_err(format!("{e:#}")))?;
    if concurrent_runs == Some(0) {
        return Err(PyValueError::new_err("concurrent_runs = 0: at least 1"));
    }
    study.concurrent_runs = concurrent_runs;
    study.budget = preflight::Budget::new(max_memory_gib, max_steps);
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
    let (report, stopped_by) = drive(py, progress.as_ref(), |p| {
        let sums = Sums {
            progress: p,
            runs: Mutex::new(Vec::new()),
        };
        compare::gate::run_gate(&study, &PAPER_RESOLUTION, &dir, &sums)
    })?;
    if let Some(e) = stopped_by {
        return Err(e);
    }
    let report = report.map_err(|e| PyRuntimeError::new_err(format!("{e:#}")))?;
    let d = PyDict::new(py);
    d.set_item("passed", report.passed())?;
    let metrics = crate::tables::read_tables(py, &[dir.join("metrics.csv")])?;
    d.set_item("metrics", metrics.bind(py).get_item("metrics")?)?;
    let tip_files: Vec<PathBuf> = report
        .files
        .iter()
        .filter(|f| {
            f.parent() == Some(dir.as_path())
                && f.file_name().is_some_and(|n| {
                    let n = n.to_string_lossy();
                    (n.starts_with("fem_mu") || n.starts_with("spectral_mu")) && n.ends_with(".csv")
                })
        })
        .cloned()
        .collect();
    d.set_item("tips", crate::tables::read_tables(py, &tip_files)?)?;
    d.set_item("files", if keep { report.files.clone() } else { Vec::new() })?;
    d.set_item("warnings", report.warnings.clone())?;
    d.set_item("spacing", report.spacing)?;
    Ok(d.unbind())
}
