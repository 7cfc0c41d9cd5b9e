//! The FE-versus-spectral comparison of the centre crack (paper Section 3, Figures 5–8): both
//! models for every friction value of `[compare].friction_coeffs`, the spectral model at the FE
//! model's time step (paper §3.2), tip CSVs, full model outputs, the agreement metrics against
//! their tolerances, and the figures. Run at the scene's resolution by `compare` and at
//! h = 0.5 mm by `compare converged`.

pub mod fem_figures;
pub mod figures;
pub mod metrics;

use crate::output::{mu_tag, write_rows, write_tips};
use crate::runner::{Job, Keep, Reporter, fem_tips, preflight, run_fem, run_spectral, spectral_tips};
use crate::study::{Case, Study};
use anyhow::{Context, Result};
use metrics::{MuRuns, Tolerances, Verdict, verdicts};
use std::path::{Path, PathBuf};

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
    rep.planned(&preflight(study, &fems, &spectrals, dir)?);
    let case = study.case();
    let mu_detail = plans.iter().map(|p| p.mu).fold(f64::MIN, f64::max);
    let (mut runs, mut files, mut detail, mut warnings) = (Vec::new(), Vec::new(), None, Vec::new());
    for p in &plans {
        let tag = mu_tag(p.mu);
        let fem_dir = dir.join(format!("fem_mu{tag}"));
        let fem_job = Job {
            scene: &p.fem,
            label: &format!("FE        μ = {}", p.mu),
            dir: &fem_dir,
            keep: Keep::Everything,
        };
        let f = run_fem(fem_job, rep)?;
        warnings.extend(f.warnings.iter().cloned());
        let fo = f.completed()?;
        let spectral_dir = dir.join(format!("spectral_mu{tag}"));
        let spectral_job = Job {
            scene: &p.spectral,
            label: &format!("spectral  μ = {}", p.mu),
            dir: &spectral_dir,
            keep: Keep::Everything,
        };
        let so = run_spectral(spectral_job, rep)?.completed()?;
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
