//! FE-only figures of the paper's Section 3 for one friction value: damage (Fig. 5b),
//! interpenetration (6a), traction ratio (6b), mean contact tractions (6c), energies (B.14a).

use crate::figures::{field_from, reference, scale, space_time_labels, time_curve};
use crate::models::Case;
use crate::plot::{self, Labels};
use anyhow::Result;
use plotters::style::{BLACK, RGBColor};
use std::path::{Path, PathBuf};

fn finite_max(values: impl Iterator<Item = f64>) -> f64 {
    values.filter(|v| v.is_finite()).fold(0.0, f64::max)
}

/// Draws Figures 5b, 6a, 6b, 6c and B.14a for the FE run `out` at friction `mu` into `dir`.
pub fn fem_figures(dir: &Path, case: &Case, mu: f64, out: &fem::RunOutput) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();

    let damage = field_from(
        out.interface
            .iter()
            .map(|r| (r.t, r.x, if r.inserted { r.damage } else { f64::NAN })),
        case,
    );
    let p = dir.join("fig5b_damage_space_time.png");
    let title = format!("FE damage, μ = {mu} (grey: no cohesive element)");
    plot::space_time(
        &p,
        space_time_labels(&title),
        &damage,
        &scale(0.0, 1.0, "damage d [-]"),
    )?;
    written.push(p);

    let pct = 100.0 / (2.0 * case.half_length);
    let pen = field_from(out.faces.iter().map(|r| (r.t, r.x, r.penetration * pct)), case);
    let top = finite_max(pen.values.iter().flatten().copied()).max(1e-6);
    let p = dir.join("fig6a_penetration_space_time.png");
    let title = format!("FE interpenetration on the upper face, μ = {mu}");
    plot::space_time(
        &p,
        space_time_labels(&title),
        &pen,
        &scale(0.0, top, "g/(2a) [%]"),
    )?;
    written.push(p);

    let ratio = field_from(
        out.faces.iter().map(|r| {
            let v = if r.normal_traction > 0.0 {
                r.tangential_traction / r.normal_traction
            } else {
                f64::NAN
            };
            (r.t, r.x, v)
        }),
        case,
    );
    let p = dir.join("fig6b_traction_ratio_space_time.png");
    let title = format!("FE ‖T_t‖/‖T_n‖ on the upper face, μ = {mu} (grey: no contact)");
    let top = (2.0 * mu).max(0.1);
    plot::space_time(
        &p,
        space_time_labels(&title),
        &ratio,
        &scale(0.0, top, "‖T_t‖/‖T_n‖ [-]"),
    )?;
    written.push(p);

    written.push(mean_tractions(dir, case, mu, out)?);
    written.push(energies(dir, case, mu, out)?);
    Ok(written)
}

fn mean_tractions(dir: &Path, case: &Case, mu: f64, out: &fem::RunOutput) -> Result<PathBuf> {
    let tt = |t: f64| t / case.duration;
    let normal = out
        .contact
        .iter()
        .map(|r| (tt(r.t), r.mean_normal_traction / 1e6))
        .collect();
    let tangential = out
        .contact
        .iter()
        .map(|r| (tt(r.t), r.mean_tangential_traction / 1e6))
        .collect();
    let expected = case.normal_stress.abs() / 1e6;
    let marks = [
        reference(expected, BLACK, format!("|s_yy| = {expected} MPa")),
        reference(
            mu * expected,
            RGBColor(120, 120, 120),
            format!("μ|s_yy| = {:.4} MPa", mu * expected),
        ),
    ];
    let curves = [
        time_curve("mean normal traction", normal, 0),
        time_curve("mean tangential traction", tangential, 1),
    ];
    let p = dir.join("fig6c_mean_tractions.png");
    let title = format!("FE mean contact tractions on the upper face, μ = {mu}");
    plot::line_chart(
        &p,
        Labels {
            title: &title,
            x: "t/T [-]",
            y: "traction [MPa]",
        },
        &curves,
        &marks,
    )?;
    Ok(p)
}

fn energies(dir: &Path, case: &Case, mu: f64, out: &fem::RunOutput) -> Result<PathBuf> {
    let tt = |t: f64| t / case.duration;
    let kinetic = out.energy.iter().map(|r| (tt(r.t), r.kinetic)).collect();
    let strain = out.energy.iter().map(|r| (tt(r.t), r.strain)).collect();
    let curves = [
        time_curve("kinetic E_kin", kinetic, 0),
        time_curve("internal (strain) E_int", strain, 1),
    ];
    let p = dir.join("figB14a_energies.png");
    let title = format!("FE kinetic and internal energy, μ = {mu}");
    plot::line_chart(
        &p,
        Labels {
            title: &title,
            x: "t/T [-]",
            y: "energy per unit thickness [J/m]",
        },
        &curves,
        &[],
    )?;
    Ok(p)
}
