//! Running one model: progress reporting, the run, its full output written to a folder, and an
//! unstable run kept with its partial output. Every study runs its models through here; the
//! harness reaches `fem` and `spectral` only through their `run_with_progress`, `write_csv` and
//! output records (docs/solver-api.md).

use crate::series::TipRow;
use crate::study::Study;
use anyhow::{Context, Result};
use preflight::RunEnded;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Progress reporting for long runs, and the request to stop them: the binary draws progress
/// bars and stops on Ctrl-C, tests stay silent.
pub trait Reporter: Sync {
    /// A run labelled `label` starts; returns its callback `(steps_done, total_steps)`.
    fn run_started(&self, label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_>;

    /// A study's runs have passed every check: `plan` says how many, how long and how big.
    fn planned(&self, _plan: &Plan) {}

    /// The flag that stops the runs at their next step (never raised by default).
    fn stop(&self) -> &AtomicBool {
        static NEVER: AtomicBool = AtomicBool::new(false);
        &NEVER
    }
}

/// A reporter that reports nothing.
pub struct Silent;

impl Reporter for Silent {
    fn run_started(&self, _label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_> {
        Box::new(|_, _| {})
    }
}

/// Everything about the runs of a study that can be checked before the first of them starts:
/// each run's steps and memory against the study's budget (with the run's label, the estimate
/// and the key to change) and the study's output folder (created, written to, and held against
/// any other run until the returned claim is dropped: keep it until the study's last file is
/// written). The spectral kernel fits are computed here too, and kept for the runs.
pub fn preflight(
    study: &Study,
    fem_runs: &[(&str, &fem::Scene)],
    spectral_runs: &[(&str, &spectral::Scene)],
    dir: &Path,
) -> Result<(Plan, preflight::paths::Claim)> {
    let mut problems = Vec::new();
    let mut estimates = Vec::new();
    for (label, scene) in fem_runs {
        estimates.push((*label, fem::estimate(scene)));
    }
    for (label, scene) in spectral_runs {
        match spectral::estimate(scene) {
            Ok(e) => estimates.push((*label, e)),
            Err(e) => problems.push(format!("{label}: {e}")),
        }
    }
    for (label, e) in &estimates {
        if let Err(e) = study.budget.check(e) {
            problems.push(format!("{label}: {e}"));
        }
    }
    if !problems.is_empty() {
        anyhow::bail!("{}", problems.join("\n"));
    }
    let claim = preflight::paths::claim(dir, "compare").map_err(|e| anyhow::anyhow!(e))?;
    if let Some(note) = claim.taken_over() {
        eprintln!("warning: {note}");
    }
    let plan = Plan {
        runs: estimates.len(),
        steps: estimates.iter().map(|(_, e)| e.steps).sum(),
        seconds: estimates.iter().map(|(_, e)| e.seconds).sum(),
        largest_bytes: estimates.iter().map(|(_, e)| e.bytes()).max().unwrap_or(0),
        longest_seconds: estimates.iter().map(|(_, e)| e.seconds).fold(0.0, f64::max),
        lanes: crate::concurrent::Lanes::new(1, rayon::current_num_threads(), Some(1)),
    };
    Ok((plan, claim))
}

/// Wall time of a run on one core over its time on two [-]: 1.45 for the FE centre crack at
/// paper resolution (11.3 s against 7.8 s), 1.06 for the spectral one (5.0 s against 4.7 s), when
/// it was set; the larger, so that side-by-side estimates err long (docs/performance.md). Later
/// code gains more from a second core (1.70 and 1.53 on a 2-core AMD EPYC on 2026-12-04), but the
/// runs' own estimates err long by more than that (there `compare` was estimated at about 18 s and
/// took 14.0 s), so the factor was left as it was.
pub const ONE_CORE_SLOWDOWN: f64 = 1.45;

/// The runs of a study, once checked.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plan {
    /// Number of runs.
    pub runs: usize,
    /// Time steps of all runs [-].
    pub steps: u64,
    /// Expected wall time of all runs on 2 cores [s].
    pub seconds: f64,
    /// Memory of the largest run [B].
    pub largest_bytes: u64,
    /// Expected wall time of the longest run on 2 cores [s].
    pub longest_seconds: f64,
    /// How the runs share the cores.
    pub lanes: crate::concurrent::Lanes,
}

impl Plan {
    /// The plan with the runs shared out as `lanes` says: memory is then that of the largest
    /// runs going at once, and on 2 cores two runs on one core each take
    /// [`ONE_CORE_SLOWDOWN`] times their 2-core time, side by side, in rounds.
    pub fn with_lanes(self, lanes: crate::concurrent::Lanes) -> Plan {
        let n = lanes.lanes.min(self.runs.max(1));
        // the runs go in rounds of n: ⌈runs/n⌉ rounds of one run's one-core time each
        let rounds = self.runs.div_ceil(n.max(1)) as f64;
        let mean = self.seconds / self.runs.max(1) as f64;
        Plan {
            largest_bytes: self.largest_bytes * n as u64,
            seconds: if n > 1 {
                rounds * mean * ONE_CORE_SLOWDOWN
            } else {
                self.seconds
            },
            lanes,
            ..self
        }
    }
}

impl std::fmt::Display for Plan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} runs ({}), {} steps, at most {} of memory, about {} on 2 cores",
            self.runs,
            self.lanes,
            self.steps,
            preflight::budget::human(self.largest_bytes),
            preflight::budget::duration(self.seconds)
        )
    }
}

