//! The onset agreement once the FE model has converged: the FE-versus-spectral comparison at
//! h = 0.5 mm (the spectral model on the matching power-of-two grid, at the FE step), where the
//! onsets must agree within 0.01 T for every friction value. At the paper's h = 1 mm the FE onset
//! is still 0.005 T from converged, which is why the default gate allows 0.015 T there.

use crate::gate::metrics::CONVERGED;
use crate::gate::{GateReport, run_gate};
use crate::output::write_rows;
use crate::runner::Reporter;
use crate::series::{Series, mean_speed, onset};
use crate::study::Study;
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Nominal FE element size of the converged comparison [m] (half the paper's).
pub const ELEMENT_SIZE: f64 = 0.5e-3;

/// One friction value of the converged comparison (`converged.csv`; the committed copy in
/// `reference/` is what the validation test reproduces).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ConvergedRow {
    /// Friction coefficient μ [-].
    pub mu: f64,
    /// FE element size h [m].
    pub fem_element_size: f64,
    /// Spectral grid spacing Δx [m].
    pub spectral_grid_spacing: f64,
    /// Onset of the FE crack [s] (half-length advance of 0.05 a).
    pub fem_onset: f64,
    /// Onset of the spectral crack [s], unshifted.
    pub spectral_onset: f64,
    /// |t_on,FE − (t_on,SBI + a/c_d)| / T [-].
    pub onset_difference_over_t: f64,
    /// FE mean tip speed between 1.2a and 1.9a [m/s].
    pub fem_mean_speed: f64,
    /// Spectral mean tip speed between 1.2a and 1.9a [m/s].
    pub spectral_mean_speed: f64,
}

/// The converged comparison's report and its per-μ rows.
#[derive(Debug, Clone)]
pub struct ConvergedReport {
    /// The comparison at h = 0.5 mm (tolerances of [`CONVERGED`]).
    pub gate: GateReport,
    /// One row per friction value.
    pub rows: Vec<ConvergedRow>,
}

/// Runs the comparison of `study` at h = [`ELEMENT_SIZE`] into `dir`, with `converged.csv`.
pub fn run_converged(study: &Study, dir: &Path, rep: &dyn Reporter) -> Result<ConvergedReport> {
    let fine = study.at_resolution(ELEMENT_SIZE)?;
    let mut gate = run_gate(&fine, &CONVERGED, dir, rep)?;
    let c = gate.case;
    let rows: Vec<ConvergedRow> = gate
        .runs
        .iter()
        .map(|r| {
            let (f, s) = (Series::half_length(&r.fem), Series::half_length(&r.spectral));
            let (tf, ts) = (
                onset(&f, c.half_length).unwrap_or(f64::NAN),
                onset(&s, c.half_length).unwrap_or(f64::NAN),
            );
            ConvergedRow {
                mu: r.mu,
                fem_element_size: gate.spacing.0,
                spectral_grid_spacing: gate.spacing.1,
                fem_onset: tf,
                spectral_onset: ts,
                onset_difference_over_t: (tf - (ts + c.shift())).abs() / c.duration,
                fem_mean_speed: mean_speed(&f, c.half_length).unwrap_or(f64::NAN),
                spectral_mean_speed: mean_speed(&s, c.half_length).unwrap_or(f64::NAN),
            }
        })
        .collect();
    gate.files.push(write_rows(&dir.join("converged.csv"), &rows)?);
    Ok(ConvergedReport { gate, rows })
}
