//! How much the FE–spectral agreement depends on the FE box and its boundary field. The paper's
//! box is 4a × 2a with the crack growing towards a displacement-controlled edge 2a from its centre,
//! and the case's boundary field (paper eqs. C.8–C.9) is not an exact elastic solution. This
//! study runs the comparison in boxes k times larger (x ∈ [x_c − 2ka, x_c + 2ka], y ∈ [−ka, ka],
//! the cohesive interface filling the whole row) with the case's field and with the exact one
//! (mode-II part of u_y restored), against the same spectral runs.

pub mod figure;
pub mod rows;

use crate::gate::metrics::{CaseScales, PAPER_RESOLUTION, Verdict, per_mu};
use crate::output::write_rows;
use crate::runner::{Job, Keep, Reporter, fem_tips, preflight, run_fem, run_spectral, spectral_tips};
use crate::series::Series;
use crate::study::Study;
use anyhow::{Context, Result};
pub use rows::{BoundaryRow, Field};
use std::path::{Path, PathBuf};

/// Box factors k of the default study: 4a × 2a (the paper's), 8a × 4a, 12a × 6a.
pub const BOX_FACTORS: [u32; 3] = [1, 2, 3];

/// Everything the study produced.
#[derive(Debug, Clone)]
pub struct BoundaryReport {
    /// One row per (box, field, μ).
    pub rows: Vec<BoundaryRow>,
    /// Every file written.
    pub files: Vec<PathBuf>,
}

/// The FE scene of box factor k with `field`, validated before any run.
fn box_scene(study: &Study, k: u32, field: Field, mu: f64) -> Result<fem::Scene> {
    let (xc, a) = (study.fem.center_x(), study.fem.half_length());
    let k = f64::from(k);
    study
        .fem
        .with_friction_coeff(mu)?
        .with_domain([xc - 2.0 * k * a, xc + 2.0 * k * a], [-k * a, k * a])?
        .with_mode_ii_uy(field == Field::Exact)
        .with_context(|| format!("the FE box {}a × {}a", 4.0 * k, 2.0 * k))
}

fn signed(verdicts: &[Verdict], f: &Series, s: &Series, scales: &CaseScales) -> (f64, f64, f64) {
    let a = scales.half_length;
    let lag = match (crate::series::onset(f, a), crate::series::onset(s, a)) {
        (Some(tf), Some(ts)) => (tf - ts - scales.shift) / scales.duration,
        _ => f64::NAN,
    };
    let speed = match (crate::series::mean_speed(f, a), crate::series::mean_speed(s, a)) {
        (Some(vf), Some(vs)) => (vf - vs) / vs,
        _ => f64::NAN,
    };
    (lag, verdicts[1].value, speed)
}

/// Runs the study for the friction values of `[compare].friction_coeffs` and the box factors
/// `boxes`, with both fields, writing `boundary.csv` and its figure into `dir`.
pub fn run_study(study: &Study, boxes: &[u32], dir: &Path, rep: &dyn Reporter) -> Result<BoundaryReport> {
    let mus = study.friction_coeffs()?;
    let spec = study.spectral()?;
    let mut plans = Vec::new();
    for &mu in &mus {
        let spectral = spec
            .with_friction_coeff(mu)?
            .with_time_step(study.fem.time_step())?;
        let mut fems = Vec::new();
        for &k in boxes {
            for field in [Field::Case, Field::Exact] {
                fems.push((k, field, box_scene(study, k, field, mu)?));
            }
        }
        plans.push((mu, spectral, fems));
    }
    let labels: Vec<(String, Vec<String>)> = plans
        .iter()
        .map(|(mu, _, fems)| {
            let boxes = fems
                .iter()
                .map(|(k, f, _)| format!("FE box {k} {f:?} μ = {mu}"))
                .collect();
            (format!("spectral μ = {mu}"), boxes)
        })
        .collect();
    let spectrals: Vec<(&str, &spectral::Scene)> = labels
        .iter()
        .zip(&plans)
        .map(|((l, _), (_, s, _))| (l.as_str(), s))
        .collect();
    let fems: Vec<(&str, &fem::Scene)> = labels
        .iter()
        .zip(&plans)
        .flat_map(|((_, ls), (_, _, fems))| ls.iter().zip(fems).map(|(l, (_, _, s))| (l.as_str(), s)))
        .collect();
    // the folder stays locked against other runs until the study returns, its files written
    let (plan, _held) = preflight(study, &fems, &spectrals, dir)?;
    rep.planned(&plan);
    let case = study.case();
    let scales = CaseScales {
        half_length: case.half_length,
        duration: case.duration,
        shift: case.shift(),
    };
    let mut rows = Vec::new();
    for (mu, spectral, fems) in &plans {
        let label = format!("spectral μ = {mu}");
        let sub = dir.join(format!("spectral_mu{mu}"));
        let job = Job {
            scene: spectral,
            label: &label,
            dir: &sub,
            keep: Keep::OnFailure,
        };
        let s = Series::half_length(&spectral_tips(&run_spectral(job, rep)?.completed()?));
        for (k, field, scene) in fems {
            let label = format!("FE {}a x {}a {field:?} μ = {mu}", 4 * k, 2 * k);
            let sub = dir.join(format!("fem_box{k}_{field:?}_mu{mu}").to_lowercase());
            let job = Job {
                scene,
                label: &label,
                dir: &sub,
                keep: Keep::OnFailure,
            };
            let run = run_fem(job, rep)?;
            let wall_s = run.wall_s;
            let f = Series::half_length(&fem_tips(&run.completed()?));
            let verdicts = per_mu(*mu, &f, &s, &scales, &PAPER_RESOLUTION);
            let (lag, rms, speed) = signed(&verdicts, &f, &s, &scales);
            rows.push(BoundaryRow {
                box_factor: *k,
                field: *field,
                mu: *mu,
                onset_lag_over_t: lag,
                tip_position_rms_over_a: rms,
                mean_speed_difference: speed,
                wall_s,
            });
        }
    }
    let mut files = vec![write_rows(&dir.join("boundary.csv"), &rows)?];
    files.push(figure::draw(dir, &rows)?);
    Ok(BoundaryReport { rows, files })
}

/// Prints the study's table (one row per box, field and friction value) and where its files
/// went (`dir`).
pub fn print_report(report: &BoundaryReport, dir: &Path) {
    println!(
        "\n{:>6} {:>6} {:>6} {:>14} {:>12} {:>14} {:>8}",
        "box", "field", "mu", "onset lag/T", "RMS/a", "speed diff", "wall s"
    );
    for r in &report.rows {
        println!(
            "{:>5}a {:>6} {:>6} {:>14.5} {:>12.4} {:>13.2}% {:>8.1}",
            4 * r.box_factor,
            format!("{:?}", r.field).to_lowercase(),
            r.mu,
            r.onset_lag_over_t,
            r.tip_position_rms_over_a,
            100.0 * r.mean_speed_difference,
            r.wall_s
        );
    }
    println!("\n{} files written to {}", report.files.len(), dir.display());
}
