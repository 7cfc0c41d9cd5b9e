//! `cargo run --release -p compare`: FE versus spectral on the centre-crack scene.

use anyhow::{Context, Result, bail};
use compare::gate::{Reporter, run_gate};
use compare::metrics::Verdict;
use compare::sweep::{self, Model};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

const HELP: &str = "\
compare — run the FE and spectral models on one scene and check that they agree

USAGE:
    cargo run --release -p compare [-- OPTIONS]           FE vs spectral gate
    cargo run --release -p compare -- sweep [OPTIONS]     speed/accuracy sweep
    cargo run --release -p compare -- penalty [OPTIONS]   penalty study (paper Appendix D)
    cargo run --release -p compare -- sinusoid [OPTIONS]  standard vs hybrid model (paper Section 4)

OPTIONS:
    --scene FILE   scene to run (default: scenes/center-crack.toml)
    --out DIR      output folder (default: out/<scene name>/)
    --open M@MU    a metric known to fail and tracked as open (e.g. onset_difference_over_T@0.3):
                   still reported as failing, but it does not set the exit code (repeatable)
    --factors LIST penalty only: the factors f of eps_n = eps_t = f x E per metre, comma-separated
                   whole numbers >= 1 (default 100,200,300, the paper's Appendix D)
    -h, --help     this text

For every friction coefficient in [compare].friction_coeffs the FE model and the spectral model
(at the FE time step) run from 0 to T. The spectral curves are shifted by a/c_d (paper Fig. 7b)
and the crack-tip histories are compared:
    onset_difference_over_T              |t_on,FE − (t_on,SBI + a/c_d)| / T      <= 0.01
    tip_position_rms_over_a              RMS from a common origin, a → 1.9a       <= 0.05
    mean_speed_relative_difference       mean speed between 1.2a and 1.9a       <= 0.05
    friction_delay_sign_product_over_T2  delays (μ vs smallest μ) of equal sign  > 0
    friction_delay_difference_over_T     |delay_FE − delay_SBI| / T               <= 0.01
Writes fem_mu*.csv, spectral_mu*.csv (t,tip_right,tip_left,cz_tip_right,cz_tip_left),
metrics.csv (metric,mu,value,tolerance,pass), the full model outputs in fem_mu*/ and
spectral_mu*/, and PNG figures. Exits non-zero if any metric fails.

sweep: runs the FE model at h = 4, 2, 1, 0.5 mm (rounded so that a/h is whole) and the
spectral model at the power-of-two N nearest to X/h, each in its own process, at the scene's
[friction].friction_coeff; records wall time, peak memory, onset time and mean tip speed with
their errors against the finest run of the same model; writes sweep.csv and
sweep_error_vs_wall_time.png, and each point's tip history tips_<model>_<h>mm.csv
(default folder out/<scene name>-sweep/).

penalty: runs the FE model at the scene's [friction].friction_coeff with eps_n = eps_t =
100, 200, 300 x E per metre (or the --factors given); writes penalty_faces.csv (upper-face penetration/2a at t/T = 0.6),
penalty_means.csv (mean contact tractions against time), penalty_summary.csv (window means
against |s_yy| and mu|s_yy|) and the three panels of Figure D.15 (default folder
out/<scene name>-penalty/).

sinusoid: runs the FE model with every model of [compare].models (default scene
scenes/sinusoidal-interface.toml); writes each run's outputs to <out>/<model>/,
sinusoid_summary.csv (KKT violations, residual stress, E_kin/E_strain, tips; wall time) and the
figures 10, 11, 12, E.16, B.14b and the KKT metric as PNG with their data as CSV (default folder
out/<scene name>/). Exits non-zero if a run goes unstable (its partial output is kept).
";

/// What the command line asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Command {
    Gate,
    Sweep,
    /// Penalty study (paper Appendix D).
    Penalty,
    /// Standard against hybrid model on the sinusoidal interface (paper Section 4).
    Sinusoid,
    /// Child side of the sweep: one model at one nominal size [m].
    SweepPoint(Model, f64),
}

struct Args {
    command: Command,
    scene: PathBuf,
    out: Option<PathBuf>,
    /// Metrics known to fail and tracked as open (`METRIC@MU`): still printed and written as
    /// failing, but they do not set the exit code.
    open: Vec<String>,
    /// Penalty factors of the penalty study (`--factors`).
    factors: Vec<u32>,
}

fn default_scene(file: &str) -> PathBuf {
    let local = PathBuf::from("scenes").join(file);
    if local.exists() {
        local
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes").join(file)
    }
}

