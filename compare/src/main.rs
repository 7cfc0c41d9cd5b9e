//! `cargo run --release -p compare [-- JOB] [OPTIONS]`: the harness's command line.

use anyhow::{Context, Result, anyhow};
use clap::parser::ValueSource;
use clap::{ArgMatches, Args, CommandFactory, FromArgMatches, Parser, Subcommand, ValueEnum};
use compare::gate::metrics::{METRIC_NAMES, PAPER_RESOLUTION};
use compare::gate::verdict::print_report;
use compare::runner::Reporter;
use compare::study::{FrictionRule, Study};
use compare::sweep::{self, Model, scale_out};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;

/// Runs the FE and the spectral model on one scene and checks that they agree (paper Section 3);
/// the other jobs reproduce the paper's further studies.
///
/// Without a job: for every friction coefficient of [compare].friction_coeffs, the FE model and
/// the spectral model (at the FE time step) run from 0 to T; the spectral curves are shifted by
/// a/c_d (paper Fig. 7b) and the crack-tip histories compared against fixed tolerances (onset
/// ≤ 0.015 T, RMS tip position ≤ 0.05 a, mean speed within 5 %, friction delays of the same sign
/// and within 0.01 T). Prints the metrics, writes CSVs, every model's full output and the
/// figures, and exits non-zero if a metric fails.
#[derive(Debug, Parser)]
#[command(name = "compare", version)]
struct Cli {
    #[command(subcommand)]
    job: Option<Job>,
    #[command(flatten)]
    common: Common,
}

/// Options every job takes.
#[derive(Debug, Args)]
struct Common {
    /// Scene file (default: scenes/center-crack.toml; scenes/sinusoidal-interface.toml for
    /// `sinusoid`, scenes/rough-interface.toml for `rough`).
    #[arg(long, global = true, value_name = "FILE")]
    scene: Option<PathBuf>,
    /// Output folder (default: out/<scene file name>[-<job>]/).
    #[arg(long, global = true, value_name = "DIR")]
    out: Option<PathBuf>,
    #[command(flatten)]
    budget: preflight::options::BudgetOptions,
    /// How many of a comparison's independent runs go at once, the cores shared out between them
    /// (default: one per core, but one per two cores for FE runs on mapped meshes, as `sinusoid`
    /// and `rough`, which finish sooner so; 1 runs them one after the other, each on every core).
    #[arg(long, global = true, value_name = "N", allow_negative_numbers = true,
          value_parser = clap::value_parser!(u32).range(1..))]
    concurrent_runs: Option<u32>,
    /// Where contact friction acts in both models, instead of the scene's [friction]
    /// contact_friction (the comparison and `converged` only; the output folder gets the rule's
    /// name): all_faces, the paper's hybrid model (friction on every closed face, partly damaged
    /// ones included, on top of the cohesive shear), or failed_only (friction only where the
    /// interface has fully failed).
    #[arg(long, global = true, value_name = "RULE")]
    friction_rule: Option<RuleArg>,
    /// METRIC@MU, comma-separated (for `suite`, CASE:METRIC): metrics of the comparison,
    /// `converged` or `suite` that are known to fail and whose decision is open (docs/cases.md). They are still printed, with their value
    /// and tolerance, and marked open; they do not set the exit code. Each must fail: a listed
    /// metric that passes is an error, so the list cannot outlive its cause.
    #[arg(long, global = true, value_name = "METRIC@MU", value_delimiter = ',')]
    open: Vec<String>,
}

/// `--friction-rule`.
#[derive(Debug, Clone, Copy, ValueEnum)]
#[value(rename_all = "snake_case")]
enum RuleArg {
    AllFaces,
    FailedOnly,
}

