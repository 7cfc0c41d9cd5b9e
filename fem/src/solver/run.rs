//! The time loop: steps from 0 to T, samples every `output_interval` (and takes the ParaView
//! snapshots a caller asks for), stops on instability (RunError::Unstable), when asked to
//! (RunError::Interrupted) or when a snapshot or a checkpoint cannot be written
//! (RunError::FieldOutput), with the output computed so far. It writes checkpoints when asked to,
//! and resumes from one.

use crate::diag::fields::Snapshots;
use crate::diag::{Observer, Recorder, tips};
use crate::error::RunError;
use crate::model::build::build;
use crate::model::state::{Model, State, Workspace};
use crate::profile::Phase;
use crate::records::RunOutput;
use crate::records::fields::FieldSink;
use crate::scene::Scene;
use crate::solver::central_difference::step;
use crate::solver::checkpoint;
use preflight::RunEnded;
use preflight::checkpoint::{Resumed, Writer};
use std::sync::atomic::{AtomicBool, Ordering};

/// Runs the scene from t = 0 to T.
pub fn run(scene: &Scene) -> Result<RunOutput, RunError> {
    run_with_progress(scene, &mut |_, _| {}, &AtomicBool::new(false))
}

/// As [`run`]; `progress(steps_done, total_steps)` is called at most a few hundred times, and the
/// run stops after the first step that begins once `stop` is raised (e.g. by Ctrl-C), with
/// `RunError::Interrupted` and everything recorded so far.
pub fn run_with_progress(
    scene: &Scene,
    progress: &mut dyn FnMut(u64, u64),
    stop: &AtomicBool,
) -> Result<RunOutput, RunError> {
    run_with_fields(scene, progress, stop, None)
}

/// How a run ended, from what [`run_with_fields`] (or [`run`], [`run_with_progress`]) returned:
/// the error when there was no run (an invalid scene, a model that cannot be built).
pub fn ended(result: Result<RunOutput, RunError>) -> Result<RunEnded<RunOutput>, RunError> {
    match result {
        Ok(out) => Ok(RunEnded::Finished(out)),
        Err(RunError::Unstable {
            step,
            time_s,
            location,
            partial,
        }) => Ok(RunEnded::Unstable {
            step,
            time_s,
            location,
            partial: *partial,
        }),
        Err(RunError::Interrupted {
            step,
            time_s,
            partial,
        }) => Ok(RunEnded::Interrupted {
            step,
            time_s,
            partial: *partial,
        }),
        Err(RunError::FieldOutput {
            step,
            time_s,
            message,
            partial,
        }) => Ok(RunEnded::OutputFailed {
            step,
            time_s,
            message,
            partial: *partial,
        }),
        Err(e) => Err(e),
    }
}

/// As [`run_with_progress`]; with `fields`, the ParaView snapshots the scene declares
/// (`[fem.paraview]`) are computed and handed to it as they are taken: at t = 0, every interval,
/// and at the last step however the run ends. A snapshot the sink cannot take stops the run with
/// `RunError::FieldOutput`. Without `[fem.paraview]` or without `fields`, none is computed.
pub fn run_with_fields(
    scene: &Scene,
    progress: &mut dyn FnMut(u64, u64),
    stop: &AtomicBool,
    fields: Option<&mut dyn FieldSink>,
) -> Result<RunOutput, RunError> {
    run_checkpointed(scene, progress, stop, fields, None, None)
}

