//! The cross-check suite (docs/claims.md, "Cross-checks beyond the paper"): canonical problems of
//! dynamic fracture, each run in both models and measured against its analytic answer. Today its
//! cases are Freund's crack under uniform shear and under uniform tension
//! (`scenes/suite/freund-mode2.toml`, `freund-mode1.toml`): an FE box that carries the far field on
//! every side and lets the scattered waves out, and the spectral model's unbounded body.
//!
//! For each case it writes a folder with both models' tip histories (`fem.csv`, `spectral.csv`:
//! `t,tip_right,tip_left` [s, m, m], the gate's tip files), the speeds at each crack length
//! (`speeds.csv`), each model's full output and the figure `speed.png`; and `suite.csv` with
//! `case,metric,value,tolerance,pass`.

mod figure;
pub mod metrics;

use crate::concurrent::{Lanes, Task, run_all};
use crate::output::write_rows;
use crate::runner::{Finished, Job, Keep, Reporter, fem_tips, run_fem, run_spectral, spectral_tips};
use crate::study::Study;
use crate::theory::freund::{Material, Mode};
use anyhow::{Context, Result, anyhow, bail};
use metrics::{FreundCase, SpeedRow, speed_rows, worst};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The cases, in the order they run and are reported: (name, theory mode). Each is the scene
/// `scenes/suite/<name>.toml`.
pub const CASES: [(&str, Mode); 2] = [("freund-mode2", Mode::II), ("freund-mode1", Mode::I)];

/// FE tip speeds agree with the spectral ones at each crack length from 1.2 a₀ to 3 a₀ within this
/// share of the spectral speed [-]: the gate's tolerance on the mean speeds (docs/outputs.md).
pub const SPEED_TOLERANCE: f64 = 0.05;

/// Each model's speed puts its crack, by the theory, within this many process zones l_p of its
/// measured length [-] (in the theory's speed range): a cohesive crack's tip is not defined more
/// finely than its process zone, and the equation of motion G = g(v) G_static ∝ a shifts by
/// l_p/a when a does by l_p.
pub const LENGTH_TOLERANCE: f64 = 1.0;

/// One row of `suite.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct SuiteRow {
    /// The case.
    pub case: String,
    /// Metric name.
    pub metric: &'static str,
    /// Measured value (NaN: a model never reached a length the metric needs).
    pub value: f64,
    /// The acceptance condition, e.g. `<= 0.05`.
    pub tolerance: String,
    /// Whether the value meets it.
    pub pass: bool,
}

/// The suite's result.
#[derive(Debug)]
pub struct SuiteReport {
    /// Every metric of every case.
    pub rows: Vec<SuiteRow>,
    /// The files written.
    pub files: Vec<PathBuf>,
    /// Wall time of the whole suite [s].
    pub wall_s: f64,
}

/// One case, read and checked: its name, scale and both scenes.
struct Planned {
    name: &'static str,
    case: FreundCase,
    study: Study,
    spectral: spectral::Scene,
}

/// Reads and checks every case of `scenes_dir` (at half their element size with `fine`); every
/// problem of every case at once.
fn plan(scenes_dir: &Path, fine: bool) -> Result<Vec<Planned>> {
    let mut problems = Vec::new();
    let mut planned = Vec::new();
    for (name, mode) in CASES {
        let path = scenes_dir.join(format!("{name}.toml"));
        match plan_case(&path, name, mode, fine) {
            Ok(p) => planned.push(p),
            Err(e) => problems.push(format!("{name}: {e:#}")),
        }
    }
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    Ok(planned)
}

fn plan_case(path: &Path, name: &'static str, mode: Mode, fine: bool) -> Result<Planned> {
    let study = Study::load(path)?;
    let study = if fine {
        study.at_resolution(0.5 * study.fem.fem.element_size)?
    } else {
        study
    };
    let spectral = study
        .spectral
        .clone()
        .ok_or_else(|| anyhow!("{}: no [spectral] section", path.display()))?;
    let s = &study.fem;
    let (crack, law) = match (s.crack, s.interface) {
        (Some(c), Some(l)) => (c, l),
        _ => bail!("{}: a Freund case needs [crack] and [interface]", path.display()),
    };
    let m = s.material;
    let c = m.wave_speeds();
    let mu_prime = m.shear_modulus / (1.0 - m.poisson_ratio);
    let case = FreundCase {
        mode,
        a0: crack.half_length,
        lp: 9.0 * std::f64::consts::PI / 32.0 * mu_prime * law.delta_c / law.sigma_c,
        material: Material::new(c.cd, c.cs).ok_or_else(|| anyhow!("invariant: a validated material"))?,
        mu_prime,
        gc: 0.5 * law.sigma_c * law.delta_c,
        load: match mode {
            Mode::I => s.loading.normal,
            Mode::II => s.loading.shear,
        },
    };
    Ok(Planned {
        name,
        case,
        study,
        spectral,
    })
}

