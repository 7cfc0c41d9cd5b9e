//! `spectral SCENE.toml [--out DIR] [--checkpoint-every SECONDS] [--resume DIR]`: checks
//! everything first (the scene, the kernel fit, the budgets, the output folder, the checkpoint to
//! resume), then runs the scene, writes CSV and prints where the outputs went.

use std::path::{Path, PathBuf};

use anyhow::{Context, anyhow};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use preflight::RunEnded;
use preflight::command::{Prepared, StoppedEarly};

/// Runs one scene with the spectral boundary-integral model of an interface between identical
/// half-spaces and writes its records as CSV (tips, contact means, space-time fields). A run that
/// goes unstable, or is stopped with Ctrl-C, keeps what it computed and exits non-zero.
#[derive(Debug, Parser)]
#[command(name = "spectral", version)]
struct Cli {
    /// Scene file (TOML; see docs/scenes.md for every key).
    scene: PathBuf,
    #[command(flatten)]
    run: preflight::options::RunOptions,
}

/// Prints an error with its causes on one line and exits 1: never a backtrace, whatever
/// `RUST_BACKTRACE` says (it would bury the one line that says what to change).
fn main() -> std::process::ExitCode {
    preflight::command::exit(run())
}

/// Checks everything ([`preflight::command::prepare`]), runs the scene with a progress bar and
/// writes what it computed; a run that stopped before T ends in an error saying why and where its
/// output went.
fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    let scene_path = &cli.scene;
    let prepared = preflight::command::prepare(
        "spectral",
        scene_path,
        &cli.run,
        preflight::command::ModelSteps {
            read: |text: &str, _: &Path| spectral::Scene::from_toml_str(text),
            inputs: |_: &spectral::Scene| Vec::new(),
            estimate: spectral::estimate,
            clear_previous: spectral::output::clear_previous,
        },
    )?;
    let stop = preflight::stop::on_signal().map_err(|e| anyhow!(e))?;
    for w in prepared.scene.warnings() {
        eprintln!("warning: {w}");
    }
    prepared.announce(scene_path, prepared.scene.time_step());
    let Prepared {
        scene,
        estimate,
        out_dir,
        // the folder stays locked against other runs until this function returns, output written
        claim: _held,
        resumed,
        mut checkpoints,
        ..
    } = prepared;
    let bar = ProgressBar::new(estimate.steps);
    bar.set_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}",
    )?);
    let start = std::time::Instant::now();
    let result = spectral::run_checkpointed(
        &scene,
        &mut |done, total| {
            bar.set_length(total);
            bar.set_position(done);
        },
        stop,
        checkpoints.as_mut(),
        resumed.as_ref(),
    );
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    let ended = spectral::ended(result)?;
    let why = why(&ended);
    let finished = matches!(ended, RunEnded::Finished(_));
    let from = resumed.as_ref().map_or(0, |r| r.header.step);
    report(&ended.into_output(), &out_dir, wall, from)?;
    if let Some(w) = &checkpoints {
        println!("{}", w.summary());
    }
    if finished {
        // nothing left to resume; removed once the output is written, so that a failed write
        // can still be redone from the checkpoint
        match &checkpoints {
            Some(w) => w.remove()?,
            None => {
                preflight::paths::remove_files([out_dir.join(preflight::checkpoint::FILE)])
                    .with_context(|| format!("removing the checkpoint in {}", out_dir.display()))?;
            }
        }
    }
    match why {
        Some(why) => Err(StoppedEarly { why, out_dir }.into()),
        None => Ok(()),
    }
}

/// Why a run stopped before T, as this command says it (`None`: it reached T).
fn why(ended: &RunEnded<spectral::RunOutput>) -> Option<String> {
    match ended {
        RunEnded::Finished(_) => None,
        RunEnded::Unstable {
            step,
            time_s,
            location,
            ..
        } => Some(format!(
            "unstable at step {step} (t = {time_s:e} s) at {location}"
        )),
        RunEnded::Interrupted { step, time_s, .. } => {
            Some(format!("stopped on request at step {step} (t = {time_s:e} s)"))
        }
        RunEnded::OutputFailed {
            step,
            time_s,
            message,
            ..
        } => Some(format!(
            "stopped at step {step} (t = {time_s:e} s): an output could not be written: {message}"
        )),
    }
}

/// Writes the run's records (complete or partial) and says what went where: the run's
/// statistics over `wall` seconds, spent on the steps after the first `from` (those of the
/// checkpoint a resumed run started from), the time profile of those steps and the work of one
/// step with the rates it achieved, then one file a line.
fn report(output: &spectral::RunOutput, out_dir: &Path, wall: f64, from: u64) -> anyhow::Result<()> {
    let files =
        spectral::write_csv(output, out_dir).with_context(|| format!("writing {}", out_dir.display()))?;
    let s = output.stats;
    let computed = s.steps.saturating_sub(from);
    println!(
        "{} steps, N = {}, {:.2} s wall ({:.3} ms/step), {:.1} MB history streamed per step, {} exp terms",
        s.steps,
        s.grid_points,
        wall,
        1e3 * wall / computed.max(1) as f64,
        s.bytes_per_step as f64 / 1e6,
        s.exp_terms
    );
    let p = &output.profile;
    let resumed = if from > 0 {
        format!(" (steps {} to {}, resumed)", from + 1, s.steps)
    } else {
        String::new()
    };
    // the placement's steps on one thread: its timed trials, and the chunks a trial chose it for
    let one = match p.one_thread_steps {
        0 => String::new(),
        n => format!(", {n} of them on one (its timed trials, and any chunks run there as the faster)"),
    };
    println!(
        "{computed} steps{resumed} on {} thread(s){one}; where the time went:\n{}",
        rayon::current_num_threads(),
        spectral::profile::table(p, computed, s.grid_points)
    );
    println!(
        "the clock: {} laps at {:.0} ns = {:.4} s ({:.2} % of the laps' time)",
        p.total_laps(),
        1e9 * p.lap_cost_s,
        p.clock_cost(),
        100.0 * p.clock_cost() / p.total().max(f64::MIN_POSITIVE)
    );
    let w = output.work.total();
    println!(
        "work per step (as the model counts it): {:.2} MB moved ({:.2} MB read, {:.2} MB written), \
         {:.2} Mflop, {:.2} flop/B; achieved per phase:\n{}",
        w.bytes() / 1e6,
        w.read / 1e6,
        w.written / 1e6,
        w.flops / 1e6,
        w.intensity(),
        spectral::profile::work_table(&output.work, p, computed)
    );
    for f in files {
        println!("{}", f.display());
    }
    Ok(())
}
