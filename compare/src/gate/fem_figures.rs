//! FE-only figures of the paper's Section 3 for one friction value: damage (Fig. 5b),
//! interpenetration (6a), traction ratio (6b), mean contact tractions (6c), energies (B.14a) and
//! the Appendix B ratio E_kin/E_int with its quasi-static estimate.

use crate::output::write_rows;
use crate::plot::{self, Curve, Dash, Field, Labels, LineChart, LogAxes, Mark, Scale};
use crate::quasi_static::{LIMIT, RATIO_AXIS, max_ratio, ratio_rows};
use crate::series::{Series, onset};
use crate::study::Case;
use anyhow::Result;
use plotters::style::{BLACK, RGBColor};
use std::path::{Path, PathBuf};

/// Start of the phase Appendix B is tested in, t/T [-]: the end of the normal ramp, after which
/// the compression is held; the phase ends at the onset of propagation.
pub const QUASI_STATIC_FROM_OVER_T: f64 = 0.2;

fn finite_max(values: impl Iterator<Item = f64>) -> f64 {
    values.filter(|v| v.is_finite()).fold(0.0, f64::max)
}

fn space_time_labels(title: &str) -> Labels<'_> {
    Labels {
        title,
        x: "(x − x_c)/a [-]",
        y: "t/T [-]",
    }
}

/// Draws Figures 5b, 6a, 6b, 6c, B.14a and the Appendix B ratio for the FE run `out` of `scene`
/// into `dir`.
pub fn fem_figures(
    dir: &Path,
    case: &Case,
    scene: &fem::Scene,
    out: &fem::RunOutput,
) -> Result<Vec<PathBuf>> {
    let mu = scene.friction_coeff;
    let field = |samples: &mut dyn Iterator<Item = (f64, f64, f64)>| {
        Field::from_samples(
            samples,
            |x| (x - case.center_x) / case.half_length,
            |t| t / case.duration,
        )
    };
    let mut written = Vec::new();

    let damage = field(
        &mut out
            .interface
            .iter()
            .map(|r| (r.t, r.x, if r.inserted { r.damage } else { f64::NAN })),
    );
    let p = dir.join("fig5b_damage_space_time.png");
    let title = format!("FE damage, μ = {mu} (grey: no cohesive element)");
    plot::space_time(
        &p,
        space_time_labels(&title),
        &damage,
        &Scale::new(0.0, 1.0, "damage d [-]"),
        &[],
    )?;
    written.push(p);

    let pct = 100.0 / (2.0 * case.half_length);
    let pen = field(&mut out.faces.iter().map(|r| (r.t, r.x, r.penetration * pct)));
    let top = finite_max(pen.values.iter().flatten().copied()).max(1e-6);
    let p = dir.join("fig6a_penetration_space_time.png");
    let title = format!("FE interpenetration on the upper face, μ = {mu}");
    plot::space_time(
        &p,
        space_time_labels(&title),
        &pen,
        &Scale::new(0.0, top, "g/(2a) [%]"),
        &[],
    )?;
    written.push(p);

    let ratio = field(&mut out.faces.iter().map(|r| {
        let v = if r.normal_traction > 0.0 {
            r.tangential_traction / r.normal_traction
        } else {
            f64::NAN
        };
        (r.t, r.x, v)
    }));
    let p = dir.join("fig6b_traction_ratio_space_time.png");
    let title = format!("FE ‖T_t‖/‖T_n‖ on the upper face, μ = {mu} (grey: no contact)");
    let top = (2.0 * mu).max(0.1);
    // the pre-crack's stick-to-slip line, as the paper draws it (the new faces behind the running
    // tips stick for a few samples after they first touch, which the field itself shows)
    let mut slip = first_slip(&ratio, mu);
    slip.retain(|r| r.x_over_a.abs() < 1.0);
    let guide = Curve {
        label: format!("stick → slip on the pre-crack, ‖T_t‖/‖T_n‖ = μ = {mu}"),
        points: slip.iter().map(|r| (r.x_over_a, r.t_over_t)).collect(),
        color: RGBColor(255, 255, 255),
        dash: Dash::Solid,
    };
    plot::space_time(
        &p,
        space_time_labels(&title),
        &ratio,
        &Scale::new(0.0, top, "‖T_t‖/‖T_n‖ [-]"),
        if mu > 0.0 {
            std::slice::from_ref(&guide)
        } else {
            &[]
        },
    )?;
    written.push(p);
    if mu > 0.0 {
        written.push(write_rows(&dir.join("fig6b_first_slip.csv"), &slip)?);
    }

    written.push(mean_tractions(dir, case, mu, out)?);
    written.push(energies(dir, case, mu, out)?);
    written.extend(energy_ratio(dir, case, scene, out)?);
    Ok(written)
}

