//! One model's run from Python: the scene checked as the command line checks it (the scene, then
//! the budget), the run on a worker thread with the GIL released, and the calling thread polling
//! every 20 ms for Ctrl-C (`KeyboardInterrupt` raises the run's stop flag: it stops at its next
//! step) and for progress to report. The run goes through the harness's `runner::Model`, as every
//! run of `compare` does.

use crate::scene::Scene;
use crate::{BudgetError, RunUnstable, SceneError};
use compare::runner::Model;
use preflight::RunEnded;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How often the calling thread looks for Ctrl-C and reports progress while a run goes on.
const POLL: Duration = Duration::from_millis(20);

/// The records of a finished (or stopped) run.
enum Output {
    Fem(Box<fem::RunOutput>),
    Spectral(Box<spectral::RunOutput>),
}

/// The result of one run of one model (``fem.run`` or ``spectral.run``): its records and how it
/// went. The package's ``Result`` wraps it.
#[pyclass(module = "cohesive_contact", frozen)]
pub struct Run {
    output: Output,
    /// "finished", "unstable" or "interrupted".
    ended: &'static str,
    /// Why a run stopped before T, with when (and where); `None` when it reached T.
    why: Option<String>,
    wall_time_s: f64,
    threads: usize,
    warnings: Vec<String>,
}

impl Run {
    fn write(&self, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
        match &self.output {
            Output::Fem(o) => fem::Scene::write(o, dir),
            Output::Spectral(o) => spectral::Scene::write(o, dir),
        }
    }

    fn model(&self) -> &'static str {
        match self.output {
            Output::Fem(_) => "fem",
            Output::Spectral(_) => "spectral",
        }
    }
}

#[pymethods]
impl Run {
    /// Every CSV table the command line writes for this run, as
    /// ``{table: {column: numpy array}}`` (docs/outputs.md lists the columns and their units).
    fn tables(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        let tmp =
            tempfile::tempdir().map_err(|e| PyRuntimeError::new_err(format!("temporary folder: {e}")))?;
        let files = py
            .detach(|| self.write(tmp.path()))
            .map_err(|e| PyRuntimeError::new_err(format!("writing the tables: {e}")))?;
        crate::tables::read_tables(py, &files)
    }

    /// Writes the run's CSV files into ``folder``, as the command line does (the same bytes);
    /// returns their paths. The folder is claimed for the model as the command line claims it.
    fn write_csv(&self, py: Python<'_>, folder: PathBuf) -> PyResult<Vec<PathBuf>> {
        // held while the files are written: no other run writes into the folder meanwhile
        let _claim = preflight::paths::claim(&folder, self.model()).map_err(PyValueError::new_err)?;
        py.detach(|| self.write(&folder))
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(format!("writing {}: {e}", folder.display())))
    }

    /// How the run went: ``model``, ``ended`` ("finished", "unstable" or "interrupted"), ``why``
    /// (when and where a run stopped before T, else None), ``steps``, ``time_step`` [s],
    /// ``wall_time_s`` [s], ``threads``, ``warnings``, and the model's own figures (FE:
    /// ``elements``, ``model``, ``dropped_contacts``; spectral: ``grid_points``,
    /// ``grid_spacing`` [m], ``bytes_per_step``, ``exp_terms``).
    #[getter]
    fn summary(&self, py: Python<'_>) -> PyResult<Py<PyDict>> {
        let d = PyDict::new(py);
        d.set_item("model", self.model())?;
        d.set_item("ended", self.ended)?;
        d.set_item("why", self.why.clone())?;
        match &self.output {
            Output::Fem(o) => {
                d.set_item("steps", o.steps)?;
                d.set_item("time_step", o.time_step)?;
                d.set_item("elements", o.elements)?;
                d.set_item("fem_model", o.model.clone())?;
                d.set_item("dropped_contacts", o.record().dropped_contacts)?;
            }
            Output::Spectral(o) => {
                d.set_item("steps", o.stats.steps)?;
                d.set_item("time_step", o.time_step)?;
                d.set_item("grid_points", o.stats.grid_points)?;
                d.set_item("grid_spacing", o.grid_spacing)?;
                d.set_item("bytes_per_step", o.stats.bytes_per_step)?;
                d.set_item("exp_terms", o.stats.exp_terms)?;
            }
        }
        d.set_item("wall_time_s", self.wall_time_s)?;
        d.set_item("threads", self.threads)?;
        d.set_item("warnings", self.warnings.clone())?;
        Ok(d.unbind())
    }
}

/// Where a run stands, shared between the worker thread and the calling thread.
pub(crate) struct Progress {
    /// Steps done (over every run of a study).
    pub done: AtomicU64,
    /// Steps in all.
    pub total: AtomicU64,
    /// Raised to stop the run at its next step.
    pub stop: AtomicBool,
}