/// As [`run_with_fields`], with checkpoints (docs/checkpoints.md):
/// - with `checkpoints`, the complete state is written whenever the writer says one is due (it
///   is asked a few hundred times per run, between steps), and when the run is stopped on
///   request, so that the run can be resumed; a checkpoint that cannot be written stops the run
///   with `RunError::FieldOutput`;
/// - with `resumed`, the run continues from that checkpoint (which `preflight::checkpoint::read`
///   checked against the scene) instead of t = 0; its records, snapshots and files are then
///   the same, to the bit, as those of a run that never stopped.
pub fn run_checkpointed(
    scene: &Scene,
    progress: &mut dyn FnMut(u64, u64),
    stop: &AtomicBool,
    fields: Option<&mut dyn FieldSink>,
    mut checkpoints: Option<&mut Writer>,
    resumed: Option<&Resumed>,
) -> Result<RunOutput, RunError> {
    let (model, mut state, mut ws) = build(scene)?;
    let dt = model.dt;
    let total = (scene.duration() / dt).ceil() as u64;
    let every = ((scene.fem.output_interval / dt).round() as u64).max(1);
    let report = (total / 200).max(1);
    let mut out = RunOutput {
        time_step: dt,
        elements: model.num_elements(),
        model: match scene.fem.model {
            crate::scene::ModelKind::Hybrid => "hybrid",
            crate::scene::ModelKind::Standard => "standard",
        }
        .to_string(),
        lateral_contraction: model.boundary.lateral_contraction,
        mode_ii_uy: scene.fem.mode_ii_uy,
        damping: scene.fem.damping.describe(),
        boundary_parts: model.boundary.parts.names.clone(),
        ..RunOutput::default()
    };
    let mut snapshots = Snapshots::new(scene, dt, fields);
    match resumed {
        Some(r) => {
            let saved = r.state().map_err(RunError::Resume)?;
            checkpoint::restore(saved, &model, &mut state, &mut ws, &mut out, &mut snapshots)
                .map_err(RunError::Resume)?;
        }
        None => {
            Recorder { out: &mut out }.observe(&model, &state, &ws);
            snapshots.after_step(&model, &state);
        }
    }
    let mut done = state.step;
    let pool = preflight::pool::Steps::new();
    while done < total {
        let end = (done + report).min(total);
        // The steps run inside a rayon scope, i.e. on a pool thread: parallel loops then use the
        // worker's own deque instead of injecting jobs from outside (which allocates); the pool's
        // other workers wait for them awake, not asleep (`preflight::pool`).
        let failed = pool.run(|| {
            for n in done + 1..=end {
                let record = n % every == 0 || n == total;
                // A step whose state is read after it (by the records, a snapshot, or the end of
                // a stopped run) leaves every node at t_{n+1}: an unsampled step may already
                // have moved the bulk on by the next step's predictor.
                let stopping = stop.load(Ordering::Relaxed);
                let sample = record || snapshots.due(n) || stopping;
                if let Err(b) = step(&model, &mut state, &mut ws, sample) {
                    return Some(Err(b));
                }
                if record {
                    ws.clock.start();
                    Recorder { out: &mut out }.observe(&model, &state, &ws);
                    ws.clock.lap(Phase::Diagnostics);
                }
                if !snapshots.after_step(&model, &state) || stopping {
                    return Some(Ok(()));
                }
            }
            None
        });
        if let Some(Ok(())) = failed {
            // stopped on request: the checkpoint of this step, before the records of the end
            let unsaved = match checkpoints.as_deref_mut() {
                Some(w) if !snapshots.failed() => checkpoint::write(w, &state, &ws, &out, &snapshots).err(),
                _ => None,
            };
            finish(&model, &state, &ws, &mut out, &mut snapshots);
            let failed = snapshots.error().map(|e| format!("field snapshot: {e}"));
            if let Some(message) = failed.or(unsaved.map(|e| format!("checkpoint: {e}"))) {
                out.status = preflight::Status::OutputFailed;
                return Err(RunError::FieldOutput {
                    step: state.step,
                    time_s: state.t,
                    message,
                    partial: Box::new(out),
                });
            }
            out.status = preflight::Status::Interrupted;
            return Err(RunError::Interrupted {
                step: state.step,
                time_s: state.t,
                partial: Box::new(out),
            });
        }
        if let Some(Err(b)) = failed {
            let x = model.bulk.x0[b.node];
            let v = state.v[b.node];
            finish(&model, &state, &ws, &mut out, &mut snapshots);
            out.status = preflight::Status::Unstable;
            return Err(RunError::Unstable {
                step: state.step,
                time_s: state.t,
                location: format!(
                    "node {} at ({:.6}, {:.6}) m, velocity ({:.3e}, {:.3e}) m/s",
                    b.node, x.x, x.y, v.x, v.y
                ),
                partial: Box::new(out),
            });
        }
        done = end;
        progress(done, total);
        if let Some(w) = checkpoints.as_deref_mut()
            && done < total
            && w.due()
            && let Err(e) = checkpoint::write(w, &state, &ws, &out, &snapshots)
        {
            finish(&model, &state, &ws, &mut out, &mut snapshots);
            out.status = preflight::Status::OutputFailed;
            return Err(RunError::FieldOutput {
                step: state.step,
                time_s: state.t,
                message: format!("checkpoint: {e}"),
                partial: Box::new(out),
            });
        }
    }
    finish(&model, &state, &ws, &mut out, &mut snapshots);
    match snapshots.error() {
        Some(e) => {
            out.status = preflight::Status::OutputFailed;
            Err(RunError::FieldOutput {
                step: state.step,
                time_s: state.t,
                message: format!("field snapshot: {e}"),
                partial: Box::new(out),
            })
        }
        None => {
            out.status = preflight::Status::Finished;
            Ok(out)
        }
    }
}

