//! Spectral boundary-integral (SBI) solver for a planar interface between two identical linear
//! elastic half-spaces (plane strain, modes I + II), in the independent formulation of Breitenfeld &
//! Geubelle (1998) as implemented in cRacklet, with the linear coupled cohesive law, contact by
//! matching normal displacements and Prakash-regularised Coulomb friction (Pundir & Anciaux 2020,
//! §3.2). Method notes: docs/spectral-model.md. SI units throughout.
//!
//! Public surface: [`Scene`], [`run`], [`run_with_progress`], [`run_checkpointed`], [`ended`], [`RunOutput`],
//! [`TipRecord`], errors, the time profile of a run and the work of a step ([`profile`],
//! [`work_per_step`]); the building blocks ([`kernels`], [`elastodynamics`], [`law`]) are
//! public for verification.
#![warn(missing_docs)]

mod checkpoint;
mod convolution;
mod diag;
pub mod elastodynamics;
mod error;
mod estimate;
mod fast;
mod history;
pub mod kernels;
pub mod law;
pub mod loading;
mod modes;
pub mod output;
mod placement;
pub mod profile;
mod scene;
mod soe;
mod solver;

use std::sync::atomic::{AtomicBool, Ordering};

use preflight::checkpoint::{Resumed, Writer};

use checkpoint::Cursor;
use placement::Placement;

pub use elastodynamics::{ConvolutionStats, FaceFields, HalfSpaceParams, HalfSpaces, Operator};
pub use error::{BuildError, RunError, SceneError};
pub use estimate::estimate;
pub use output::{ContactMeanRecord, FieldRecord, RunOutput, RunStats, TipRecord, write_csv};
pub use profile::{Phase, Profile, StepWork, Work};
pub use scene::{
    ContactFriction, Convolution, DEFAULT_FAST_TOLERANCE, FastStorage, InitialInterface, Nucleation, Ramp,
    Scene, Solid, WaveSpeeds, rayleigh_ratio, slip_wave_exists,
};

/// Runs the scene from t = 0 to T = `[loading].duration`.
pub fn run(scene: &Scene) -> Result<RunOutput, RunError> {
    run_with_progress(scene, &mut |_, _| {}, &AtomicBool::new(false))
}

/// The work of one step of `scene`'s model, per phase (bytes and flops as the model counts
/// them, the direct path's windows full; [`profile`]): builds the model (the kernel fit of the
/// fast path included) without running it.
pub fn work_per_step(scene: &Scene) -> Result<StepWork, BuildError> {
    let (model, _, ws) = solver::build(scene)?;
    Ok(solver::work(&model, &ws))
}

/// How a run ended, from what [`run_with_progress`] (or [`run`]) returned: the error when there
/// was no run (the model cannot be built).
pub fn ended(result: Result<RunOutput, RunError>) -> Result<preflight::RunEnded<RunOutput>, RunError> {
    match result {
        Ok(out) => Ok(preflight::RunEnded::Finished(out)),
        Err(RunError::Unstable {
            step,
            time_s,
            location,
            partial,
        }) => Ok(preflight::RunEnded::Unstable {
            step,
            time_s,
            location,
            partial: *partial,
        }),
        Err(RunError::Interrupted {
            step,
            time_s,
            partial,
        }) => Ok(preflight::RunEnded::Interrupted {
            step,
            time_s,
            partial: *partial,
        }),
        Err(RunError::OutputFailed {
            step,
            time_s,
            message,
            partial,
        }) => Ok(preflight::RunEnded::OutputFailed {
            step,
            time_s,
            message,
            partial: *partial,
        }),
        Err(e) => Err(e),
    }
}

/// Number of sample times k·interval ≤ duration (+1 for t = 0).
fn samples(duration: f64, interval: f64) -> usize {
    (duration / interval).floor() as usize + 2
}

/// As [`run`]; `progress(steps_done, total_steps)` is called at most ~200 times, and the run stops
/// after the step during which `stop` is raised (e.g. by Ctrl-C) with `RunError::Interrupted` and
/// everything recorded so far.
pub fn run_with_progress(
    scene: &Scene,
    progress: &mut dyn FnMut(u64, u64),
    stop: &AtomicBool,
) -> Result<RunOutput, RunError> {
    run_checkpointed(scene, progress, stop, None, None)
}

/// As [`run_with_progress`], with checkpoints (`preflight::checkpoint`; what one holds: the
/// `checkpoint` module's notes).
///
/// - `checkpoints`: where [`progress`](run_with_progress) is reported, the state after the last
///   step done is written when the writer says one is [due](Writer::due), and once more when the
///   run is stopped on request, so that a stopped run resumes. A checkpoint that cannot be
///   written stops the run with `RunError::OutputFailed`, the message naming the file.
/// - `resumed`: the model is built from `scene` (which `preflight::checkpoint::read` checked is
///   the checkpoint's), the checkpoint's state is restored into it and the run continues with
///   its next step; its records are then those of a run that never stopped, to the bit, whatever
///   the thread count. A state that cannot be read or does not fit is `RunError::Resume`.
///
/// With neither, this is [`run_with_progress`]: nothing more is done or allocated.
pub fn run_checkpointed(
    scene: &Scene,
    progress: &mut dyn FnMut(u64, u64),
    stop: &AtomicBool,
    checkpoints: Option<&mut Writer>,
    resumed: Option<&Resumed>,
) -> Result<RunOutput, RunError> {
    let (model, st, ws) = solver::build(scene)?;
    run_placed(
        scene,
        (model, st, ws),
        (progress, stop),
        (checkpoints, resumed),
        &mut Placement::new(),
    )
}

