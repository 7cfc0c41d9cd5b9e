//! The FE-versus-spectral comparison of the centre crack (paper Section 3, Figures 5–8): both
//! models for every friction value of `[compare].friction_coeffs`, the spectral model at the FE
//! model's time step (paper §3.2), tip CSVs, full model outputs, the agreement metrics against
//! their tolerances, and the figures. Run at the scene's resolution by `compare` and at
//! h = 0.5 mm by `compare converged`.

pub mod fem_figures;
pub mod figures;
pub mod metrics;
pub mod verdict;

use crate::concurrent::{self, Lanes, Task};
use crate::output::{mu_tag, write_rows, write_tips};
use crate::runner::{
    Finished, Job, Keep, Reporter, fem_tips, preflight, run_fem, run_spectral, spectral_tips,
};
use crate::study::{Case, Study};
use anyhow::{Context, Result};
use metrics::{MuRuns, Tolerances, Verdict, verdicts};
use std::path::{Path, PathBuf};

/// One finished run of the comparison.
enum Ran {
    Fem(Box<Finished<fem::RunOutput>>),
    Spectral(Box<Finished<spectral::RunOutput>>),
}

/// What a comparison produced.
#[derive(Debug, Clone)]
pub struct GateReport {
    /// Every metric with its tolerance and verdict.
    pub verdicts: Vec<Verdict>,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// Both models' tip histories per friction value.
    pub runs: Vec<MuRuns>,
    /// Scale quantities of the case.
    pub case: Case,
    /// FE element size h [m] and spectral grid spacing Δx [m] of the runs.
    pub spacing: (f64, f64),
    /// What the runs did that the user should know.
    pub warnings: Vec<String>,
}

impl GateReport {
    /// True when every metric meets its tolerance.
    pub fn passed(&self) -> bool {
        self.verdicts.iter().all(|v| v.pass)
    }
}

/// The two runs of one friction value, validated before any runs.
struct MuPlan {
    mu: f64,
    fem: fem::Scene,
    spectral: spectral::Scene,
}

/// Every run of the comparison, each scene validated (friction values, the spectral model at the
/// FE step) before the first time step.
fn plan(study: &Study) -> Result<Vec<MuPlan>> {
    let spec = study.spectral()?;
    study
        .friction_coeffs()?
        .into_iter()
        .map(|mu| {
            let fem = study.fem.with_friction_coeff(mu)?;
            let spectral = spec
                .with_friction_coeff(mu)?
                .with_time_step(fem.time_step())
                .with_context(|| {
                    format!(
                        "the spectral model runs at the FE time step {:e} s (paper §3.2); \
                         with its grid that step is out of range",
                        fem.time_step()
                    )
                })?;
            Ok(MuPlan { mu, fem, spectral })
        })
        .collect()
}

/// Runs the comparison of `study` against the tolerances `tol`, writing everything into `dir`.
/// Every scene is validated before the first run; an unstable run stops the comparison with its
/// partial output kept.
pub fn run_gate(study: &Study, tol: &Tolerances, dir: &Path, rep: &dyn Reporter) -> Result<GateReport> {
    let plans = plan(study)?;
    let labels: Vec<String> = plans.iter().map(|p| format!("μ = {}", p.mu)).collect();
    let fems: Vec<(&str, &fem::Scene)> = labels
        .iter()
        .zip(&plans)
        .map(|(l, p)| (l.as_str(), &p.fem))
        .collect();
    let spectrals: Vec<(&str, &spectral::Scene)> = labels
        .iter()
        .zip(&plans)
        .map(|(l, p)| (l.as_str(), &p.spectral))
        .collect();
    let lanes = Lanes::new(
        2 * plans.len(),
        rayon::current_num_threads(),
        study.concurrent_runs,
    );
    rep.planned(&preflight(study, &fems, &spectrals, dir)?.with_lanes(lanes));
    let case = study.case();
    let mu_detail = plans.iter().map(|p| p.mu).fold(f64::MIN, f64::max);
    // Every run is independent (the spectral model takes the FE step from the scene, not from
    // the FE run): the FE runs first, as the longest, then the spectral ones.
    let labels: Vec<(String, String)> = plans
        .iter()
        .map(|p| {
            (
                format!("FE        μ = {}", p.mu),
                format!("spectral  μ = {}", p.mu),
            )
        })
        .collect();
    let dirs: Vec<(PathBuf, PathBuf)> = plans
        .iter()
        .map(|p| {
            let tag = mu_tag(p.mu);
            (
                dir.join(format!("fem_mu{tag}")),
                dir.join(format!("spectral_mu{tag}")),
            )
        })
        .collect();
    let mut tasks: Vec<Task<Ran>> = Vec::new();
    for ((p, (fem_label, _)), (fem_dir, _)) in plans.iter().zip(&labels).zip(&dirs) {
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.fem,
                label: fem_label,
                dir: fem_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Fem(Box::new(run_fem(job, rep)?)))
        }));
    }
    for ((p, (_, spectral_label)), (_, spectral_dir)) in plans.iter().zip(&labels).zip(&dirs) {
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.spectral,
                label: spectral_label,
                dir: spectral_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Spectral(Box::new(run_spectral(job, rep)?)))
        }));
    }
    let mut ran = Vec::new();
    for r in concurrent::run_all(tasks, lanes)? {
        match r {
            Some(r) => ran.push(r?),
            None => unreachable!("invariant: a run is skipped only after an earlier one failed"),
        }
    }
    let (fems, spectrals) = ran.split_at(plans.len());
    let (mut runs, mut files, mut detail, mut warnings) = (Vec::new(), Vec::new(), None, Vec::new());
    for ((p, f), s) in plans.iter().zip(fems).zip(spectrals) {
        let (Ran::Fem(f), Ran::Spectral(s)) = (f, s) else {
            unreachable!("invariant: the FE runs come first, then the spectral ones");
        };
        warnings.extend(f.warnings.iter().cloned());
        let fo = f.clone().completed()?;
        let so = s.clone().completed()?;
        let r = MuRuns {
            mu: p.mu,
            fem: fem_tips(&fo),
            spectral: spectral_tips(&so),
        };
        files.push(write_tips(dir, "fem", p.mu, &r.fem)?);
        files.push(write_tips(dir, "spectral", p.mu, &r.spectral)?);
        runs.push(r);
        if p.mu == mu_detail {
            detail = Some((p.fem.clone(), fo));
        }
    }
    let verdicts = verdicts(&case, &runs, tol);
    files.push(write_rows(&dir.join("metrics.csv"), &verdicts)?);
    files.extend(figures::tip_figures(dir, &case, &runs)?);
    if let Some((scene, fo)) = &detail {
        files.extend(fem_figures::fem_figures(dir, &case, scene, fo)?);
    }
    let spacing = plans.first().map_or((f64::NAN, f64::NAN), |p| {
        (p.fem.fem.element_size, p.spectral.grid_spacing())
    });
    Ok(GateReport {
        verdicts,
        files,
        runs,
        case,
        spacing,
        warnings,
    })
}
