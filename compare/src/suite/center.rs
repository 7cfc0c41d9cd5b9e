//! The suite's first case: the centre crack of the comparison (`scenes/center-crack.toml`, the
//! paper's model in both models), with the comparison's own metrics and tolerances (docs/outputs.md:
//! at paper resolution, and those of `converged` with `--fine`).
//!
//! With a folder where that comparison already ran (`--gate DIR`: `compare --out DIR`, or
//! `compare converged --out DIR` with `--fine`), the metrics are computed again from its tip files,
//! so that a session that has just run the comparison does not run it twice. Without one, the suite
//! runs the comparison into its own folder `center-crack/`.

use super::SuiteRow;
use crate::gate::metrics::{CONVERGED, MuRuns, PAPER_RESOLUTION, Verdict, verdicts};
use crate::output::mu_tag;
use crate::runner::Reporter;
use crate::series::TipRow;
use crate::study::Study;
use anyhow::{Context, Result};
use std::path::Path;

/// The case's name in `suite.csv`.
pub const NAME: &str = "center-crack";

/// The centre crack's study at the suite's resolution (the converged one with `fine`).
pub fn study(scene: &Path, fine: bool) -> Result<Study> {
    let study = Study::load(scene)?;
    if fine {
        study.at_resolution(crate::converged::ELEMENT_SIZE)
    } else {
        Ok(study)
    }
}

/// Runs the comparison of `study` into `dir` and returns its metrics.
pub fn run(study: &Study, fine: bool, dir: &Path, rep: &dyn Reporter) -> Result<Vec<SuiteRow>> {
    let report = crate::gate::run_gate(study, tolerances(fine), dir, rep)?;
    Ok(rows(&report.verdicts))
}

/// The metrics of `study` from the tip files (`fem_mu*.csv`, `spectral_mu*.csv`) of a comparison
/// that ran into `dir`.
pub fn from_folder(study: &Study, fine: bool, dir: &Path) -> Result<Vec<SuiteRow>> {
    let mut runs = Vec::new();
    for mu in study.friction_coeffs()? {
        let read = |model: &str| -> Result<Vec<TipRow>> {
            let path = dir.join(format!("{model}_mu{}.csv", mu_tag(mu)));
            let rows: Result<Vec<TipRow>, csv::Error> = csv::Reader::from_path(&path)
                .with_context(|| format!("--gate: reading {}", path.display()))?
                .into_deserialize()
                .collect();
            rows.with_context(|| format!("--gate: reading {}", path.display()))
        };
        runs.push(MuRuns {
            mu,
            fem: read("fem")?,
            spectral: read("spectral")?,
        });
    }
    Ok(rows(&verdicts(&study.case(), &runs, tolerances(fine))))
}

fn tolerances(fine: bool) -> &'static crate::gate::metrics::Tolerances {
    if fine { &CONVERGED } else { &PAPER_RESOLUTION }
}

/// The comparison's verdicts as rows of `suite.csv` (metric `METRIC@MU`).
fn rows(verdicts: &[Verdict]) -> Vec<SuiteRow> {
    verdicts
        .iter()
        .map(|v| SuiteRow {
            case: NAME.to_string(),
            metric: format!("{}@{}", v.metric, v.mu),
            value: v.value,
            tolerance: v.tolerance.clone(),
            pass: v.pass,
        })
        .collect()
}
