//! The comparison run: both models for every friction value of the scene, tip CSVs, full
//! model outputs, metrics against their tolerances, and figures.

use crate::align::Series;
use crate::fem_figures::fem_figures;
use crate::figures::{MuRuns, tip_figures};
use crate::metrics::{CaseScales, Verdict, friction_delay, per_mu};
use crate::models::{self, Case};
use crate::output::{mu_tag, write_metrics, write_tips};
use crate::scene::friction_coeffs;
use anyhow::{Context, Result, anyhow};
use std::path::{Path, PathBuf};

/// Progress reporting for long runs: the binary draws indicatif bars, tests stay silent.
pub trait Reporter {
    /// A run labelled `label` starts; returns its callback `(steps_done, total_steps)`.
    fn run_started(&self, label: &str) -> Box<dyn FnMut(u64, u64) + '_>;
}

/// A reporter that reports nothing.
pub struct Silent;

impl Reporter for Silent {
    fn run_started(&self, _label: &str) -> Box<dyn FnMut(u64, u64) + '_> {
        Box::new(|_, _| {})
    }
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
}

impl GateReport {
    /// True when every metric meets its tolerance.
    pub fn passed(&self) -> bool {
        self.verdicts.iter().all(|v| v.pass)
    }
}

fn run_fem(text: &str, mu: f64, dir: &Path, rep: &dyn Reporter) -> Result<fem::RunOutput> {
    let scene = models::fem_scene(text, mu)?;
    let sub = dir.join(format!("fem_mu{}", mu_tag(mu)));
    std::fs::create_dir_all(&sub)?;
    let mut progress = rep.run_started(&format!("FE        μ = {mu}"));
    match fem::run_with_progress(&scene, &mut *progress) {
        Ok(out) => {
            fem::output::write_csv(&out, &sub).with_context(|| format!("writing {}", sub.display()))?;
            Ok(out)
        }
        Err(fem::RunError::Unstable { partial, .. }) => {
            let written = fem::output::write_csv(&partial, &sub);
            Err(anyhow!(
                "FE run μ = {mu} went unstable; output so far in {} ({written:?})",
                sub.display()
            ))
        }
        Err(e) => Err(e).context(format!("FE run μ = {mu}")),
    }
}

fn run_spectral(text: &str, mu: f64, dt: f64, dir: &Path, rep: &dyn Reporter) -> Result<spectral::RunOutput> {
    let scene = models::spectral_scene(text, mu, dt)?;
    let sub = dir.join(format!("spectral_mu{}", mu_tag(mu)));
    std::fs::create_dir_all(&sub)?;
    let mut progress = rep.run_started(&format!("spectral  μ = {mu}"));
    match spectral::run_with_progress(&scene, &mut *progress) {
        Ok(out) => {
            spectral::output::write_csv(&out, &sub).with_context(|| format!("writing {}", sub.display()))?;
            Ok(out)
        }
        Err(spectral::RunError::Unstable { partial, .. }) => {
            let written = spectral::output::write_csv(&partial, &sub);
            Err(anyhow!(
                "spectral run μ = {mu} went unstable; output so far in {} ({written:?})",
                sub.display()
            ))
        }
        Err(e) => Err(e).context(format!("spectral run μ = {mu}")),
    }
}

fn verdicts(case: &Case, runs: &[MuRuns]) -> Vec<Verdict> {
    let scales = CaseScales {
        half_length: case.half_length,
        duration: case.duration,
        shift: case.shift(),
    };
    let hl = |r: &MuRuns| (Series::half_length(&r.fem), Series::half_length(&r.spectral));
    let mut out = Vec::new();
    for r in runs {
        let (f, s) = hl(r);
        out.extend(per_mu(r.mu, &f, &s, &scales));
    }
    let reference = runs.iter().min_by(|a, b| a.mu.total_cmp(&b.mu));
    if let Some(r0) = reference {
        let (f0, s0) = hl(r0);
        for r in runs.iter().filter(|r| r.mu > r0.mu) {
            let (f, s) = hl(r);
            out.extend(friction_delay((r0.mu, r.mu), (&f0, &f), (&s0, &s), &scales));
        }
    }
    out
}

/// Runs the comparison on the scene `text`, writing everything into `dir`.
pub fn run_gate(text: &str, dir: &Path, rep: &dyn Reporter) -> Result<GateReport> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let case = models::case(text)?;
    let mus = friction_coeffs(text)?;
    let mu_detail = mus.iter().copied().fold(f64::MIN, f64::max);
    let (mut runs, mut files, mut detail) = (Vec::new(), Vec::new(), None);
    for &mu in &mus {
        let fo = run_fem(text, mu, dir, rep)?;
        let so = run_spectral(text, mu, fo.time_step, dir, rep)?;
        let r = MuRuns {
            mu,
            fem: models::fem_tips(&fo),
            spectral: models::spectral_tips(&so),
        };
        files.push(write_tips(dir, "fem", mu, &r.fem)?);
        files.push(write_tips(dir, "spectral", mu, &r.spectral)?);
        runs.push(r);
        if mu == mu_detail {
            detail = Some(fo);
        }
    }
    let verdicts = verdicts(&case, &runs);
    files.push(write_metrics(dir, &verdicts)?);
    files.extend(tip_figures(dir, &case, &runs)?);
    if let Some(fo) = &detail {
        files.extend(fem_figures(dir, &case, mu_detail, fo)?);
    }
    Ok(GateReport {
        verdicts,
        files,
        runs,
        case,
    })
}
