//! `spectral SCENE.toml [--out DIR]`: checks everything first (the scene, the kernel fit, the
//! budgets, the output folder), then runs the scene, writes CSV and prints where the outputs went.

use std::path::PathBuf;

use anyhow::{Context, anyhow};
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};

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
    match run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run() -> anyhow::Result<()> {
    let cli = Cli::parse();
    let scene_path = &cli.scene;
    let text =
        std::fs::read_to_string(scene_path).with_context(|| format!("reading {}", scene_path.display()))?;
    let scene =
        spectral::Scene::from_toml_str(&text).with_context(|| format!("scene {}", scene_path.display()))?;
    let out_dir = cli.run.out_dir("spectral", scene_path).map_err(|e| anyhow!(e))?;
    let estimate = spectral::estimate(&scene).with_context(|| format!("scene {}", scene_path.display()))?;
    cli.run
        .budget
        .budget()
        .check(&estimate)
        .map_err(|e| anyhow!("scene {}: {e}", scene_path.display()))?;
    preflight::paths::claim(&out_dir, "spectral").map_err(|e| anyhow!(e))?;
    // one run per folder: an earlier run's files would stand beside this one's
    let removed = spectral::output::clear_previous(&out_dir).with_context(|| {
        format!(
            "output folder {}: removing the previous run's files",
            out_dir.display()
        )
    })?;
    let stop = preflight::stop::on_signal().map_err(|e| anyhow!(e))?;
    for w in scene.warnings() {
        eprintln!("warning: {w}");
    }
    println!(
        "{}: {} (dt = {:.4e} s); output in {}{}",
        scene_path.display(),
        estimate.summary(),
        scene.time_step(),
        out_dir.display(),
        preflight::paths::removed_note(removed)
    );
    let bar = ProgressBar::new(estimate.steps);
    bar.set_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}",
    )?);
    let start = std::time::Instant::now();
    let result = spectral::run_with_progress(
        &scene,
        &mut |done, total| {
            bar.set_length(total);
            bar.set_position(done);
        },
        stop,
    );
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    let (output, failure) = match result {
        Ok(o) => (o, None),
        Err(spectral::RunError::Unstable {
            partial,
            step,
            time_s,
            location,
        }) => (
            *partial,
            Some(format!(
                "unstable at step {step} (t = {time_s:e} s) at {location}"
            )),
        ),
        Err(spectral::RunError::Interrupted {
            partial,
            step,
            time_s,
        }) => (
            *partial,
            Some(format!("stopped on request at step {step} (t = {time_s:e} s)")),
        ),
        Err(e) => return Err(e.into()),
    };
    let files =
        spectral::write_csv(&output, &out_dir).with_context(|| format!("writing {}", out_dir.display()))?;
    let s = output.stats;
    println!(
        "{} steps, N = {}, {:.2} s wall ({:.3} ms/step), {:.1} MB history streamed per step, {} exp terms",
        s.steps,
        s.grid_points,
        wall,
        1e3 * wall / s.steps.max(1) as f64,
        s.bytes_per_step as f64 / 1e6,
        s.exp_terms
    );
    for f in files {
        println!("{}", f.display());
    }
    if let Some(msg) = failure {
        anyhow::bail!("{msg}; the output up to there is in {}", out_dir.display());
    }
    Ok(())
}
