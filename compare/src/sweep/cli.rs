//! The sweep's command line: runs it here (each point a child process), writes it out as jobs to
//! run elsewhere (`--emit`), reads their results back (`--collect`), and runs one point (the
//! hidden `sweep-point` that the children and the emitted jobs run).

use super::{Model, Point, scale_out};
use crate::runner::Reporter;
use crate::study::Study;
use anyhow::{Context, Result, anyhow};
use indicatif::{ProgressBar, ProgressStyle};
use preflight::Budget;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// No progress bars (a sweep point's parent draws its own), but stops on Ctrl-C.
struct Quiet(&'static AtomicBool);

impl Reporter for Quiet {
    fn run_started(&self, _label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_> {
        Box::new(|_, _| {})
    }

    fn stop(&self) -> &AtomicBool {
        self.0
    }
}

/// One sweep point in this process. With `--result` every error after the command line was read
/// (the scene, the budget, the run) is recorded in `<result>.failed` too, so that `--collect`
/// can say why the point failed; the command exits non-zero either way.
///
/// `scene`: the scene file; `out`: `--out` (default `out/<scene name>-sweep`); `budget`: each
/// run's budget.
pub fn point(
    scene: &Path,
    out: Option<&Path>,
    budget: Budget,
    model: Model,
    size: f64,
    result: Option<&Path>,
) -> Result<bool> {
    if let Some(r) = result {
        scale_out::prepare_result(r)?;
    }
    let run = || -> Result<Point> {
        let mut study = Study::load(scene)?;
        study.budget = budget;
        let dir = match out {
            Some(dir) => preflight::paths::explicit(dir)
                .map_err(|e| anyhow!(e))?
                .to_path_buf(),
            None => {
                PathBuf::from("out").join(format!("{}-sweep", preflight::paths::folder_name(&study.stem)))
            }
        };
        let stop = preflight::stop::on_signal().map_err(|e| anyhow!(e))?;
        super::run_point(&study, model, size, &dir, &Quiet(stop))
    };
    match (run(), result) {
        (Ok(p), None) => super::print_point(&p)?,
        (Ok(p), Some(r)) => {
            scale_out::write_result(r, &p)?;
            println!("wrote {}", r.display());
        }
        (Err(e), Some(r)) => {
            if let Err(w) = scale_out::write_failure(r, &format!("{e:#}")) {
                return Err(e.context(format!("(and recording the failure: {w:#})")));
            }
            return Err(e);
        }
        (Err(e), None) => return Err(e),
    }
    Ok(true)
}

/// The sweep written out as jobs (`sweep --emit DIR`), after every check the sweep makes.
pub fn emit(study: &Study, text: &str, scene: &Path, sizes: &[f64], dir: &Path) -> Result<bool> {
    let points = super::plan(study, &super::sizes(sizes)?)?;
    let exe = std::env::current_exe().context("locating the compare executable")?;
    let target = scale_out::check(dir, &exe)?;
    // claimed for `compare` (`--collect` writes its results into the same folder), and held
    // until the jobs are written; the jobs themselves write only their own files in it
    let (plan, _held) = super::preflight(study, &points, &target.dir)?;
    println!("{plan}");
    let files = scale_out::emit(&target, study, text, scene, &points, &plan)?;
    let d = target.dir.display();
    let jobs = target.dir.join(scale_out::JOBS);
    let jobs = jobs.display();
    println!(
        "
wrote {} files to {d}: a scene per point in {}/, {}, {} and {}",
        files.len(),
        scale_out::SCENES,
        scale_out::JOBS,
        scale_out::SBATCH,
        scale_out::MANIFEST
    );
    println!(
        "run the {} points (each writes {d}/{}/<model>_<h>mm.csv) with one of:",
        points.len(),
        scale_out::POINTS
    );
    let ways = [
        (
            format!("xargs -P 2 -I{{}} sh -c {{}} < {jobs}"),
            "here, two at a time",
        ),
        (
            format!("parallel < {jobs}"),
            "GNU parallel (--sshlogin for other machines)",
        ),
        (
            format!("sbatch {d}/{}", scale_out::SBATCH),
            "Slurm, one array task per point",
        ),
    ];
    let width = ways.iter().map(|(c, _)| c.len()).max().unwrap_or(0);
    for (command, what) in ways {
        println!("  {command:<width$}  # {what}");
    }
    println!("then: {} sweep --collect {d}", exe.display());
    Ok(true)
}

/// The results of an emitted sweep (`sweep --collect DIR`), written as the sweep writes them.
pub fn collect(dir: &Path, out: Option<&Path>) -> Result<bool> {
    let out = match out {
        Some(o) => preflight::paths::explicit(o).map_err(|e| anyhow!(e))?,
        None => dir,
    };
    let (manifest, measured) = scale_out::collect(dir)?;
    let _held = preflight::paths::claim(out, "compare").map_err(|e| anyhow!(e))?;
    finish(&measured, manifest.duration, out)
}

/// The sweep run here (`sweep`): each point in its own child process, one after the other, with
/// a progress bar over the points; then the table, `sweep.csv` and the figure ([`finish`]).
///
/// `stop` (Ctrl-C, SIGTERM) is forwarded to the point running: it writes its output up to there,
/// and the sweep ends in an error naming it.
pub fn run(study: &Study, scene: &Path, sizes: &[f64], dir: &Path, stop: &AtomicBool) -> Result<bool> {
    let points = super::plan(study, &super::sizes(sizes)?)?;
    // held until sweep.csv is written; the children write their own files in it, unlocked
    let (plan, _held) = super::preflight(study, &points, dir)?;
    println!("{plan}");
    let exe = std::env::current_exe().context("locating the compare executable")?;
    let bar = ProgressBar::new(points.len() as u64).with_style(
        ProgressStyle::with_template("sweep [{bar:40}] {pos}/{len} points ({elapsed}) {msg}")
            .expect("invariant: the template is valid"),
    );
    let measured = super::run_children(&exe, scene, dir, study.budget, &points, stop, &mut |p| {
        bar.set_message(format!(
            "{:?} h = {:.2e} m: {:.1} s",
            p.model, p.spacing, p.wall_s
        ));
        bar.inc(1);
    })?;
    bar.finish();
    finish(&measured, study.fem.duration(), dir)
}

/// Errors against the finest point of each model, the table, `sweep.csv` and the figure.
pub fn finish(measured: &[Point], duration: f64, dir: &Path) -> Result<bool> {
    let rows = super::with_errors(measured, duration);
    println!(
        "\n{:<9} {:>10} {:>10} {:>9} {:>9} {:>9} {:>11} {:>9}",
        "model", "spacing_m", "dt_s", "wall_s", "peak_MiB", "onset_s", "onsetErr/T", "speedErr"
    );
    for r in &rows {
        let line = format!(
            "{:<9} {:>10.3e} {:>10.3e} {:>9.1} {:>9.0} {:>9.5} {:>11.4} {:>9.4} {}",
            r.model.tag(),
            r.spacing,
            r.time_step,
            r.wall_s,
            r.peak_memory_bytes / 1048576.0,
            r.onset,
            r.onset_error_over_t,
            r.speed_error_rel,
            r.note
        );
        println!("{}", line.trim_end());
    }
    let files = super::write_results(dir, &rows)?;
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    println!("\nwrote {}", names.join(", "));
    Ok(true)
}
