//! Paper Appendix D (Figure D.15): the centre crack at ε_n = ε_t = f · E per metre for every
//! factor f given (the paper's [`EPS_FACTORS`] by default), at the scene's friction coefficient,
//! and the limit of the mean contact tractions as ε_n → ∞ ([`limit`]).

pub mod figures;
pub mod limit;
pub mod rows;
pub mod windows;

use crate::concurrent::Lanes;
use crate::output::write_rows;
use crate::runner::{Keep, Reporter, preflight, run_fems};
use crate::study::Study;
use anyhow::{Context, Result};
use figures::{Expected, penalty_figures};
use limit::{Limit, limits};
pub use rows::EPS_FACTORS;
use rows::{SummaryRow, face_rows, mean_rows, summary};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Everything the study produced.
#[derive(Debug, Clone)]
pub struct PenaltyReport {
    /// One summary row per penalty factor.
    pub summary: Vec<SummaryRow>,
    /// The limits ε_n → ∞ of both mean tractions (empty with fewer than two factors).
    pub limits: Vec<Limit>,
    /// Every file written.
    pub files: Vec<PathBuf>,
    /// What the runs did that the user should know.
    pub warnings: Vec<String>,
}

/// The FE scene of every factor f of `factors`, ε_n = ε_t = f · E per metre, validated before
/// any run. A factor given twice is refused.
pub fn plan(study: &Study, factors: &[u32]) -> Result<Vec<(u32, fem::Scene)>> {
    let e = study.fem.material.youngs_modulus;
    factors
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            if factors[..k].contains(&f) {
                anyhow::bail!("--factors: {f} is listed twice");
            }
            let eps = f64::from(f) * e;
            let scene = study
                .fem
                .with_penalties(eps, eps)
                .with_context(|| format!("ε_n = ε_t = {f} E per metre"))?;
            Ok((f, scene))
        })
        .collect()
}

/// Runs the study of `study` at each penalty factor of `factors`, writing CSVs and figures into
/// `dir`. A run that goes unstable stops the study with its output kept in `dir/fem_eps<f>/`.
pub fn run_study(study: &Study, factors: &[u32], dir: &Path, rep: &dyn Reporter) -> Result<PenaltyReport> {
    let plans = plan(study, factors)?;
    let labels: Vec<String> = plans.iter().map(|(f, _)| format!("ε_n = {f} E/m")).collect();
    let fems: Vec<(&str, &fem::Scene)> = labels
        .iter()
        .zip(&plans)
        .map(|(l, (_, s))| (l.as_str(), s))
        .collect();
    let lanes = Lanes::for_fe(
        plans.iter().map(|(_, s)| s),
        rayon::current_num_threads(),
        study.concurrent_runs,
    );
    // the folder stays locked against other runs until the study returns, its files written
    let (plan, _held) = preflight(study, &fems, &[], dir)?;
    rep.planned(&plan.with_lanes(lanes));
    let runs: Vec<_> = plans
        .iter()
        .map(|(factor, scene)| {
            (
                scene,
                format!("FE ε_n = {factor:>4} E/m"),
                dir.join(format!("fem_eps{factor}")),
            )
        })
        .collect();
    let (mut faces, mut means, mut summaries, mut warnings) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for ((factor, scene), f) in plans.iter().zip(run_fems(&runs, Keep::OnFailure, lanes, rep)?) {
        warnings.extend(f.warnings.iter().cloned());
        let out = f.completed()?;
        faces.extend(face_rows(*factor, scene, &out));
        means.extend(mean_rows(*factor, scene, &out));
        summaries.push(summary(*factor, scene, &out));
    }
    let s_yy = study.fem.loading.normal.final_value.abs();
    let limits = limits(&summaries, s_yy, study.fem.friction_coeff);
    let mut files = vec![
        write_rows(&dir.join("penalty_faces.csv"), &faces)?,
        write_rows(&dir.join("penalty_means.csv"), &means)?,
        write_rows(&dir.join("penalty_summary.csv"), &summaries)?,
    ];
    if !limits.is_empty() {
        files.push(write_rows(&dir.join("penalty_limit.csv"), &limits)?);
    }
    files.extend(penalty_figures(dir, &Expected::of(&study.fem), &faces, &means)?);
    Ok(PenaltyReport {
        summary: summaries,
        limits,
        files,
        warnings,
    })
}

