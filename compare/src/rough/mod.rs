//! Paper Section 5 outlook: the standard against the hybrid model on a self-affine rough weak
//! interface (`fem.interface_rough`), with the runs, metrics, CSVs and figures of the sinusoid
//! study ([`crate::sinusoid`]) on the rough scene.

use crate::runner::Reporter;
use crate::study::Study;
use anyhow::Result;
use std::path::Path;

/// The study's scene in scenes/ (the default of `compare rough`).
pub const SCENE: &str = "rough-interface.toml";

/// Runs every model of `study` (a scene with `fem.interface_rough`) into `dir` as the sinusoid
/// study does ([`crate::sinusoid::run_study`]) and prints its end; true when no run went
/// unstable (an unstable run's output is kept).
pub fn run(study: &Study, dir: &Path, rep: &dyn Reporter) -> Result<bool> {
    let report = crate::sinusoid::run_study(study, dir, rep)?;
    Ok(crate::sinusoid::print_report(&report, dir))
}