/// One point of the stick-to-slip boundary of Figure 6b (`fig6b_first_slip.csv`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FirstSlip {
    /// Node position (x − x_c)/a [-].
    pub x_over_a: f64,
    /// First sample time at which the node's ‖T_t‖/‖T_n‖ reaches μ, t/T [-].
    pub t_over_t: f64,
}

/// The line the paper's Figure 6b draws in white, ‖T_t‖/‖T_n‖ = μ, where the faces go from stick
/// to slip: per node (column of the ratio field, x increasing) the first sample at which its
/// ratio reaches μ (to 1e-9, the return map's slip condition), for every node that stuck in
/// contact before (a finite ratio below μ at an earlier sample). Nodes that never slip, and new
/// faces that slip from their first contact on, have no stick-to-slip transition and are left
/// out.
pub fn first_slip(ratio: &Field, mu: f64) -> Vec<FirstSlip> {
    let slips = |v: f64| v >= (1.0 - 1e-9) * mu;
    (0..ratio.x.len())
        .filter_map(|j| {
            let i = ratio.values.iter().position(|row| slips(row[j]))?;
            let stuck = ratio.values[..i].iter().any(|row| row[j].is_finite());
            stuck.then_some(FirstSlip {
                x_over_a: ratio.x[j],
                t_over_t: ratio.t[i],
            })
        })
        .collect()
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
        Mark::Horizontal(expected, BLACK, format!("|s_yy| = {expected} MPa")),
        Mark::Horizontal(
            mu * expected,
            RGBColor(120, 120, 120),
            format!("μ|s_yy| = {:.4} MPa", mu * expected),
        ),
    ];
    let curves = [
        Curve::nth("mean normal traction", normal, 0, Dash::Solid),
        Curve::nth("mean tangential traction", tangential, 1, Dash::Solid),
    ];
    let p = dir.join("fig6c_mean_tractions.png");
    let title = format!("FE mean contact tractions on the upper face, μ = {mu}");
    let labels = Labels {
        title: &title,
        x: "t/T [-]",
        y: "traction [MPa]",
    };
    plot::line_chart(&p, labels, &curves, &marks)?;
    Ok(p)
}

fn energies(dir: &Path, case: &Case, mu: f64, out: &fem::RunOutput) -> Result<PathBuf> {
    let tt = |t: f64| t / case.duration;
    let kinetic = out.energy.iter().map(|r| (tt(r.t), r.kinetic)).collect();
    let strain = out.energy.iter().map(|r| (tt(r.t), r.strain)).collect();
    let curves = [
        Curve::nth("kinetic E_kin", kinetic, 0, Dash::Solid),
        Curve::nth("internal (strain) E_int", strain, 1, Dash::Solid),
    ];
    let p = dir.join("figB14a_energies.png");
    let title = format!("FE kinetic and internal energy, μ = {mu}");
    let labels = Labels {
        title: &title,
        x: "t/T [-]",
        y: "energy per unit thickness [J/m]",
    };
    plot::line_chart(&p, labels, &curves, &[])?;
    Ok(p)
}