#[derive(Debug, Subcommand)]
enum Job {
    /// The comparison at h = 0.5 mm, where the onsets must agree within 0.01 T (the FE onset has
    /// converged there); writes converged.csv next to the comparison's files.
    Converged,
    /// Speed against accuracy: each model at h = 4, 2, 1, 0.5 mm, each point in its own process
    /// (wall time and peak memory are its own); writes sweep.csv and a log-log figure.
    ///
    /// With --emit DIR the points are written out as jobs to run elsewhere (xargs, GNU parallel,
    /// a Slurm job array); --collect DIR then reads their results and writes the same files.
    Sweep {
        /// Nominal FE element sizes [m], comma-separated, each finite, > 0 and listed once; the
        /// points run coarse to fine whatever the order given.
        #[arg(long, value_name = "M", value_delimiter = ',', allow_hyphen_values = true,
              default_values_t = sweep::NOMINAL_SIZES, value_parser = sweep::parse_size)]
        sizes: Vec<f64>,
        /// Check everything as the sweep does, then write into DIR one scene file per point,
        /// jobs.txt (one command line per point), sweep.sbatch (a Slurm job array) and
        /// sweep-manifest.toml, instead of running the points.
        #[arg(long, value_name = "DIR", conflicts_with = "collect")]
        emit: Option<PathBuf>,
        /// Read the results of the sweep emitted into DIR and write sweep.csv and the figure into
        /// DIR (or --out); refused, naming each, while any point is missing or failed.
        #[arg(long, value_name = "DIR")]
        collect: Option<PathBuf>,
    },
    /// Paper Appendix D: the FE model at eps_n = eps_t = f × E per metre for each factor f, and
    /// the mean contact tractions as eps_n → ∞.
    Penalty {
        /// Factors f, comma-separated whole numbers ≥ 1.
        #[arg(long, value_delimiter = ',', default_values_t = compare::penalty::EPS_FACTORS, allow_negative_numbers = true,
              value_parser = clap::value_parser!(u32).range(1..))]
        factors: Vec<u32>,
    },
    /// How the FE–spectral agreement depends on the FE box and its boundary field: the
    /// comparison in boxes k × (4a × 2a) with the case's field and the exact elastic one.
    Boundary {
        /// Box factors k, comma-separated whole numbers ≥ 1.
        #[arg(long, value_delimiter = ',', default_values_t = compare::boundary::BOX_FACTORS, allow_negative_numbers = true,
              value_parser = clap::value_parser!(u32).range(1..))]
        boxes: Vec<u32>,
    },
    /// Paper Section 4: the standard against the hybrid model on the sinusoidal interface, every
    /// model of [compare].models; exits non-zero if a run goes unstable (its output is kept).
    Sinusoid,
    /// Cross-checks beyond the paper: every case of scenes/suite (Freund's crack under uniform
    /// shear and under uniform tension) in both models, each against its analytic answer; writes
    /// suite.csv and one folder per case, and exits non-zero if a metric fails.
    Suite {
        /// At half the scenes' element size and spectral grid spacing (docs/results.md).
        #[arg(long)]
        fine: bool,
        /// A folder where the comparison of the centre crack already ran at the suite's
        /// resolution (`compare --out DIR`; with --fine, `compare converged --out DIR`): the
        /// suite's first case is measured from its tip files instead of running it again.
        #[arg(long, value_name = "DIR")]
        gate: Option<PathBuf>,
    },
    /// Paper Section 5 outlook: the same study on a self-affine rough weak interface
    /// (fem.interface_rough), standard against hybrid model, with the same metrics, CSVs and
    /// figures; exits non-zero if a run goes unstable (its output is kept).
    Rough,
    /// One point of a sweep in this process (what `sweep` runs in its children and the lines of
    /// an emitted jobs.txt run): prints the point as CSV on stdout, or writes it to --result.
    #[command(hide = true)]
    SweepPoint {
        /// Which model.
        #[arg(long)]
        model: PointModel,
        /// Nominal FE element size [m].
        #[arg(long, value_parser = sweep::parse_size)]
        size: f64,
        /// Write the point as CSV to FILE (through a temporary file and a rename) instead of
        /// stdout; a failed point writes FILE.failed with the error instead.
        #[arg(long, value_name = "FILE")]
        result: Option<PathBuf>,
    },
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum PointModel {
    Fem,
    Spectral,
}