/// What a run returned.
enum Ran {
    Fem(Box<Finished<fem::RunOutput>>),
    Spectral(Box<Finished<spectral::RunOutput>>),
}

/// How the suite runs: where its scenes are, at which resolution, within which budget.
#[derive(Debug, Clone)]
pub struct Options {
    /// The folder of the cases' scenes (`scenes/suite`).
    pub scenes: PathBuf,
    /// At half the scenes' element size (and the spectral grid to match).
    pub fine: bool,
    /// The most one run may cost.
    pub budget: preflight::Budget,
    /// Runs at once (`None`: one per core).
    pub concurrent_runs: Option<usize>,
}

/// Runs every case into `dir` (one folder per case). Every scene is checked, and each run's
/// budget and the output folder, before the first run.
pub fn run(options: &Options, dir: &Path, rep: &dyn Reporter) -> Result<SuiteReport> {
    let start = std::time::Instant::now();
    let planned = plan(&options.scenes, options.fine)?;
    let labels: Vec<(String, String)> = planned
        .iter()
        .map(|p| (format!("FE        {}", p.name), format!("spectral  {}", p.name)))
        .collect();
    let fems: Vec<(&str, &fem::Scene)> = planned
        .iter()
        .zip(&labels)
        .map(|(p, l)| (l.0.as_str(), &p.study.fem))
        .collect();
    let spectrals: Vec<(&str, &spectral::Scene)> = planned
        .iter()
        .zip(&labels)
        .map(|(p, l)| (l.1.as_str(), &p.spectral))
        .collect();
    let check = Study {
        budget: options.budget,
        ..planned[0].study.clone()
    };
    let plan = crate::runner::preflight(&check, &fems, &spectrals, dir)?;
    let lanes = Lanes::new(
        2 * planned.len(),
        rayon::current_num_threads(),
        options.concurrent_runs,
    );
    rep.planned(&plan.with_lanes(lanes));
    let dirs: Vec<PathBuf> = planned.iter().map(|p| dir.join(p.name)).collect();
    let mut tasks: Vec<Task<Ran>> = Vec::new();
    for ((p, l), d) in planned.iter().zip(&labels).zip(&dirs) {
        let fem_dir = d.join("fem");
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.study.fem,
                label: &l.0,
                dir: &fem_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Fem(Box::new(run_fem(job, rep)?)))
        }));
    }
    for ((p, l), d) in planned.iter().zip(&labels).zip(&dirs) {
        let spectral_dir = d.join("spectral");
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.spectral,
                label: &l.1,
                dir: &spectral_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Spectral(Box::new(run_spectral(job, rep)?)))
        }));
    }
    let mut results = run_all(tasks, lanes)?.into_iter();
    let n = planned.len();
    let mut fems_out = Vec::new();
    for _ in 0..n {
        match results.next().flatten().transpose()? {
            Some(Ran::Fem(f)) => fems_out.push(f.completed()?),
            _ => bail!("invariant: the FE runs come first"),
        }
    }
    let mut spectral_out = Vec::new();
    for _ in 0..n {
        match results.next().flatten().transpose()? {
            Some(Ran::Spectral(s)) => spectral_out.push(s.completed()?),
            _ => bail!("invariant: the spectral runs follow"),
        }
    }
    let mut rows = Vec::new();
    let mut files = Vec::new();
    for (((p, d), f), s) in planned.iter().zip(&dirs).zip(&fems_out).zip(&spectral_out) {
        let (case_rows, case_files) = measure(p, d, f, s)?;
        rows.extend(case_rows);
        files.extend(case_files);
    }
    files.push(write_rows(&dir.join("suite.csv"), &rows)?);
    Ok(SuiteReport {
        rows,
        files,
        wall_s: start.elapsed().as_secs_f64(),
    })
}

/// A case's speeds, metrics, tip files and figure.
fn measure(
    p: &Planned,
    dir: &Path,
    fem_out: &fem::RunOutput,
    spectral_out: &spectral::RunOutput,
) -> Result<(Vec<SuiteRow>, Vec<PathBuf>)> {
    let centre = p.study.fem.crack.map_or(0.0, |c| c.center_x);
    let fem_points: Vec<(f64, f64)> = fem_out
        .arrivals
        .iter()
        .map(|r| ((r.x - centre).abs(), r.failure_time))
        .filter(|(a, t)| *a > p.case.a0 && t.is_finite())
        .collect();
    let spectral_points: Vec<(f64, f64)> = spectral_out
        .tips
        .iter()
        .map(|r| (0.5 * (r.tip_right - r.tip_left), r.t))
        .filter(|(a, _)| *a > p.case.a0)
        .collect();
    let speeds = speed_rows(&p.case, &fem_points, &spectral_points);
    let mut files = vec![
        write_tip_file(&dir.join("fem.csv"), &fem_tips(fem_out))?,
        write_tip_file(&dir.join("spectral.csv"), &spectral_tips(spectral_out))?,
        write_rows(&dir.join("speeds.csv"), &speeds)?,
    ];
    files.push(figure::draw(&dir.join("speed.png"), p.name, &p.case, &speeds)?);
    Ok((case_rows(p.name, &speeds), files))
}