fn parse_args() -> Result<Option<Args>> {
    let mut args = Args {
        command: Command::Gate,
        scene: default_scene("center-crack.toml"),
        out: None,
        open: Vec::new(),
        factors: compare::penalty::EPS_FACTORS.to_vec(),
    };
    let (mut model, mut size) = (None, None);
    let mut it = std::env::args().skip(1).peekable();
    match it.peek().map(String::as_str) {
        Some("sweep") => args.command = Command::Sweep,
        Some("penalty") => args.command = Command::Penalty,
        Some("sinusoid") => {
            args.command = Command::Sinusoid;
            args.scene = default_scene("sinusoidal-interface.toml");
        }
        Some("sweep-point") => args.command = Command::SweepPoint(Model::Fem, 0.0),
        _ => {}
    }
    if args.command != Command::Gate {
        it.next();
    }
    while let Some(a) = it.next() {
        match a.as_str() {
            "-h" | "--help" => return Ok(None),
            "--scene" => args.scene = it.next().context("--scene needs a file")?.into(),
            "--out" => args.out = Some(it.next().context("--out needs a folder")?.into()),
            "--open" => args.open.push(it.next().context("--open needs METRIC@MU")?),
            "--factors" => {
                args.factors =
                    parse_factors(&it.next().context("--factors needs a list such as 100,200,300")?)?
            }
            "--model" => model = Some(it.next().context("--model needs fem or spectral")?),
            "--size" => {
                size = Some(
                    it.next()
                        .context("--size needs a length in metres")?
                        .parse::<f64>()?,
                )
            }
            other => bail!("unknown argument `{other}`; see --help"),
        }
    }
    if let Command::SweepPoint(..) = args.command {
        let m = match model.as_deref() {
            Some("fem") => Model::Fem,
            Some("spectral") => Model::Spectral,
            _ => bail!("sweep-point: --model must be fem or spectral"),
        };
        let h = size
            .filter(|h| *h > 0.0)
            .context("sweep-point: --size must be > 0 (metres)")?;
        args.command = Command::SweepPoint(m, h);
    }
    Ok(Some(args))
}

/// `--factors`: comma-separated whole numbers >= 1, at least one.
fn parse_factors(list: &str) -> Result<Vec<u32>> {
    let factors = list
        .split(',')
        .map(|f| match f.trim().parse::<u32>() {
            Ok(v) if v >= 1 => Ok(v),
            _ => bail!("--factors: `{f}` is not a whole number >= 1 (factor f of eps_n = f x E per metre)"),
        })
        .collect::<Result<Vec<u32>>>()?;
    if factors.is_empty() {
        bail!("--factors: give at least one factor");
    }
    Ok(factors)
}

struct Bars(MultiProgress);

impl Reporter for Bars {
    fn run_started(&self, label: &str) -> Box<dyn FnMut(u64, u64) + '_> {
        let style =
            ProgressStyle::with_template("{prefix} [{bar:40}] {pos}/{len} steps ({elapsed}, eta {eta})")
                .expect("invariant: the template is valid")
                .progress_chars("=> ");
        let bar = self.0.add(
            ProgressBar::new(1)
                .with_style(style)
                .with_prefix(label.to_string()),
        );
        Box::new(move |done, total| {
            bar.set_length(total);
            bar.set_position(done);
            if done >= total {
                bar.finish();
            }
        })
    }
}

fn is_open(v: &Verdict, open: &[String]) -> bool {
    open.iter().any(|o| *o == format!("{}@{}", v.metric, v.mu))
}

fn print_table(verdicts: &[Verdict], open: &[String]) {
    println!(
        "\n{:<38} {:>8} {:>12} {:>10} {:>6}",
        "metric", "mu", "value", "tolerance", "pass"
    );
    for v in verdicts {
        let pass = match (v.pass, is_open(v, open)) {
            (true, _) => "yes",
            (false, false) => "NO",
            (false, true) => "NO (open)",
        };
        println!(
            "{:<38} {:>8} {:>12.5} {:>10} {:>6}",
            v.metric, v.mu, v.value, v.tolerance, pass
        );
    }
}