/// The summary as a text table (for the binary to print).
pub fn table(rows: &[SummaryRow]) -> String {
    let opt = |v: Option<f64>, scale: f64, digits: usize| {
        v.map_or("—".to_string(), |v| format!("{:.*}", digits, v * scale))
    };
    let mut s = format!(
        "\n{:>10} {:>16} {:>14} {:>10} {:>14} {:>10}\n",
        "eps_n [E]", "max p/2a @0.6T", "T_n before [Pa]", "err_n", "T_t slip [Pa]", "err_t"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:>10} {:>15.5}% {:>14} {:>9}% {:>14} {:>9}%",
            r.eps_factor,
            100.0 * r.max_penetration_over_2a_at_profile,
            opt(r.mean_normal_before_onset, 1.0, 1),
            opt(r.rel_error_normal, 100.0, 2),
            opt(r.mean_tangential_while_slipping, 1.0, 1),
            opt(r.rel_error_tangential, 100.0, 2),
        );
    }
    s
}

/// The limits as text lines (for the binary to print).
pub fn limit_lines(limits: &[Limit]) -> String {
    let mut s = String::new();
    for l in limits {
        let _ = writeln!(
            s,
            "{} traction as eps_n -> inf: {:.1} Pa, {:+.2} % of {:.0} Pa (error falls with eps_n: {})",
            l.traction,
            l.limit,
            100.0 * l.rel_error,
            l.expected,
            if l.monotone { "yes" } else { "NO" }
        );
    }
    s
}

/// Prints the study's table, the limits as eps_n → ∞, the runs' warnings and where its files
/// went (`dir`).
pub fn print_report(report: &PenaltyReport, dir: &Path) {
    print!("{}", table(&report.summary));
    print!("{}", limit_lines(&report.limits));
    crate::runner::print_warnings(&report.warnings);
    println!("\n{} files written to {}", report.files.len(), dir.display());
}

#[cfg(test)]
mod tests {
    use super::rows::tests::{scene, synthetic};
    use super::*;

    #[test]
    fn files_have_the_documented_headers() {
        let dir = std::env::temp_dir().join(format!("compare-penalty-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (s, out) = (scene(), synthetic());
        let p = write_rows(&dir.join("penalty_summary.csv"), &[summary(300, &s, &out)]).unwrap();
        let text = std::fs::read_to_string(p).unwrap();
        assert!(text.starts_with(
            "eps_factor,max_penetration_over_2a_at_0.6T,mean_normal_before_onset,rel_error_normal,\
             mean_tangential_while_slipping,rel_error_tangential\n"
        ));
        let p = write_rows(&dir.join("penalty_means.csv"), &mean_rows(300, &s, &out)).unwrap();
        let text = std::fs::read_to_string(p).unwrap();
        assert!(text.starts_with(
            "eps_factor,t,t_over_T,mean_normal_traction,mean_tangential_traction,max_penetration_over_2a\n"
        ));
        let pngs = penalty_figures(
            &dir,
            &Expected::of(&s),
            &face_rows(300, &s, &out),
            &mean_rows(300, &s, &out),
        );
        assert_eq!(pngs.unwrap().len(), 3);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_empty_window_prints_as_a_dash() {
        let mut out = synthetic();
        out.faces.iter_mut().for_each(|f| f.tangential_traction = 0.0);
        assert!(table(&[summary(100, &scene(), &out)]).contains('—'));
    }

    #[test]
    fn every_factor_is_validated_before_any_run() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
        let study = Study::load(&path).unwrap();
        let plans = plan(&study, &[100, 1000]).unwrap();
        assert_eq!(plans[1].1.fem.eps_n, 1000.0 * 70e6);
        assert!(
            plan(&study, &[300, 300])
                .unwrap_err()
                .to_string()
                .contains("twice")
        );
        let e = format!("{:#}", plan(&study, &[300, 0]).unwrap_err());
        assert!(e.contains("0 E per metre") && e.contains("fem.eps_n"), "{e}");
    }
}
