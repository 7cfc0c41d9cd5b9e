//! The two models as the harness sees them: scene text in, crack-tip rows out. `compare`
//! reaches `fem` and `spectral` only through `Scene::from_toml_str`, `run_with_progress` and
//! the output records (docs/solver-api.md).

use crate::align::TipRow;
use crate::scene::with_overrides;
use anyhow::{Context, Result};
use toml::Value;

/// Scale quantities of a scene, taken from the FE model's validated scene.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// Pre-crack half-length a [m].
    pub half_length: f64,
    /// Pre-crack centre x [m].
    pub center_x: f64,
    /// Run duration T [s].
    pub duration: f64,
    /// Dilatational wave speed c_d [m/s].
    pub cd: f64,
    /// Rayleigh wave speed c_R [m/s].
    pub cr: f64,
    /// Far-field normal stress after its ramp, s_yy [Pa] (negative in compression).
    pub normal_stress: f64,
}

impl Case {
    /// The a/c_d time shift [s] applied to the spectral curves (paper Figure 7b): the time a
    /// dilatational wave needs from the FE model's top boundary (y = a) to the crack plane.
    pub fn shift(&self) -> f64 {
        self.half_length / self.cd
    }
}

fn friction(mu: f64) -> (&'static str, Option<Value>) {
    ("friction.friction_coeff", Some(Value::Float(mu)))
}

/// The FE scene for friction coefficient `mu`.
pub fn fem_scene(text: &str, mu: f64) -> Result<fem::Scene> {
    let text = with_overrides(text, &[friction(mu)])?;
    fem::Scene::from_toml_str(&text).context("FE model: invalid scene")
}

/// The spectral scene for friction `mu`, run with the FE model's time step `dt` [s]
/// (paper §3.2: "a time step Δt_crit equal to the one used for the Finite Element simulations").
pub fn spectral_scene(text: &str, mu: f64, dt: f64) -> Result<spectral::Scene> {
    let text = with_overrides(
        text,
        &[
            friction(mu),
            ("spectral.cs_dt_over_dx", None),
            ("spectral.time_step", Some(Value::Float(dt))),
        ],
    )?;
    spectral::Scene::from_toml_str(&text).context("spectral model: invalid scene")
}

/// Scale quantities of the problem in `text`.
pub fn case(text: &str) -> Result<Case> {
    let scene = fem_scene(text, 0.0)?;
    let table: toml::Table = text.parse()?;
    let normal_stress = table
        .get("loading")
        .and_then(|l| l.get("normal"))
        .and_then(|n| n.get("final"))
        .and_then(Value::as_float)
        .unwrap_or(0.0);
    let w = scene.wave_speeds();
    Ok(Case {
        half_length: scene.half_length(),
        center_x: scene.center_x(),
        duration: scene.duration(),
        cd: w.cd,
        cr: w.cr,
        normal_stress,
    })
}

/// A model's tip records as harness rows (both crates' `TipRecord`s have the same fields).
macro_rules! tip_rows {
    ($records:expr) => {
        $records
            .iter()
            .map(|r| TipRow {
                t: r.t,
                tip_right: r.tip_right,
                tip_left: r.tip_left,
                cz_tip_right: r.cz_tip_right,
                cz_tip_left: r.cz_tip_left,
            })
            .collect()
    };
}

/// Tip rows of an FE run.
pub fn fem_tips(out: &fem::RunOutput) -> Vec<TipRow> {
    tip_rows!(out.tips)
}

/// Tip rows of a spectral run.
pub fn spectral_tips(out: &spectral::RunOutput) -> Vec<TipRow> {
    tip_rows!(out.tips)
}
