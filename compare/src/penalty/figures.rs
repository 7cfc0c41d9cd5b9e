//! Figure D.15 of the paper from the penalty study's rows: (a) upper-face interpenetration at
//! t/T = 0.6, (b) mean normal and (c) mean tangential contact traction against time, one curve
//! per penalty factor. Draws what it is given.

use super::rows::{FaceRow, MeanRow, PROFILE_TIME_OVER_T};
use crate::plot::{self, Curve, Dash, Labels, Mark};
use anyhow::Result;
use plotters::style::BLACK;
use std::path::{Path, PathBuf};

/// The scale quantities and expected values the figures need.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Expected {
    /// Pre-crack half-length a [m].
    pub half_length: f64,
    /// Pre-crack centre x_c [m].
    pub center_x: f64,
    /// Far-field compression after its ramp, |s_yy| [Pa].
    pub normal_stress: f64,
    /// Friction coefficient μ [-].
    pub friction_coeff: f64,
}

impl Expected {
    /// The quantities of `scene`.
    pub fn of(scene: &fem::Scene) -> Expected {
        Expected {
            half_length: scene.half_length(),
            center_x: scene.center_x(),
            normal_stress: scene.loading.normal.final_value.abs(),
            friction_coeff: scene.friction_coeff,
        }
    }
}

/// Factors in the order they first appear.
fn factors(ids: impl Iterator<Item = u32>) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    for f in ids {
        if !out.contains(&f) {
            out.push(f);
        }
    }
    out
}

fn label(factor: u32) -> String {
    format!("ε_n = ε_t = {factor} E/m")
}

/// Draws Figures D.15a–c into `dir`; returns the files written.
pub fn penalty_figures(
    dir: &Path,
    e: &Expected,
    faces: &[FaceRow],
    means: &[MeanRow],
) -> Result<Vec<PathBuf>> {
    Ok(vec![
        profile(dir, e, faces)?,
        traction(dir, e, means, Component::Normal)?,
        traction(dir, e, means, Component::Tangential)?,
    ])
}

fn profile(dir: &Path, e: &Expected, faces: &[FaceRow]) -> Result<PathBuf> {
    let curves: Vec<Curve> = factors(faces.iter().map(|r| r.eps_factor))
        .into_iter()
        .enumerate()
        .map(|(i, f)| {
            let pts = faces
                .iter()
                .filter(|r| r.eps_factor == f)
                .map(|r| ((r.x - e.center_x) / e.half_length, 100.0 * r.penetration_over_2a))
                .collect();
            Curve::nth(label(f), pts, i, Dash::Solid)
        })
        .collect();
    let p = dir.join("figD15a_penetration_profile.png");
    let title = format!(
        "FE interpenetration on the upper face at t/T = {PROFILE_TIME_OVER_T}, μ = {}",
        e.friction_coeff
    );
    let labels = Labels {
        title: &title,
        x: "(x − x_c)/a [-]",
        y: "penetration / 2a [%]",
    };
    plot::line_chart(&p, labels, &curves, &[])?;
    Ok(p)
}

/// Which mean traction a chart shows.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Component {
    Normal,
    Tangential,
}

fn traction(dir: &Path, e: &Expected, means: &[MeanRow], c: Component) -> Result<PathBuf> {
    let value = |r: &MeanRow| match c {
        Component::Normal => r.mean_normal_traction,
        Component::Tangential => r.mean_tangential_traction,
    };
    let curves: Vec<Curve> = factors(means.iter().map(|r| r.eps_factor))
        .into_iter()
        .enumerate()
        .map(|(i, f)| {
            let pts = means
                .iter()
                .filter(|r| r.eps_factor == f)
                .map(|r| (r.t_over_t, value(r) / 1e6))
                .collect();
            Curve::nth(label(f), pts, i, Dash::Solid)
        })
        .collect();
    let s_yy = e.normal_stress / 1e6;
    let (name, what, mark) = match c {
        Component::Normal => (
            "figD15b_mean_normal_traction.png",
            "normal",
            Mark::Horizontal(s_yy, BLACK, format!("|s_yy| = {s_yy} MPa")),
        ),
        Component::Tangential => (
            "figD15c_mean_tangential_traction.png",
            "tangential",
            Mark::Horizontal(
                e.friction_coeff * s_yy,
                BLACK,
                format!("μ|s_yy| = {:.4} MPa", e.friction_coeff * s_yy),
            ),
        ),
    };
    let p = dir.join(name);
    let title = format!(
        "FE mean {what} contact traction on the upper face, μ = {}",
        e.friction_coeff
    );
    let labels = Labels {
        title: &title,
        x: "t/T [-]",
        y: "traction [MPa]",
    };
    plot::line_chart(&p, labels, &curves, &[mark])?;
    Ok(p)
}