fn main() -> ExitCode {
    match real_main() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn real_main() -> Result<bool> {
    let Some(args) = parse_args()? else {
        print!("{HELP}");
        return Ok(true);
    };
    let text =
        std::fs::read_to_string(&args.scene).with_context(|| format!("reading {}", args.scene.display()))?;
    let stem = args
        .scene
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    match args.command {
        Command::Gate => {}
        Command::SweepPoint(model, h) => {
            let dir = args
                .out
                .unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-sweep")));
            sweep::print_point(&sweep::run_point(&text, model, h, &dir)?)?;
            return Ok(true);
        }
        Command::Sweep => {
            let out = args
                .out
                .unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-sweep")));
            return run_sweep(&args.scene, &text, &out);
        }
        Command::Penalty => {
            let out = args
                .out
                .unwrap_or_else(|| PathBuf::from("out").join(format!("{stem}-penalty")));
            let report =
                compare::penalty::run_study(&text, &out, &args.factors, &Bars(MultiProgress::new()))?;
            print!("{}", compare::penalty::table(&report.summary));
            println!("\n{} files written to {}", report.files.len(), out.display());
            return Ok(true);
        }
        Command::Sinusoid => {
            let out = args.out.unwrap_or_else(|| PathBuf::from("out").join(&stem));
            return run_sinusoid(&text, &out);
        }
    }
    let out = args.out.unwrap_or_else(|| PathBuf::from("out").join(stem));
    let report = run_gate(&text, &out, &Bars(MultiProgress::new()))?;
    print_table(&report.verdicts, &args.open);
    println!("\n{} files written to {}", report.files.len(), out.display());
    let failing: Vec<&Verdict> = report.verdicts.iter().filter(|v| !v.pass).collect();
    let blocking = failing.iter().filter(|v| !is_open(v, &args.open)).count();
    for v in report
        .verdicts
        .iter()
        .filter(|v| v.pass && is_open(v, &args.open))
    {
        println!(
            "--open {}@{} now passes: remove it from the command line",
            v.metric, v.mu
        );
    }
    match (failing.len(), blocking) {
        (0, _) => println!("all metrics within tolerance"),
        (n, 0) => println!("{n} metric(s) fail, all of them listed as open with --open"),
        (n, b) => println!("SOME METRICS FAIL: {n} failing, {b} not listed as open"),
    }
    Ok(blocking == 0)
}

fn run_sweep(scene: &Path, text: &str, out: &Path) -> Result<bool> {
    let exe = std::env::current_exe().context("locating the compare executable")?;
    let bar = ProgressBar::new((2 * sweep::NOMINAL_SIZES.len()) as u64).with_style(
        ProgressStyle::with_template("sweep [{bar:40}] {pos}/{len} points ({elapsed}) {msg}")
            .expect("invariant: the template is valid"),
    );
    let points = sweep::run_children(&exe, scene, out, &mut |p| {
        bar.set_message(format!(
            "{:?} h = {:.2e} m: {:.1} s",
            p.model, p.spacing, p.wall_s
        ));
        bar.inc(1);
    })?;
    bar.finish();
    let case = compare::models::case(text)?;
    let rows = sweep::with_errors(&points, case.duration);
    println!(
        "\n{:<9} {:>10} {:>10} {:>9} {:>9} {:>9} {:>11} {:>9}",
        "model", "spacing_m", "dt_s", "wall_s", "peak_MiB", "onset_s", "onsetErr/T", "speedErr"
    );
    for r in &rows {
        let p = r;
        println!(
            "{:<9} {:>10.3e} {:>10.3e} {:>9.1} {:>9.0} {:>9.5} {:>11.4} {:>9.4}",
            format!("{:?}", p.model),
            p.spacing,
            p.time_step,
            p.wall_s,
            p.peak_memory_bytes / 1048576.0,
            p.onset,
            r.onset_error_over_t,
            r.speed_error_rel
        );
    }
    let files = sweep::write_results(out, &rows)?;
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    println!("\nwrote {}", names.join(", "));
    Ok(true)
}

fn run_sinusoid(text: &str, out: &Path) -> Result<bool> {
    let report = compare::sinusoid::run_study(text, out, &Bars(MultiProgress::new()))?;
    print!("{}", compare::sinusoid::table(&report.rows, &report.setup));
    println!();
    for f in &report.files {
        println!("wrote {}", f.display());
    }
    println!("{} files written to {}", report.files.len(), out.display());
    for f in &report.failures {
        println!("FAILED: {f}");
    }
    Ok(report.failures.is_empty())
}

#[cfg(test)]
mod tests {
    use super::parse_factors;

    #[test]
    fn factors_are_whole_numbers_of_at_least_one() {
        assert_eq!(parse_factors("100, 200,300").unwrap(), vec![100, 200, 300]);
        for bad in ["0", "-5", "2.5", "100,,300", ""] {
            let e = parse_factors(bad).unwrap_err().to_string();
            assert!(e.contains("--factors"), "{bad}: {e}");
        }
    }
}
