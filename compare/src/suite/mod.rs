//! The cross-check suite (docs/claims.md, "Cross-checks beyond the paper"): canonical problems of
//! dynamic fracture, each run in both models and measured against its analytic answer. Its cases
//! are Freund's crack under uniform shear and under uniform tension
//! (`scenes/suite/freund-mode2.toml`, `freund-mode1.toml`), and Andrews' supershear transition
//! under slip weakening at four seismic ratios (`andrews-s*.toml`): an FE box that carries the far
//! field on every side and lets the scattered waves out, and the spectral model's unbounded body.
//!
//! For each case it writes a folder with both models' tip histories (`fem.csv`, `spectral.csv`:
//! `t,tip_right,tip_left` [s, m, m], the gate's tip files), the speeds at each crack length
//! (`speeds.csv` for Freund, `front_speeds.csv` for Andrews), each model's full output and the
//! figure `speed.png`; and `suite.csv` with `case,metric,value,tolerance,pass`.

pub mod andrews;
pub mod center;
mod figure;
pub mod metrics;
mod report;

pub use report::{open_rows, print_report};

use crate::concurrent::{Lanes, Task, run_all};
use crate::output::write_rows;
use crate::runner::{Finished, Job, Keep, Reporter, fem_tips, run_fem, run_spectral, spectral_tips};
use crate::study::Study;
use crate::theory::freund::{Material, Mode};
use andrews::AndrewsCase;
use anyhow::{Context, Result, anyhow, bail};
use metrics::{FreundCase, speed_rows};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Which theory a case is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Theory {
    /// Freund's equation of motion in this mode.
    Freund(Mode),
    /// Andrews' supershear transition.
    Andrews,
}

/// The cases, in the order they run and are reported: (name, theory). Each is the scene
/// `scenes/suite/<name>.toml`.
pub const CASES: [(&str, Theory); 6] = [
    ("freund-mode2", Theory::Freund(Mode::II)),
    ("freund-mode1", Theory::Freund(Mode::I)),
    ("andrews-s0.8", Theory::Andrews),
    ("andrews-s1.0", Theory::Andrews),
    ("andrews-s1.2", Theory::Andrews),
    ("andrews-s2.5", Theory::Andrews),
];