/// A progress bar per run, and the runs stopped on Ctrl-C.
struct Bars(MultiProgress, &'static AtomicBool);

impl Reporter for Bars {
    fn stop(&self) -> &AtomicBool {
        self.1
    }

    fn planned(&self, plan: &compare::runner::Plan) {
        println!("{plan}");
    }

    fn run_started(&self, label: &str) -> Box<dyn FnMut(u64, u64) + Send + '_> {
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

/// A default scene file: in scenes/ of the working directory, else of the repository.
fn default_scene(file: &str) -> PathBuf {
    let local = PathBuf::from("scenes").join(file);
    if local.exists() {
        local
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes").join(file)
    }
}

/// Prints an error with its causes on one line and exits 1; exits 1 too when a check fails.
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

/// Whether option `id` was given on the command line, before or after the job's name.
fn given(m: &ArgMatches, id: &str) -> bool {
    let here = m.ids().any(|i| i.as_str() == id) && m.value_source(id) == Some(ValueSource::CommandLine);
    here || m.subcommand().is_some_and(|(_, sub)| given(sub, id))
}

/// The sweep jobs that read no scene here (`--collect`, a sweep point) run, and what `--emit`
/// refuses is checked; `None`: the job reads its scene next.
fn before_scene(matches: &ArgMatches, cli: &Cli) -> Result<Option<bool>> {
    match &cli.job {
        Some(Job::Sweep {
            collect: Some(dir), ..
        }) => {
            for (id, flag) in [
                ("scene", "--scene"),
                ("sizes", "--sizes"),
                ("max_memory", "--max-memory"),
                ("max_steps", "--max-steps"),
            ] {
                anyhow::ensure!(
                    !given(matches, id),
                    "{flag}: not taken with --collect, which reads each point's scene, size and budget \
                     from {}",
                    dir.join(scale_out::MANIFEST).display()
                );
            }
            return sweep::cli::collect(dir, cli.common.out.as_deref()).map(Some);
        }
        Some(Job::Sweep { emit: Some(dir), .. }) => anyhow::ensure!(
            !given(matches, "out"),
            "--out: not taken with --emit; the points write into {} (give --out to --collect to put \
             sweep.csv elsewhere)",
            dir.display()
        ),
        Some(Job::SweepPoint { model, size, result }) => {
            let scene = cli
                .common
                .scene
                .clone()
                .unwrap_or_else(|| default_scene("center-crack.toml"));
            let model = match model {
                PointModel::Fem => Model::Fem,
                PointModel::Spectral => Model::Spectral,
            };
            let (out, budget) = (cli.common.out.as_deref(), cli.common.budget.budget());
            return sweep::cli::point(&scene, out, budget, model, *size, result.as_deref()).map(Some);
        }
        _ => {}
    }
    Ok(None)
}

/// Parses the command line and runs its job; true when every check of the job passed.
fn real_main() -> Result<bool> {
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some(passed) = before_scene(&matches, &cli)? {
        return Ok(passed);
    }
    if let Some(Job::Suite { fine, gate }) = cli.job {
        return suite(&matches, &cli.common, fine, gate);
    }
    let file = match cli.job {
        Some(Job::Sinusoid) => compare::sinusoid::SCENE,
        Some(Job::Rough) => compare::rough::SCENE,
        _ => "center-crack.toml",
    };
    let scene_path = cli.common.scene.clone().unwrap_or_else(|| default_scene(file));
    let (study, text) = Study::read(&scene_path)?;
    let (study, rule_suffix) = apply_options(study, &cli.common, cli.job.as_ref())?;
    let out = |suffix: &str| {
        cli.common.out.clone().unwrap_or_else(|| {
            PathBuf::from("out").join(format!("{}{suffix}", preflight::paths::folder_name(&study.stem)))
        })
    };
    let bars = Bars(
        MultiProgress::new(),
        preflight::stop::on_signal().map_err(|e| anyhow!(e))?,
    );
    match cli.job {
        None => {
            let dir = out(&rule_suffix);
            let report = compare::gate::run_gate(&study, &PAPER_RESOLUTION, &dir, &bars)?;
            print_report(&report, &dir, &cli.common.open)
        }
        Some(Job::Converged) => {
            let dir = out(&format!("-converged{rule_suffix}"));
            let report = compare::converged::run_converged(&study, &dir, &bars)?;
            print_report(&report.gate, &dir, &cli.common.open)
        }
        Some(Job::Sweep { sizes, emit, .. }) => match emit {
            Some(dir) => sweep::cli::emit(&study, &text, &scene_path, &sizes, &dir),
            None => sweep::cli::run(&study, &scene_path, &sizes, &out("-sweep"), bars.1),
        },
        Some(Job::Boundary { boxes }) => {
            let dir = out("-boundary");
            let report = compare::boundary::run_study(&study, &boxes, &dir, &bars)?;
            compare::boundary::print_report(&report, &dir);
            Ok(true)
        }
        Some(Job::Penalty { factors }) => {
            let dir = out("-penalty");
            let report = compare::penalty::run_study(&study, &factors, &dir, &bars)?;
            compare::penalty::print_report(&report, &dir);
            Ok(true)
        }
        Some(Job::Sinusoid) => compare::sinusoid::run(&study, &out(""), &bars),
        Some(Job::Rough) => compare::rough::run(&study, &out(""), &bars),
        Some(Job::SweepPoint { .. } | Job::Suite { .. }) => {
            unreachable!("invariant: handled before the scene is read")
        }
    }
}

/// `suite`: its cases are the scenes of scenes/suite and the centre crack, so it takes no
/// --scene; its --open lists CASE:METRIC.
fn suite(matches: &ArgMatches, common: &Common, fine: bool, gate: Option<PathBuf>) -> Result<bool> {
    for (id, flag) in [("scene", "--scene"), ("friction_rule", "--friction-rule")] {
        anyhow::ensure!(
            !given(matches, id),
            "{flag}: not taken by `suite`, which runs the scenes of scenes/suite as they are"
        );
    }
    if let Some(dir) = &common.out {
        preflight::paths::explicit(dir).map_err(|e| anyhow!(e))?;
    }
    let dir = common
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(if fine { "suite-fine" } else { "suite" }));
    for o in &common.open {
        anyhow::ensure!(
            o.contains(':'),
            "--open {o}: `suite` takes CASE:METRIC as it prints them, e.g. \
             center-crack:tip_position_rms_over_a@0.3"
        );
    }
    if let Some(g) = &gate {
        anyhow::ensure!(g.is_dir(), "--gate {}: no such folder", g.display());
    }
    let options = compare::suite::Options {
        scenes: default_scene("suite"),
        center_crack: default_scene("center-crack.toml"),
        gate,
        fine,
        budget: common.budget.budget(),
        concurrent_runs: common.concurrent_runs.map(|n| n as usize),
    };
    let bars = Bars(
        MultiProgress::new(),
        preflight::stop::on_signal().map_err(|e| anyhow!(e))?,
    );
    let report = compare::suite::run(&options, &dir, &bars)?;
    compare::suite::print_report(&report, &dir, &common.open)
}

/// The options that change the study, checked: `--friction-rule` (its output-folder suffix
/// returned), `--open`, the budget, `--concurrent-runs` and `--out`.
fn apply_options(mut study: Study, common: &Common, job: Option<&Job>) -> Result<(Study, String)> {
    let rule_suffix = match (common.friction_rule, job) {
        (None, _) => String::new(),
        (Some(rule), None | Some(Job::Converged)) => {
            let rule = match rule {
                RuleArg::AllFaces => FrictionRule::AllFaces,
                RuleArg::FailedOnly => FrictionRule::FailedOnly,
            };
            study = study
                .with_friction_rule(rule)
                .with_context(|| format!("--friction-rule {}", rule.name()))?;
            format!("-{}", rule.name())
        }
        (Some(_), Some(_)) => anyhow::bail!(
            "--friction-rule: taken by the comparison and `converged` only; for another job set \
             [friction] contact_friction in the scene"
        ),
    };
    if !common.open.is_empty() {
        anyhow::ensure!(
            matches!(job, None | Some(Job::Converged)),
            "--open: taken by the comparison and `converged` only"
        );
        for o in &common.open {
            let name = o.split('@').next().unwrap_or_default();
            anyhow::ensure!(
                o.contains('@') && METRIC_NAMES.contains(&name),
                "--open {o}: expected METRIC@MU with METRIC one of {}",
                METRIC_NAMES.join(", ")
            );
        }
    }
    study.budget = common.budget.budget();
    study.concurrent_runs = common.concurrent_runs.map(|n| n as usize);
    if let Some(dir) = &common.out {
        preflight::paths::explicit(dir).map_err(|e| anyhow!(e))?;
    }
    Ok((study, rule_suffix))
}