/// A run that ended, as a study reads it: its output, its wall time, and why it stopped before T
/// if it did.
#[derive(Debug, Clone)]
pub struct Finished<O> {
    /// The output: complete, or up to the failure.
    pub out: O,
    /// Wall time of the run [s].
    pub wall_s: f64,
    /// Why the run stopped before T, with when and where (`None`: it reached T).
    pub failure: Option<String>,
    /// What the run did that its user should know (e.g. contacts lost to the detection distance).
    pub warnings: Vec<String>,
}

impl<O> Finished<O> {
    /// The output of a run that reached T; an error naming the failure otherwise.
    pub fn completed(self) -> Result<O> {
        match self.failure {
            None => Ok(self.out),
            Some(f) => Err(anyhow::anyhow!(f)),
        }
    }
}

/// Prints the runs' warnings on stderr, one a line.
pub fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// When a run's full output is written to its folder.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keep {
    /// Always (the studies that show a run's fields).
    Everything,
    /// Only when the run goes unstable, to show where (the studies that keep a summary per run).
    OnFailure,
}

impl Keep {
    fn writes(self, failed: bool) -> bool {
        self == Keep::Everything || failed
    }
}

/// What an unstable run reports: when, where, and where its partial output went.
fn unstable(label: &str, dir: &Path, step: u64, time_s: f64, location: &str) -> String {
    format!(
        "{label}: unstable at step {step}, t = {time_s:e} s ({location}); its output up to there is in {}",
        dir.display()
    )
}

/// A run stopped on request ends its study: when, and where its output up to there went.
fn interrupted(label: &str, dir: &Path, step: u64, time_s: f64) -> anyhow::Error {
    anyhow::anyhow!(
        "{label}: stopped on request at step {step}, t = {time_s:e} s; its output up to there is in {}",
        dir.display()
    )
}

/// A model run: the scene, its label in progress and messages, the folder of its full output
/// and when that output is written.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a, S> {
    /// The validated scene.
    pub scene: &'a S,
    /// Label of the run.
    pub label: &'a str,
    /// Folder of its full output.
    pub dir: &'a Path,
    /// When the full output is written.
    pub keep: Keep,
}

/// What the runner needs of a model: run a scene, write its output, say what the user should
/// know about a finished run.
pub trait Model: Sync {
    /// The run's records.
    type Output;

    /// Runs the scene with progress reports and the stop flag; the error when it could not start.
    fn run_scene(
        &self,
        progress: &mut dyn FnMut(u64, u64),
        stop: &AtomicBool,
    ) -> Result<RunEnded<Self::Output>>;

    /// Writes every record of `out` as CSV into `dir`.
    fn write(out: &Self::Output, dir: &Path) -> std::io::Result<Vec<std::path::PathBuf>>;

    /// Warnings about a finished run (e.g. contacts lost to the detection distance).
    fn warnings(&self, _label: &str, _out: &Self::Output) -> Vec<String> {
        Vec::new()
    }
}

impl Model for fem::Scene {
    type Output = fem::RunOutput;

    fn run_scene(
        &self,
        progress: &mut dyn FnMut(u64, u64),
        stop: &AtomicBool,
    ) -> Result<RunEnded<fem::RunOutput>> {
        Ok(fem::ended(fem::run_with_progress(self, progress, stop))?)
    }

    fn write(out: &fem::RunOutput, dir: &Path) -> std::io::Result<Vec<std::path::PathBuf>> {
        // a run's subfolder of the study's folder: never a link to elsewhere
        preflight::save::not_a_link(dir)?;
        // the folder holds this run's files only (an earlier run's would stand beside them)
        fem::output::clear_previous(dir)?;
        fem::write_csv(out, dir)
    }

    fn warnings(&self, label: &str, out: &fem::RunOutput) -> Vec<String> {
        let dropped = out.record().dropped_contacts;
        if dropped == 0 {
            return Vec::new();
        }
        vec![format!(
            "{label}: {dropped} contacts lost because a penetration exceeded the detection distance \
             fem.max_gap = {} m; raise it or stiffen fem.eps_n",
            self.fem.max_gap
        )]
    }
}

impl Model for spectral::Scene {
    type Output = spectral::RunOutput;

    fn run_scene(
        &self,
        progress: &mut dyn FnMut(u64, u64),
        stop: &AtomicBool,
    ) -> Result<RunEnded<spectral::RunOutput>> {
        Ok(spectral::ended(spectral::run_with_progress(
            self, progress, stop,
        ))?)
    }