/// One row of `suite.csv`.
#[derive(Debug, Clone, Serialize)]
pub struct SuiteRow {
    /// The case.
    pub case: String,
    /// Metric name (the centre crack's: `METRIC@MU`, as the comparison prints them).
    pub metric: String,
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

/// A case's scales.
#[derive(Debug, Clone, Copy)]
enum Case {
    Freund(FreundCase),
    Andrews(AndrewsCase),
}

/// One case, read and checked: its name, scale and both scenes.
struct Planned {
    name: &'static str,
    case: Case,
    study: Study,
    spectral: spectral::Scene,
}

/// Reads and checks every case of `scenes_dir` (at half their element size with `fine`); every
/// problem of every case at once.
fn plan(scenes_dir: &Path, fine: bool) -> Result<Vec<Planned>> {
    let mut problems = Vec::new();
    let mut planned = Vec::new();
    for (name, theory) in CASES {
        let path = scenes_dir.join(format!("{name}.toml"));
        match plan_case(&path, name, theory, fine) {
            Ok(p) => planned.push(p),
            Err(e) => problems.push(format!("{name}: {e:#}")),
        }
    }
    if !problems.is_empty() {
        bail!("{}", problems.join("\n"));
    }
    Ok(planned)
}

fn plan_case(path: &Path, name: &'static str, theory: Theory, fine: bool) -> Result<Planned> {
    let study = Study::load(path)?;
    let scene_spectral = study
        .spectral
        .clone()
        .ok_or_else(|| anyhow!("{}: no [spectral] section", path.display()))?;
    // fine: both models at half their spacing (the FE element size as `converged` sets it, the
    // spectral grid twice as dense as the scene's; some scenes' grids are finer than their h)
    let (study, spectral) = if fine {
        let study = study.at_resolution(0.5 * study.fem.fem.element_size)?;
        let n = 2 * scene_spectral.grid_points;
        let spectral = scene_spectral
            .with_grid_points(n)
            .with_context(|| format!("{}: the spectral model on N = {n} points", path.display()))?;
        (study, spectral)
    } else {
        (study, scene_spectral)
    };
    let s = &study.fem;
    let mode = match theory {
        Theory::Freund(mode) => mode,
        Theory::Andrews => {
            let case = AndrewsCase::from_scene(s).with_context(|| path.display().to_string())?;
            return Ok(Planned {
                name,
                case: Case::Andrews(case),
                study,
                spectral,
            });
        }
    };
    let (crack, law) = match (s.crack, s.interface) {
        (Some(c), Some(l)) => (c, l),
        _ => bail!("{}: a Freund case needs [crack] and [interface]", path.display()),
    };
    let m = s.material;
    let c = m.wave_speeds();
    let mu_prime = m.shear_modulus / (1.0 - m.poisson_ratio);
    let case = Case::Freund(FreundCase {
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
    });
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
    /// The centre crack's scene (`scenes/center-crack.toml`).
    pub center_crack: PathBuf,
    /// A folder where the comparison of the centre crack already ran (at the suite's resolution):
    /// its metrics are computed from its tip files instead of running it again.
    pub gate: Option<PathBuf>,
    /// At half the scenes' element size and spectral grid spacing.
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
    let center = center::study(&options.center_crack, options.fine).map(|c| Study {
        budget: options.budget,
        concurrent_runs: options.concurrent_runs,
        ..c
    });
    let planned = plan(&options.scenes, options.fine);
    let (center, planned) = match (center, planned) {
        (Ok(c), Ok(p)) => (c, p),
        (c, p) => {
            let problems: Vec<String> = [c.err(), p.err()]
                .into_iter()
                .flatten()
                .map(|e| format!("{e:#}"))
                .collect();
            bail!("{}", problems.join("\n"));
        }
    };
    // the centre crack first: read from an earlier comparison before any run, or run
    let mut rows = match &options.gate {
        Some(gate) => center::from_folder(&center, options.fine, gate)?,
        None => Vec::new(),
    };
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
    // the folder stays locked against other runs until the study returns, its files written
    let (plan, _held) = crate::runner::preflight(&check, &fems, &spectrals, dir)?;
    let lanes = Lanes::new(
        2 * planned.len(),
        rayon::current_num_threads(),
        options.concurrent_runs,
    );
    if options.gate.is_none() {
        rows = center::run(&center, options.fine, &dir.join(center::NAME), rep)?;
    }
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
    // every run stopped side by side is named, not the first only
    let mut results = crate::concurrent::all_ok(run_all(tasks, lanes)?)?
        .into_iter()
        .map(|r| Some(Ok::<_, anyhow::Error>(r)));
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
    let mut files = vec![
        write_tip_file(&dir.join("fem.csv"), &fem_tips(fem_out))?,
        write_tip_file(&dir.join("spectral.csv"), &spectral_tips(spectral_out))?,
    ];
    let centre = p.study.fem.crack.map_or(0.0, |c| c.center_x);
    let rows = match &p.case {
        Case::Freund(case) => {
            let fem_points: Vec<(f64, f64)> = fem_out
                .arrivals
                .iter()
                .map(|r| ((r.x - centre).abs(), r.failure_time))
                .filter(|(a, t)| *a > case.a0 && t.is_finite())
                .collect();
            let spectral_points: Vec<(f64, f64)> = spectral_out
                .tips
                .iter()
                .map(|r| (0.5 * (r.tip_right - r.tip_left), r.t))
                .filter(|(a, _)| *a > case.a0)
                .collect();
            let speeds = speed_rows(case, &fem_points, &spectral_points);
            files.push(write_rows(&dir.join("speeds.csv"), &speeds)?);
            files.push(figure::draw(&dir.join("speed.png"), p.name, case, &speeds)?);
            metrics::rows(p.name, &speeds)
        }
        Case::Andrews(case) => {
            let points: Vec<(f64, f64)> = fem_out.arrivals.iter().map(|r| (r.x, r.failure_time)).collect();
            let fem_front = andrews::contiguous_front(&points, centre, case.a0);
            let spectral_front = andrews::spectral_front(&spectral_out.tips, case.a0);
            // both fronts are read over the half-lengths both reached, short of the last
            // process zone (the FE box's side)
            let reach = [andrews::reach(&fem_front), andrews::reach(&spectral_front)];
            let a_end = reach[0].min(reach[1]) - case.lp;
            let speeds = andrews::speed_rows(case, &fem_front, &spectral_front, a_end);
            let fem_m = andrews::measure_front(case, &fem_front, a_end);
            let spectral_m = andrews::measure_front(case, &spectral_front, a_end);
            files.push(write_rows(&dir.join("front_speeds.csv"), &speeds)?);
            files.push(figure::draw_andrews(
                &dir.join("speed.png"),
                p.name,
                case,
                &speeds,
                [fem_m.transition, spectral_m.transition],
            )?);
            andrews::rows(p.name, case, [fem_m, spectral_m], reach)
        }
    };
    Ok((rows, files))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every case reads and checks. The Freund cases have the pre-crack their scenes state: 1.1
    /// times the Griffith length of the final load (so that the crack starts near the end of the
    /// ramp), a process zone of 8.8 mm, and a theory whose speed at 3 a₀ is below c_R. The Andrews
    /// cases have the seismic ratio of their name, a pre-crack of 1.2 a_c to the nearest node
    /// (1.17 to 1.21), the same process zone, and a box long enough for Andrews' transition
    /// (or, at S = 2.5, for the reach the metric asks). The fine variant halves the element size
    /// and the spectral grid spacing and keeps everything else.
    #[test]
    fn the_cases_are_the_scenes_their_names_say() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/suite");
        for fine in [false, true] {
            let planned = plan(&dir, fine).unwrap();
            assert_eq!(planned.len(), CASES.len());
            for (p, (name, theory)) in planned.iter().zip(CASES) {
                assert_eq!(p.name, name);
                let h = p.study.fem.fem.element_size;
                assert!(
                    (h - if fine { 5e-4 } else { 1e-3 }).abs() < 1e-12,
                    "{name}: h = {h}"
                );
                let scene = Study::load(&dir.join(format!("{name}.toml"))).unwrap();
                let n = scene.spectral.unwrap().grid_points;
                assert_eq!(p.spectral.grid_points, if fine { 2 * n } else { n }, "{name}");
                match (&p.case, theory) {
                    (Case::Freund(c), Theory::Freund(mode)) => {
                        assert_eq!(c.mode, mode);
                        let end = c.load.ramp_end;
                        let ratio = c.a0 / c.griffith_length(end);
                        assert!((ratio - 1.1).abs() < 1e-6, "{name}: a0/L_c = {ratio}");
                        assert!((c.lp - 8.81e-3).abs() < 1e-4, "{name}: l_p = {}", c.lp);
                        let v = c.theory_speed(3.0 * c.a0, end);
                        assert!(v > 0.0 && v < c.material.rayleigh_speed(), "{name}: {v}");
                    }
                    (Case::Andrews(c), Theory::Andrews) => {
                        let s: f64 = name.trim_start_matches("andrews-s").parse().unwrap();
                        assert!((c.s - s).abs() < 1e-6, "{name}: S = {}", c.s);
                        let ratio = c.a0 / c.ac;
                        assert!((1.165..1.21).contains(&ratio), "{name}: a0/a_c = {ratio}");
                        assert!((c.lp - 8.81e-3).abs() < 1e-4, "{name}: Λ0 = {}", c.lp);
                        let half = p.study.fem.fem.x_range[1];
                        let needed = c.andrews_distance().unwrap_or(andrews::REACH_MIN * c.a0);
                        assert!(half > needed, "{name}: box {half} m, needs {needed} m");
                    }
                    _ => panic!("{name}: the wrong kind of case"),
                }
            }
        }
    }
}