/// Runs `run` on a worker thread with the GIL released. The calling thread wakes every [`POLL`]:
/// it raises the stop flag on Ctrl-C (or when the progress callback raises) and calls `progress`
/// with (steps done, total steps) when they changed. Returns the run's result and the Python error
/// that stopped it, if any.
pub(crate) fn drive<T: Send>(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    run: impl FnOnce(&Progress) -> T + Send,
) -> PyResult<(T, Option<PyErr>)> {
    let state = Progress {
        done: AtomicU64::new(0),
        total: AtomicU64::new(0),
        stop: AtomicBool::new(false),
    };
    let (done, total, stop) = (&state.done, &state.total, &state.stop);
    let mut reported = u64::MAX;
    let report = |py: Python<'_>, reported: &mut u64| -> PyResult<()> {
        py.check_signals()?;
        let d = done.load(Ordering::Relaxed);
        if let Some(cb) = progress
            && d != *reported
        {
            *reported = d;
            cb.call1(py, (d, total.load(Ordering::Relaxed)))?;
        }
        Ok(())
    };
    let (joined, mut stopped_by) = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| run(&state));
            let mut stopped_by: Option<PyErr> = None;
            while !worker.is_finished() {
                std::thread::sleep(POLL);
                if stopped_by.is_none()
                    && let Err(e) = Python::attach(|py| report(py, &mut reported))
                {
                    stop.store(true, Ordering::Relaxed);
                    stopped_by = Some(e);
                }
            }
            (worker.join(), stopped_by)
        })
    });
    if stopped_by.is_none()
        && let Err(e) = report(py, &mut reported)
    {
        stopped_by = Some(e);
    }
    match joined {
        Ok(r) => Ok((r, stopped_by)),
        Err(_) => Err(PyRuntimeError::new_err(
            "the run panicked (a bug: please report it with the scene)",
        )),
    }
}

/// The budget of a run, refused if not a positive number.
pub(crate) fn budget(max_memory_gib: f64, max_steps: u64) -> PyResult<preflight::Budget> {
    if !(max_memory_gib.is_finite() && max_memory_gib > 0.0) {
        return Err(PyValueError::new_err(format!(
            "max_memory_gib = {max_memory_gib}: a memory budget is a finite number of GiB > 0"
        )));
    }
    Ok(preflight::Budget::new(max_memory_gib, max_steps))
}

/// Runs a checked scene of model `M` and packs what it gave: a finished run, or the error that
/// stopped it with the run up to there as its `partial`.
fn run_model<M: Model + Sync>(
    py: Python<'_>,
    scene: &M,
    estimate: &preflight::Estimate,
    limits: preflight::Budget,
    mut warnings: Vec<String>,
    progress: Option<Py<PyAny>>,
    pack: fn(M::Output) -> Output,
) -> PyResult<Run>
where
    M::Output: Send,
{
    limits.check(estimate).map_err(|m| {
        // the command line's message, with this function's arguments for its flags
        BudgetError::new_err(
            m.replace("--max-steps ", "max_steps=")
                .replace("--max-memory ", "max_memory_gib="),
        )
    })?;
    let started = Instant::now();
    let (ended, stopped_by) = drive(py, progress.as_ref(), |p| {
        let mut report = |d, t| {
            p.total.store(t, Ordering::Relaxed);
            p.done.store(d, Ordering::Relaxed);
        };
        scene.run_scene(&mut report, &p.stop)
    })?;
    let wall_time_s = started.elapsed().as_secs_f64();
    let ended = ended.map_err(|e| SceneError::new_err(format!("{e:#}")))?;
    let (kind, why) = match &ended {
        RunEnded::Finished(_) => ("finished", None),
        RunEnded::Unstable {
            step,
            time_s,
            location,
            ..
        } => (
            "unstable",
            Some(format!("unstable at step {step}, t = {time_s} s: {location}")),
        ),
        RunEnded::Interrupted { step, time_s, .. } => (
            "interrupted",
            Some(format!("stopped on request at step {step}, t = {time_s} s")),
        ),
        RunEnded::OutputFailed {
            step,
            time_s,
            message,
            ..
        } => (
            "unstable",
            Some(format!("stopped at step {step}, t = {time_s} s: {message}")),
        ),
    };
    let out = ended.into_output();
    warnings.extend(scene.warnings("the run", &out));
    let run = Run {
        output: pack(out),
        ended: kind,
        why: why.clone(),
        wall_time_s,
        threads: rayon::current_num_threads(),
        warnings,
    };
    let err = match (kind, stopped_by) {
        ("finished", None) => return Ok(run),
        // Ctrl-C, or the progress callback raised: that error, with the run up to there
        (_, Some(e)) => e,
        ("unstable", None) => RunUnstable::new_err(why.unwrap_or_default()),
        (_, None) => PyRuntimeError::new_err(why.unwrap_or_default()),
    };
    err.value(py).setattr("partial", Py::new(py, run)?)?;
    Err(err)
}

/// Runs `model` ("fem" or "spectral") on ``scene`` from t = 0 to T, as that model's command
/// does.
#[pyfunction]
#[pyo3(signature = (scene, model, *, max_memory_gib = 8.0, max_steps = preflight::budget::DEFAULT_MAX_STEPS,
                    progress = None))]
pub(crate) fn run(
    py: Python<'_>,
    scene: &Bound<'_, Scene>,
    model: &str,
    max_memory_gib: f64,
    max_steps: u64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Run> {
    let limits = budget(max_memory_gib, max_steps)?;
    match model {
        "fem" => {
            let checked = scene.borrow().fem()?;
            let estimate = fem::estimate(&checked);
            let mut warnings = checked.warnings();
            if checked.fem.paraview.is_some() {
                warnings.push(
                    "fem.paraview: the ParaView snapshots are written by the fem command; fem.run \
                     returns the CSV tables only"
                        .into(),
                );
            }
            run_model(py, &checked, &estimate, limits, warnings, progress, |o| {
                Output::Fem(Box::new(o))
            })
        }
        "spectral" => {
            let checked = scene.borrow().spectral()?;
            let estimate = spectral::estimate(&checked).map_err(|e| SceneError::new_err(e.to_string()))?;
            let warnings = checked.warnings();
            run_model(py, &checked, &estimate, limits, warnings, progress, |o| {
                Output::Spectral(Box::new(o))
            })
        }
        other => Err(PyValueError::new_err(format!(
            "model = {other:?}: \"fem\" or \"spectral\""
        ))),
    }
}