/// The tested phase of Appendix B for the centre crack: [0.2 T, onset] [s]; `None` without onset.
pub fn quasi_static_window(case: &Case, out: &fem::RunOutput) -> Option<(f64, f64)> {
    let tips = crate::runner::fem_tips(out);
    let t_on = onset(&Series::half_length(&tips), case.half_length)?;
    Some((QUASI_STATIC_FROM_OVER_T * case.duration, t_on))
}

fn energy_ratio(dir: &Path, case: &Case, scene: &fem::Scene, out: &fem::RunOutput) -> Result<Vec<PathBuf>> {
    let mu = scene.friction_coeff;
    let rows = ratio_rows(&format!("FE μ = {mu}"), scene, out);
    let measured = rows
        .iter()
        .map(|r| (r.t_over_t, r.kinetic_over_internal))
        .collect();
    let estimate = rows
        .iter()
        .map(|r| (r.t_over_t, r.quasi_static_estimate))
        .collect();
    let whole = max_ratio(out, 0.0, f64::INFINITY).map_or(f64::NAN, |m| m.0);
    let mut marks = vec![Mark::Horizontal(
        LIMIT,
        BLACK,
        format!("{} % (App. B)", 100.0 * LIMIT),
    )];
    let window = quasi_static_window(case, out);
    let phase = match window.and_then(|(t0, t1)| max_ratio(out, t0, t1).map(|m| (t0, t1, m))) {
        Some((t0, t1, (m, at))) => {
            marks.push(Mark::Vertical(t0 / case.duration, BLACK));
            marks.push(Mark::Vertical(t1 / case.duration, BLACK));
            format!(
                "0.2 T to onset (dashed) at most {:.2} % at t/T = {:.3}",
                100.0 * m,
                at / case.duration
            )
        }
        None => "no onset: the tested phase is empty".to_string(),
    };
    let curves = [
        Curve::nth(
            format!("measured: {phase}; whole run at most {:.0} %", 100.0 * whole),
            measured,
            0,
            Dash::Solid,
        ),
        Curve::nth("the imposed quasi-static motion alone", estimate, 1, Dash::Dashed),
    ];
    let title = format!("Kinetic over internal energy, FE μ = {mu} (Appendix B, Figure B.14a)");
    let p = dir.join("figB14a_energy_ratio.png");
    let chart = LineChart {
        labels: Labels {
            title: &title,
            x: "t/T [-]",
            y: "E_kin/E_int [-]",
        },
        curves: &curves,
        marks: &marks,
        shading: None,
        log: LogAxes { x: false, y: true },
        y_range: Some(RATIO_AXIS),
    };
    plot::draw(&p, &chart)?;
    Ok(vec![p, write_rows(&dir.join("figB14a_energy_ratio.csv"), &rows)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each node's first sample at μ after sticking: a node whose ratio rises linearly crosses μ
    /// where it should; one without contact (NaN), or one that slips from its first contact on
    /// (no stick before), is left out.
    #[test]
    fn the_first_slip_line_marks_each_node_where_its_ratio_reaches_mu() {
        let t: Vec<f64> = (0..11).map(|k| 0.1 * k as f64).collect();
        let ratio = Field {
            x: vec![-0.5, 0.0, 0.5, 1.5],
            values: t
                .iter()
                .map(|&t| {
                    vec![
                        0.6 * t,
                        f64::NAN,
                        if t >= 0.35 { 0.3 } else { 0.1 },
                        if t >= 0.75 { 0.3 } else { f64::NAN },
                    ]
                })
                .collect(),
            t,
        };
        let line = first_slip(&ratio, 0.3);
        assert_eq!(
            line,
            [
                FirstSlip {
                    x_over_a: -0.5,
                    t_over_t: 0.5
                },
                FirstSlip {
                    x_over_a: 0.5,
                    t_over_t: 0.4
                },
            ]
        );
        assert!(first_slip(&ratio, 0.9).is_empty());
    }
}