    fn write(out: &spectral::RunOutput, dir: &Path) -> std::io::Result<Vec<std::path::PathBuf>> {
        preflight::save::not_a_link(dir)?;
        spectral::output::clear_previous(dir)?;
        spectral::write_csv(out, dir)
    }
}

/// Runs a job of either model. An unstable run ends with `failure` saying when and where, and its
/// partial output written; a run stopped on request writes its partial output and stops the
/// study with an error saying where it went; other errors stop the study.
pub fn run<M: Model>(job: Job<M>, rep: &dyn Reporter) -> Result<Finished<M::Output>> {
    let Job {
        scene,
        label,
        dir,
        keep,
    } = job;
    let mut progress = rep.run_started(label);
    let start = Instant::now();
    let ended = scene
        .run_scene(&mut *progress, rep.stop())
        .context(label.to_string())?;
    let wall_s = start.elapsed().as_secs_f64();
    let write =
        |out: &M::Output| M::write(out, dir).with_context(|| format!("{label}: writing {}", dir.display()));
    let failure = match &ended {
        RunEnded::Finished(_) => None,
        RunEnded::Unstable {
            step,
            time_s,
            location,
            ..
        } => Some(unstable(label, dir, *step, *time_s, location)),
        RunEnded::Interrupted {
            step,
            time_s,
            partial,
        } => {
            write(partial)?;
            return Err(interrupted(label, dir, *step, *time_s));
        }
        // the harness takes no field snapshots; were one not written, the study stops as on
        // any other error of the model
        RunEnded::OutputFailed {
            step,
            time_s,
            message,
            ..
        } => {
            return Err(anyhow::anyhow!(
                "output at step {step}, t = {time_s} s not written: {message}"
            ))
            .context(label.to_string());
        }
    };
    let out = ended.into_output();
    if keep.writes(failure.is_some()) {
        write(&out)?;
    }
    let warnings = scene.warnings(label, &out);
    Ok(Finished {
        out,
        wall_s,
        failure,
        warnings,
    })
}

/// Runs FE scenes side by side as `lanes` says, each `(scene, label, folder)` kept as `keep`
/// says; their results in the order given (an error stops the runs not yet started).
pub fn run_fems(
    runs: &[(&fem::Scene, String, std::path::PathBuf)],
    keep: Keep,
    lanes: crate::concurrent::Lanes,
    rep: &dyn Reporter,
) -> Result<Vec<Finished<fem::RunOutput>>> {
    let tasks: Vec<crate::concurrent::Task<Finished<fem::RunOutput>>> = runs
        .iter()
        .map(|(scene, label, dir)| {
            Box::new(move || {
                let job = Job {
                    scene: *scene,
                    label,
                    dir,
                    keep,
                };
                run_fem(job, rep)
            }) as crate::concurrent::Task<Finished<fem::RunOutput>>
        })
        .collect();
    crate::concurrent::all_ok(crate::concurrent::run_all(tasks, lanes)?)
}

/// Runs an FE job ([`run`]).
pub fn run_fem(job: Job<fem::Scene>, rep: &dyn Reporter) -> Result<Finished<fem::RunOutput>> {
    run(job, rep)
}

/// Runs a spectral job ([`run`]).
pub fn run_spectral(job: Job<spectral::Scene>, rep: &dyn Reporter) -> Result<Finished<spectral::RunOutput>> {
    run(job, rep)
}

/// A model's tip records as harness rows (both crates' `TipRecord`s have the same fields).
macro_rules! tip_rows {
    ($records:expr) => {
        $records
            .iter()
            .map(|r| TipRow {
                t: r.t,
                tip_right: r.tip_right,
                tip_left: r.tip_left,
                cz_tip_right: r.cz_tip_right,
                cz_tip_left: r.cz_tip_left,
            })
            .collect()
    };
}

/// Tip rows of an FE run.
pub fn fem_tips(out: &fem::RunOutput) -> Vec<TipRow> {
    tip_rows!(out.tips)
}

/// Tip rows of a spectral run.
pub fn spectral_tips(out: &spectral::RunOutput) -> Vec<TipRow> {
    tip_rows!(out.tips)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::concurrent::Lanes;

    /// Runs side by side: memory adds up over the runs at once, and the time goes in rounds of
    /// one run's one-core time (3 runs on 2 lanes: 2 rounds).
    #[test]
    fn a_plan_side_by_side_prices_memory_and_rounds() {
        let plan = Plan {
            runs: 3,
            steps: 300,
            seconds: 30.0,
            largest_bytes: 100,
            longest_seconds: 10.0,
            lanes: Lanes::new(3, 2, Some(1)),
        };
        let side = plan.with_lanes(Lanes::new(3, 2, None));
        assert_eq!(side.largest_bytes, 200);
        assert!((side.seconds - 2.0 * 10.0 * ONE_CORE_SLOWDOWN).abs() < 1e-12);
        let one = plan.with_lanes(Lanes::new(3, 2, Some(1)));
        assert_eq!((one.largest_bytes, one.seconds), (100, 30.0));
    }
}
