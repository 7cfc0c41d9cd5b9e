//! `spectral SCENE.toml [--out DIR]`: runs a scene, writes CSV, prints where the outputs went.

use std::path::PathBuf;

use anyhow::Context;
use clap::Parser;
use indicatif::{ProgressBar, ProgressStyle};

/// Runs one scene with the spectral boundary-integral model of an interface between identical
/// half-spaces and writes its records as CSV (tips, contact means, space-time fields). A run that
/// goes unstable keeps what it computed and exits non-zero.
#[derive(Debug, Parser)]
#[command(name = "spectral", version)]
struct Cli {
    /// Scene file (TOML; see spectral/README.md for every key).
    scene: PathBuf,
    /// Output folder (default: out/spectral-<scene file name>/).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    let (scene_path, out_dir) = (cli.scene, cli.out);
    let text =
        std::fs::read_to_string(&scene_path).with_context(|| format!("reading {}", scene_path.display()))?;
    let scene =
        spectral::Scene::from_toml_str(&text).with_context(|| format!("scene {}", scene_path.display()))?;
    let stem = scene_path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    let out_dir = out_dir.unwrap_or_else(|| PathBuf::from("out").join(format!("spectral-{stem}")));
    let bar = ProgressBar::new(1);
    bar.set_style(ProgressStyle::with_template(
        "{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}",
    )?);
    let start = std::time::Instant::now();
    let result = spectral::run_with_progress(&scene, &mut |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish();
    let wall = start.elapsed().as_secs_f64();
    let output = match result {
        Ok(o) => o,
        Err(spectral::RunError::Unstable {
            partial,
            step,
            time_s,
            location,
        }) => {
            let files = spectral::write_csv(&partial, &out_dir)?;
            eprintln!("partial output written to {}", out_dir.display());
            drop(files);
            anyhow::bail!("unstable at step {step} (t = {time_s:e} s) at {location}");
        }
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
        1e3 * wall / s.steps as f64,
        s.bytes_per_step as f64 / 1e6,
        s.exp_terms
    );
    for f in files {
        println!("{}", f.display());
    }
    Ok(())
}