/// The records computed once, when the run ends (at T or before), and the last snapshot.
fn finish(model: &Model, state: &State, ws: &Workspace, out: &mut RunOutput, snapshots: &mut Snapshots) {
    snapshots.last(model, state);
    out.steps = state.step;
    out.arrivals = tips::arrivals(model, state);
    out.friction = crate::diag::energy::friction_records(model, state);
    out.profile = ws.profile();
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;
    use crate::test_scenes::scene_text;

    fn tiny_with(extra: &str) -> Scene {
        let text = scene_text("tiny-fem-center-crack").replace("[fem]\n", &format!("[fem]\n{extra}\n"));
        Scene::from_toml_str(&text).unwrap()
    }

    #[test]
    fn polyline_interface_maps_the_row_and_runs() {
        // a bump y = 1.5 mm on the right cohesive part (x in [10, 20] mm), flat elsewhere
        let scene = tiny_with("interface_polyline = [[0.01, 0.0], [0.015, 1.5e-3], [0.02, 0.0]]");
        assert!((scene.fem.interface_y(0.0125) - 0.75e-3).abs() < 1e-15);
        assert_eq!(scene.fem.interface_y(0.0), 0.0);
        // rows above the bump are compressed to (10 mm − 1.5 mm)/10 rows = 0.85 mm, and the row
        // next to the peak rises with slope 1.5/5 = 0.3: altitude 0.85 mm / √(1 + 0.3²)
        let expect = 0.85e-3 / (1.0f64 + 0.09).sqrt();
        assert!(
            (scene.fem.min_edge() - expect).abs() < 1e-12,
            "{}",
            scene.fem.min_edge()
        );
        let (model, _, _) = crate::model::build::build(&scene).unwrap();
        assert!(!crate::probe::shares_stiffness(&model));
        let flat = tiny_with("");
        assert!(
            scene.time_step() < flat.time_step(),
            "h_min enters the stable step"
        );
        let out = super::run(&scene).expect("mapped run stays stable");
        assert!(out.steps > 600);
    }

    /// The displacements and velocities of every snapshot a run of `text` takes, the run being
    /// asked to stop once `stop_at` steps are reported done.
    fn snapshot_states(text: &str, stop_at: u64) -> Vec<(u64, Vec<f64>)> {
        use crate::records::fields::{FieldSink, FieldSnapshot, FieldValues};
        struct Keep(Vec<(u64, Vec<f64>)>);
        impl FieldSink for Keep {
            fn snapshot(&mut self, s: FieldSnapshot) -> std::io::Result<()> {
                let mut all = Vec::new();
                for name in ["displacement", "velocity"] {
                    match s.bulk.point_array(name) {
                        Some(FieldValues::Vectors(v)) => all.extend(v.iter().flatten()),
                        other => panic!("{name}: {other:?}"),
                    }
                }
                self.0.push((s.step, all));
                Ok(())
            }
        }
        let scene = Scene::from_toml_str(text).unwrap();
        let mut keep = Keep(Vec::new());
        let stop = std::sync::atomic::AtomicBool::new(false);
        let mut progress = |done, _| {
            if done >= stop_at {
                stop.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        };
        let ended = super::run_with_fields(&scene, &mut progress, &stop, Some(&mut keep));
        assert_eq!(ended.is_ok(), stop_at == u64::MAX);
        keep.0
    }

    /// The tiny centre crack with its records every 10th step and a snapshot every 7th, and the
    /// same run with its records and snapshots at every step (whose steps are never fused).
    fn sparse_and_dense() -> (String, String) {
        let text = scene_text("tiny-fem-center-crack");
        let dt = Scene::from_toml_str(&text).unwrap().time_step();
        let with = |output: f64, snapshot: f64| {
            let text = text.replace("output_interval = 1e-5", &format!("output_interval = {output:e}"));
            format!("{text}\n[fem.paraview]\ninterval = {snapshot:e}\n")
        };
        (with(10.0 * dt, 7.0 * dt), with(dt, dt))
    }

    /// A snapshot between two samples shows the state of its step, as one on a sampled step does:
    /// the fused corrector-predictor of an unsampled step must not leave the bulk nodes a step
    /// ahead where a snapshot reads them. Every snapshot has the bits of the run sampled at every
    /// step.
    #[test]
    fn snapshots_between_samples_show_the_state_of_their_step() {
        let (sparse, dense) = sparse_and_dense();
        let (sparse, dense) = (
            snapshot_states(&sparse, u64::MAX),
            snapshot_states(&dense, u64::MAX),
        );
        assert!(sparse.len() > 10, "{} snapshots", sparse.len());
        for (step, fields) in &sparse {
            let same = dense
                .iter()
                .find(|(s, _)| s == step)
                .expect("the dense run snapshots every step");
            assert!(*fields == same.1, "snapshot of step {step} differs");
        }
    }

    /// A run stopped on request ends on the state of its last step: its last snapshot has the bits
    /// of the run sampled at every step, though the step it stops at is not a sampled one.
    #[test]
    fn a_stopped_run_ends_on_the_state_of_its_last_step() {
        let (sparse, dense) = sparse_and_dense();
        let stopped = snapshot_states(&sparse, 100);
        let (step, fields) = stopped.last().unwrap();
        assert!(
            *step > 100 && step % 10 != 0 && step % 7 != 0,
            "stopped at step {step}"
        );
        let dense = snapshot_states(&dense, u64::MAX);
        let same = dense.iter().find(|(s, _)| s == step).unwrap();
        assert!(*fields == same.1, "last snapshot, of step {step}, differs");
    }
}
