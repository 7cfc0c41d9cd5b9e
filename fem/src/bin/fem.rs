//! Thin command line: `fem SCENE.toml [--out DIR]` checks everything first (the scene, the
//! budgets, the output folder), then runs the scene and writes the CSV records (and the ParaView
//! snapshots when the scene asks for them).

use anyhow::{Context, anyhow};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};
use preflight::RunEnded;
use preflight::command::{Prepared, StoppedEarly};
use std::convert::Infallible;
use std::path::{Path, PathBuf};

/// Runs one scene with the hybrid (or standard) cohesive-contact FE model and writes its records
/// as CSV (tips, interface, faces, contact, energy, arrivals, probes and the diagnostics the
/// scene declares), and ParaView field snapshots with `[fem.paraview]`. A run that goes
/// unstable, or is stopped with Ctrl-C, keeps what it computed and exits non-zero.
#[derive(Debug, Parser)]
#[command(name = "fem", version)]
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
    let prepared = preflight::command::prepare(
        "fem",
        &cli.scene,
        &cli.run,
        preflight::command::ModelSteps {
            read: fem::Scene::from_toml_str_in,
            inputs: |scene: &fem::Scene| scene.fem.mesh.iter().map(|m| m.file.clone()).collect(),
            estimate: |scene: &fem::Scene| Ok::<_, Infallible>(fem::estimate(scene)),
            clear_previous: fem::output::clear_previous,
        },
    )?;
    let mut fields = match prepared.scene.fem.paraview {
        Some(_) => Some(
            fem::ParaviewWriter::new(&prepared.out_dir, prepared.estimate.steps)
                .with_context(|| format!("output folder {}: fields/", prepared.out_dir.display()))?,
        ),
        None => None,
    };
    let stop = preflight::stop::on_signal().map_err(|e| anyhow!(e))?;
    for w in prepared.scene.warnings() {
        eprintln!("warning: {w}");
    }
    prepared.announce(&cli.scene, prepared.scene.time_step());
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
    announce_fields(&scene, &out_dir);
    let bar = ProgressBar::new(estimate.steps);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}")
            .context("progress style")?,
    );
    let started = std::time::Instant::now();
    let result = fem::run_checkpointed(
        &scene,
        &mut |done, total| {
            bar.set_length(total);
            bar.set_position(done);
        },
        stop,
        fields.as_mut().map(|w| w as &mut dyn fem::FieldSink),
        checkpoints.as_mut(),
        resumed.as_ref(),
    );
    bar.finish();
    let ended = fem::ended(result)?;
    let why = why(&ended);
    report(&scene, &ended.into_output(), &out_dir, started, fields.as_ref())?;
    if let Some(w) = &checkpoints {
        println!("{}", w.summary());
        // only once the files are written: a run whose files could not be written still resumes
        if why.is_none() {
            w.remove()
                .context("removing the checkpoint of the finished run")?;
        }
    }
    match why {
        Some(why) => Err(StoppedEarly { why, out_dir }.into()),
        None => Ok(()),
    }
}

/// The line before the run on the ParaView snapshots to come (none without `[fem.paraview]`).
fn announce_fields(scene: &fem::Scene, out_dir: &Path) {
    if let (Some(p), Some((count, each))) = (scene.fem.paraview, fem::solver::estimate::field_files(scene)) {
        println!(
            "ParaView: {count} snapshots, one every {} steps, about {} each ({} in all), in {}",
            p.every(scene.time_step()),
            preflight::budget::human(each),
            preflight::budget::human(each.saturating_mul(count)),
            out_dir.join("fields.pvd").display()
        );
    }
}

/// Why a run stopped before T, as this command says it (`None`: it reached T).
fn why(ended: &RunEnded<fem::RunOutput>) -> Option<String> {
    match ended {
        RunEnded::Finished(_) => None,
        RunEnded::Unstable {
            step,
            time_s,
            location,
            ..
        } => Some(format!("unstable at step {step}, t = {time_s} s: {location}")),
        RunEnded::Interrupted { step, time_s, .. } => {
            Some(format!("stopped on request at step {step}, t = {time_s} s"))
        }
        RunEnded::OutputFailed {
            step,
            time_s,
            message,
            ..
        } => Some(format!(
            "stopped at step {step}, t = {time_s} s: an output could not be written: {message}"
        )),
    }
}

/// Writes the run's records (complete or partial) and says what went where: the time profile of
/// the steps this process computed (after its checkpoint, for a resumed run), the files, the
/// ParaView collection, the cracks, and contacts lost to the detection distance.
fn report(
    scene: &fem::Scene,
    output: &fem::RunOutput,
    out_dir: &Path,
    started: std::time::Instant,
    fields: Option<&fem::ParaviewWriter>,
) -> anyhow::Result<()> {
    let files = fem::write_csv(output, out_dir).with_context(|| format!("writing {}", out_dir.display()))?;
    let from = output.resumed_from;
    let computed = output.steps.saturating_sub(from);
    let resumed = if from > 0 {
        format!(" (steps {} to {}, resumed)", from + 1, output.steps)
    } else {
        String::new()
    };
    println!(
        "{computed} steps{resumed}, dt = {:.4e} s, wall {:.1} s on {} thread(s); where the time went:\n{}",
        output.time_step,
        started.elapsed().as_secs_f64(),
        rayon::current_num_threads(),
        fem::profile::table(&output.profile, computed, output.elements)
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    if let Some(w) = fields {
        let pvd = w
            .finish()
            .with_context(|| format!("writing {}", out_dir.join("fields.pvd").display()))?;
        println!(
            "wrote {} ({} snapshots in {})",
            pvd.display(),
            w.snapshots(),
            out_dir.join("fields").display()
        );
    }
    if let Some(line) = crack_summary(&output.cracks, &output.crack_tips) {
        println!("{line}");
    }
    let record = output.record();
    if record.dropped_contacts > 0 {
        eprintln!(
            "warning: {} contacts were lost because a penetration exceeded the detection distance \
             fem.max_gap = {} m (per step in contact.csv); raise fem.max_gap or stiffen fem.eps_n",
            record.dropped_contacts, scene.fem.max_gap
        );
    }
    Ok(())
}

/// The last sample of cracks.csv and crack_tips.csv in one line: broken and cohesive lengths over
/// all chains, and the number of separate cracks.
fn crack_summary(cracks: &[fem::CrackRecord], tips: &[fem::CrackTipRecord]) -> Option<String> {
    let t = cracks.last()?.t;
    let last: Vec<_> = cracks.iter().filter(|r| r.t == t).collect();
    let (broken, cohesive) = last.iter().fold((0.0, 0.0), |(b, c), r| {
        (b + r.broken_length, c + r.cohesive_length)
    });
    let cracked = last.iter().filter(|r| r.broken_length > 0.0).count();
    let separate = tips.iter().filter(|r| r.t == t && !r.tip_start.is_nan()).count();
    Some(format!(
        "at t = {t:.6} s: {broken:.6} m broken of {cohesive:.6} m of cohesive interface, on {cracked} of {} chain(s) \
         (cracks.csv); {separate} separate crack(s), pre-cracks included, their tips in crack_tips.csv",
        last.len()
    ))
}
