//! Thin CLI: `fem SCENE.toml [--out DIR]` runs the scene and writes the CSV records.

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let (mut scene_path, mut out_dir) = (None, None);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--out" => out_dir = Some(PathBuf::from(args.next().context("--out needs a directory")?)),
            "-h" | "--help" => {
                println!("usage: fem SCENE.toml [--out DIR]   (default DIR: out/<scene name>)");
                return Ok(());
            }
            _ if scene_path.is_none() => scene_path = Some(PathBuf::from(a)),
            _ => bail!("unexpected argument {a}"),
        }
    }
    let scene_path = scene_path.context("usage: fem SCENE.toml [--out DIR]")?;
    let text =
        std::fs::read_to_string(&scene_path).with_context(|| format!("reading {}", scene_path.display()))?;
    let scene =
        fem::Scene::from_toml_str(&text).with_context(|| format!("scene {}", scene_path.display()))?;
    let out_dir = out_dir.unwrap_or_else(|| PathBuf::from("out").join(&scene.name));
    let bar = ProgressBar::new(1);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps {elapsed_precise} eta {eta}")
            .context("progress style")?,
    );
    let started = std::time::Instant::now();
    let result = fem::run_with_progress(&scene, &mut |done, total| {
        bar.set_length(total);
        bar.set_position(done);
    });
    bar.finish();
    let (output, failure) = match result {
        Ok(o) => (o, None),
        Err(fem::RunError::Unstable {
            step,
            time_s,
            location,
            partial,
        }) => (
            *partial,
            Some(format!("unstable at step {step}, t = {time_s} s: {location}")),
        ),
        Err(e) => return Err(e.into()),
    };
    let files =
        fem::write_csv(&output, &out_dir).with_context(|| format!("writing {}", out_dir.display()))?;
    println!(
        "{} steps, dt = {:.4e} s, wall {:.1} s (cohesive {:.1} s, contact {:.1} s)",
        output.steps,
        output.time_step,
        started.elapsed().as_secs_f64(),
        output.cohesive_seconds,
        output.contact_seconds
    );
    for f in files {
        println!("wrote {}", f.display());
    }
    if let Some(msg) = failure {
        bail!(msg);
    }
    Ok(())
}
