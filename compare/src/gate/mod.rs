//! The FE-versus-spectral comparison of the centre crack (paper Section 3, Figures 5–8): both
//! models for every friction value of `[compare].friction_coeffs`, the spectral model at the FE
//! model's time step (paper §3.2), tip CSVs, full model outputs, the agreement metrics against
//! their tolerances, and the figures. Run at the scene's resolution by `compare` and at
//! h = 0.5 mm by `compare converged`.

pub mod bimaterial;
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

/// One task per run of `plans`, each writing into its folder of `dir`. Every run is independent
/// (the spectral model takes the FE step from the scene, not from the FE run): the FE runs come
/// first, as the longest, then the spectral ones.
fn run_tasks<'a>(plans: &'a [MuPlan], dir: &Path, rep: &'a dyn Reporter) -> Vec<Task<'a, Ran>> {
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
    for ((p, (fem_label, _)), (fem_dir, _)) in plans.iter().zip(labels.clone()).zip(dirs.clone()) {
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.fem,
                label: &fem_label,
                dir: &fem_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Fem(Box::new(run_fem(job, rep)?)))
        }));
    }
    for ((p, (_, spectral_label)), (_, spectral_dir)) in plans.iter().zip(labels).zip(dirs) {
        tasks.push(Box::new(move || {
            let job = Job {
                scene: &p.spectral,
                label: &spectral_label,
                dir: &spectral_dir,
                keep: Keep::Everything,
            };
            Ok(Ran::Spectral(Box::new(run_spectral(job, rep)?)))
        }));
    }
    tasks
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
    // the folder stays locked against other runs until the study returns, its files written
    let (plan, _held) = preflight(study, &fems, &spectrals, dir)?;
    rep.planned(&plan.with_lanes(lanes));
    let case = study.case();
    let mu_detail = plans.iter().map(|p| p.mu).fold(f64::MIN, f64::max);
    let tasks = run_tasks(&plans, dir, rep);
    let ran = concurrent::all_ok(concurrent::run_all(tasks, lanes)?)?;
    let (fems, spectrals) = ran.split_at(plans.len());
    let (mut runs, mut files, mut detail) = (Vec::new(), Vec::new(), None);
    let mut warnings: Vec<String> = study.fem.warnings();
    warnings.extend(study.spectral()?.warnings());
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
    if let Some(pair) = &case.bimaterial {
        let shear_sign = study.spectral()?.shear.r#final.signum();
        let tips = bimaterial::tip_speeds(&case, pair, shear_sign, &runs);
        files.push(write_rows(&dir.join("bimaterial_tips.csv"), &tips)?);
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The colours of a PNG [RGB per pixel], read back.
    fn pixels(path: &std::path::Path) -> Vec<[u8; 3]> {
        let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        let channels = info.line_size / info.width as usize;
        buf[..info.buffer_size()]
            .chunks(channels)
            .map(|c| [c[0], c[1], c[2]])
            .collect()
    }

    /// Every figure of the gate renders at the tiny centre crack (its FE run standing in for both
    /// models' tips, which the figures draw alike): each PNG decodes, holds more than white and
    /// the text's grey, and Figure 6b's first-slip line, the guide line the paper draws, has its
    /// data, each point inside the pre-crack and within the run.
    #[test]
    fn every_gate_figure_renders_at_the_tiny_centre_crack() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../scenes/tiny-fem-center-crack.toml"
        );
        let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let out = fem::run(&scene).unwrap();
        let w = scene.wave_speeds();
        let case = Case {
            half_length: scene.half_length(),
            center_x: scene.center_x(),
            duration: scene.duration(),
            cd: w.cd,
            cr: w.cr,
            normal_stress: scene.loading.normal.final_value,
            bimaterial: None,
        };
        let tips = crate::runner::fem_tips(&out);
        let runs = [MuRuns {
            mu: scene.friction_coeff,
            fem: tips.clone(),
            spectral: tips,
        }];
        let dir = std::env::temp_dir().join(format!("compare-gate-figures-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut files = figures::tip_figures(&dir, &case, &runs).unwrap();
        files.extend(fem_figures::fem_figures(&dir, &case, &scene, &out).unwrap());
        let pngs: Vec<_> = files
            .iter()
            .filter(|f| f.extension().is_some_and(|e| e == "png"))
            .collect();
        assert!(pngs.len() >= 10, "{files:?}");
        for p in pngs {
            // a colour that is neither white nor grey: a curve, a field or a mark was drawn
            let coloured = pixels(p)
                .iter()
                .filter(|[r, g, b]| r.max(g).max(b) - r.min(g).min(b) > 40)
                .count();
            assert!(coloured > 500, "{}: {coloured} coloured pixels", p.display());
        }
        let slip = std::fs::read_to_string(dir.join("fig6b_first_slip.csv")).unwrap();
        let rows: Vec<Vec<f64>> = slip
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        println!("fig6b first-slip line: {} nodes", rows.len());
        assert!(!rows.is_empty(), "the stick-to-slip line has no point");
        assert!(
            rows.iter()
                .all(|r| r[0].abs() < 1.0 && (0.0..=1.0).contains(&r[1]))
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