/// [`run_checkpointed`] on a model built from `scene`, its chunks of steps run where `placement`
/// says (the whole pool or one thread: [`placement`]).
fn run_placed(
    scene: &Scene,
    (model, mut st, mut ws): (solver::Model, solver::State, solver::Workspace),
    (progress, stop): (&mut dyn FnMut(u64, u64), &AtomicBool),
    (mut checkpoints, resumed): (Option<&mut Writer>, Option<&Resumed>),
    placement: &mut Placement,
) -> Result<RunOutput, RunError> {
    let last = scene.last_step();
    let total = last + 1;
    let dt = model.dt;
    let field_interval = scene.field_output_interval;
    let conv = ws.half.stats();
    let mut out = RunOutput {
        time_step: dt,
        grid_spacing: scene.grid_spacing(),
        tips: Vec::with_capacity(total as usize),
        contact: Vec::with_capacity(samples(scene.duration, scene.output_interval)),
        fields: Vec::with_capacity(field_interval.map_or(0, |fi| samples(scene.duration, fi) * model.n)),
        stats: RunStats {
            steps: 0,
            grid_points: model.n as u64,
            history_entries: conv.history_entries,
            bytes_per_step: conv.bytes_per_step,
            exp_terms: conv.exp_terms,
            fit_error: conv.fit_error,
            status: preflight::Status::Interrupted,
            last_step: 0,
        },
        profile: Profile::default(),
        work: solver::work(&model, &ws),
    };
    let mut at = match resumed {
        Some(r) => checkpoint::restore(r, &mut st, &mut ws, &mut out)?,
        None => Cursor::START,
    };
    let report_every = (total / 200).max(1);
    while at.next_step <= last {
        let first = at.next_step;
        let end = (first + report_every).min(last + 1);
        // The steps run on a pool thread (inside a rayon scope, or on the one-thread pool the
        // placement may choose): the per-step parallel loops then split work through the
        // worker's own deque instead of injecting jobs from this thread and sleeping on a latch
        // twice per step (measured: ~13 % of the run in the kernel's context-switch paths).
        let failed = placement.run(end - first, || {
            // the progress report and the checkpoint between two chunks are not booked
            ws.clock.start();
            for n in first..end {
                let t = n as f64 * dt;
                if stop.load(Ordering::Relaxed) {
                    return Some((n, t, None));
                }
                let contact_due = t >= at.next_contact as f64 * scene.output_interval - 1e-9 * dt;
                let field_due = field_interval.is_some_and(|fi| t >= at.next_field as f64 * fi - 1e-9 * dt);
                // u^{n+1} within the law's tasks, unless this step's records read u^n
                let advance_in_law = n < last && !contact_due && !field_due;
                if let Some(m) = solver::step(&model, &mut st, &mut ws, n, advance_in_law) {
                    return Some((n, t, Some(m)));
                }
                out.stats.steps = n + 1;
                out.stats.last_step = n;
                out.tips.push(diag::tips(&model, &st, t));
                if contact_due {
                    out.contact.push(diag::contact_means(&model, &st, t));
                    at.next_contact += 1;
                }
                if field_due {
                    diag::fields(&model, &st, t, &mut out.fields);
                    at.next_field += 1;
                }
                ws.clock.lap(Phase::Records);
                if n < last && !advance_in_law {
                    solver::advance(&model, &mut st);
                }
                ws.clock.lap(Phase::Update);
                at.next_step = n + 1;
            }
            None
        });
        out.profile = Profile {
            one_thread_steps: placement.one_thread_steps(),
            ..ws.clock.profile()
        };
        if let Some((n, t, None)) = failed {
            // the state after step n − 1 (u^n included), resumable at step n
            let stopped = (n.saturating_sub(1), (t - dt).max(0.0));
            if let Some(w) = checkpoints.as_deref_mut()
                && let Err(e) = checkpoint::write(w, &model, &st, &ws, &out, at)
            {
                return Err(output_failed(out, stopped, &e));
            }
            out.stats.status = preflight::Status::Interrupted;
            return Err(RunError::Interrupted {
                step: stopped.0,
                time_s: stopped.1,
                partial: Box::new(out),
            });
        }
        if let Some((n, t, Some(m))) = failed {
            out.stats.status = preflight::Status::Unstable;
            return Err(RunError::Unstable {
                step: n,
                time_s: t,
                location: format!(
                    "grid point {m} (x = {} m): face velocity non-finite or > 1e3 × (peak stress)/Z",
                    model.x[m]
                ),
                partial: Box::new(out),
            });
        }
        // a run that reached its end has nothing to resume
        if end <= last
            && let Some(w) = checkpoints.as_deref_mut()
            && w.due()
            && let Err(e) = checkpoint::write(w, &model, &st, &ws, &out, at)
        {
            return Err(output_failed(out, (end - 1, (end - 1) as f64 * dt), &e));
        }
        progress(end, total);
    }
    progress(total, total);
    out.stats.status = preflight::Status::Finished;
    Ok(out)
}

/// The end of a run whose checkpoint could not be written after step `step` at `time_s` [s].
fn output_failed(mut out: RunOutput, (step, time_s): (u64, f64), e: &std::io::Error) -> RunError {
    out.stats.status = preflight::Status::OutputFailed;
    RunError::OutputFailed {
        step,
        time_s,
        message: format!("checkpoint: {e}"),
        partial: Box::new(out),
    }
}