/// The metrics of one case.
fn case_rows(case: &str, speeds: &[SpeedRow]) -> Vec<SuiteRow> {
    let row = |metric, value: f64, limit: f64| SuiteRow {
        case: case.to_string(),
        metric,
        value,
        tolerance: format!("<= {limit}"),
        pass: value <= limit,
    };
    let in_range = |v: f64| !v.is_nan();
    vec![
        row(
            "speed_difference_max",
            worst(
                speeds
                    .iter()
                    .map(|s| (s.fem_speed - s.spectral_speed).abs() / s.spectral_speed),
            ),
            SPEED_TOLERANCE,
        ),
        row(
            "fem_theory_length_residual_max_over_lp",
            worst(
                speeds
                    .iter()
                    .map(|s| s.fem_length_residual)
                    .filter(|v| in_range(*v)),
            ),
            LENGTH_TOLERANCE,
        ),
        row(
            "spectral_theory_length_residual_max_over_lp",
            worst(
                speeds
                    .iter()
                    .map(|s| s.spectral_length_residual)
                    .filter(|v| in_range(*v)),
            ),
            LENGTH_TOLERANCE,
        ),
    ]
}

/// `t,tip_right,tip_left` [s, m, m] of a model's tip rows.
fn write_tip_file(path: &Path, rows: &[crate::series::TipRow]) -> Result<PathBuf> {
    #[derive(Serialize)]
    struct Tip {
        t: f64,
        tip_right: f64,
        tip_left: f64,
    }
    let tips: Vec<Tip> = rows
        .iter()
        .map(|r| Tip {
            t: r.t,
            tip_right: r.tip_right,
            tip_left: r.tip_left,
        })
        .collect();
    write_rows(path, &tips).with_context(|| format!("writing {}", path.display()))
}

/// Prints the metrics table and the files written; true when every metric passes.
pub fn print_report(report: &SuiteReport, dir: &Path) -> bool {
    println!(
        "{:<16} {:<44} {:>10} {:>10} {:>6}",
        "case", "metric", "value", "tolerance", "pass"
    );
    for r in &report.rows {
        println!(
            "{:<16} {:<44} {:>10.5} {:>10} {:>6}",
            r.case,
            r.metric,
            r.value,
            r.tolerance,
            if r.pass { "yes" } else { "NO" }
        );
    }
    let failed = report.rows.iter().filter(|r| !r.pass).count();
    println!(
        "\n{} files written to {} in {:.0} s",
        report.files.len(),
        dir.display(),
        report.wall_s
    );
    if failed > 0 {
        println!("{failed} metric(s) FAIL");
    }
    failed == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both cases read and check, each with the pre-crack its scene states: 1.1 times the Griffith
    /// length of the final load (so that the crack starts near the end of the ramp), a process
    /// zone of 8.8 mm, and a theory whose speed at 3 a₀ is below c_R. The fine variant halves the
    /// element size and keeps everything else.
    #[test]
    fn the_cases_are_freund_cracks_a_little_longer_than_griffith() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/suite");
        for fine in [false, true] {
            let planned = plan(&dir, fine).unwrap();
            assert_eq!(planned.len(), CASES.len());
            for (p, (name, mode)) in planned.iter().zip(CASES) {
                let c = &p.case;
                assert_eq!((p.name, c.mode), (name, mode));
                let end = c.load.ramp_end;
                let ratio = c.a0 / c.griffith_length(end);
                assert!((ratio - 1.1).abs() < 1e-6, "{name}: a0/L_c = {ratio}");
                assert!((c.lp - 8.81e-3).abs() < 1e-4, "{name}: l_p = {}", c.lp);
                let v = c.theory_speed(3.0 * c.a0, end);
                assert!(v > 0.0 && v < c.material.rayleigh_speed(), "{name}: {v}");
                let h = p.study.fem.fem.element_size;
                assert!(
                    (h - if fine { 5e-4 } else { 1e-3 }).abs() < 1e-12,
                    "{name}: h = {h}"
                );
            }
        }
    }
}
