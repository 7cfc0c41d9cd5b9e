//! The time-history figures of the Section 4 comparison, one curve per model: residual stress
//! (paper eq. 17, Figure 12), crack-tip and cohesive-zone-tip positions against the far-field
//! shear (Figure E.16), E_kin/E_strain (Appendix B, Figure B.14b) and the KKT-violation metric.
//! Plotted data not already in the model folders also go to a CSV.

use super::metrics::{QUASI_STATIC_AFTER_ONSET_OVER_T, SinusoidSummary};
use super::setup::{ModelRun, Setup};
use crate::output::write_rows;
use crate::plot::{self, Curve, Dash, Labels, LineChart, LogAxes, Mark, PALETTE};
use crate::quasi_static::{LIMIT, RATIO_AXIS, ratio_rows};
use anyhow::Result;
use plotters::style::{BLACK, RGBColor};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The KKT-violation shares the Section 4 claims draw on: hybrid ≤ 1 %, standard ≥ 2 % [-].
pub const KKT_SHARE_LINES: [f64; 2] = [0.01, 0.02];

/// One tip sample against the far-field shear (`figE16_tips_vs_shear.csv`).
#[derive(Debug, Clone, Serialize)]
pub struct TipShearRow {
    /// Model name.
    pub model: String,
    /// Time [s].
    pub t: f64,
    /// Far-field shear σ_xy^∞(t) [Pa].
    pub shear_stress: f64,
    /// Right crack tip (x − x_c)/a [-].
    pub tip_right_over_a: f64,
    /// Right cohesive-zone tip (x − x_c)/a [-].
    pub cz_tip_right_over_a: f64,
}

/// The Figure E.16 rows of one run.
pub fn tip_shear_rows(setup: &Setup, run: &ModelRun) -> Vec<TipShearRow> {
    run.out
        .tips
        .iter()
        .map(|r| TipShearRow {
            model: run.model.clone(),
            t: r.t,
            shear_stress: setup.shear.value(r.t),
            tip_right_over_a: setup.x_over_a(r.tip_right),
            cz_tip_right_over_a: setup.x_over_a(r.cz_tip_right),
        })
        .collect()
}

/// Vertical marks at `time(summary)`/T in each run's colour (skipped where NaN).
fn time_marks(
    setup: &Setup,
    summaries: &[SinusoidSummary],
    time: impl Fn(&SinusoidSummary) -> f64,
) -> Vec<Mark> {
    summaries
        .iter()
        .enumerate()
        .map(|(i, s)| (time(s) / setup.duration, PALETTE[i % PALETTE.len()]))
        .filter(|(t, _)| t.is_finite())
        .map(|(t, c)| Mark::Vertical(t, c))
        .collect()
}

/// One solid curve per run, labelled with its model, from `f(run)`.
fn per_run(runs: &[ModelRun], f: impl Fn(&ModelRun) -> Vec<(f64, f64)>) -> Vec<Curve> {
    runs.iter()
        .enumerate()
        .map(|(i, r)| Curve::nth(r.model.clone(), f(r), i, Dash::Solid))
        .collect()
}

fn chart(dir: &Path, name: &str, labels: Labels, curves: &[Curve], marks: &[Mark]) -> Result<PathBuf> {
    let p = dir.join(name);
    plot::line_chart(&p, labels, curves, marks)?;
    Ok(p)
}

/// Draws the time-history figures into `dir`; returns the files written.
/// `summaries[i]` is the summary of `runs[i]` (marks of the slip and onset times).
/// `scenes[i]` is the scene `runs[i]` ran (the quasi-static estimate of Appendix B).
pub fn time_figures(
    dir: &Path,
    setup: &Setup,
    scenes: &[(&str, fem::Scene)],
    runs: &[ModelRun],
    summaries: &[SinusoidSummary],
) -> Result<Vec<PathBuf>> {
    let big_t = setup.duration;
    let mut files = Vec::new();
    let residual = per_run(runs, |r| {
        r.out
            .residual_stress
            .iter()
            .map(|s| (s.t / big_t, s.residual_stress / 1e3))
            .collect()
    });
    let labels = Labels {
        title: "Residual stress on the right weak branch (paper eq. 17, Figure 12)",
        x: "t/T [-]",
        y: "mean shear-direction residual stress, eq. (17) [kPa]",
    };
    files.push(chart(dir, "fig12_residual_stress.png", labels, &residual, &[])?);
    files.extend(tips_vs_shear(dir, setup, runs)?);
    files.extend(energy_ratio(dir, setup, scenes, runs, summaries)?);
    files.extend(kkt_figures(dir, setup, runs, summaries)?);
    Ok(files)
}

fn kkt_figures(
    dir: &Path,
    setup: &Setup,
    runs: &[ModelRun],
    summaries: &[SinusoidSummary],
) -> Result<Vec<PathBuf>> {
    let big_t = setup.duration;
    let slip_marks = time_marks(setup, summaries, |s| s.t_slip_2h);
    let share = per_run(runs, |r| {
        r.out
            .kkt
            .iter()
            .map(|k| (k.t / big_t, 100.0 * k.violating_share))
            .collect()
    });
    let mut marks = slip_marks.clone();
    marks.extend(
        KKT_SHARE_LINES
            .iter()
            .zip([RGBColor(0, 120, 0), BLACK])
            .map(|(&s, c)| Mark::Horizontal(100.0 * s, c, format!("{} %", 100.0 * s))),
    );
    let labels = Labels {
        title: "Crack-face nodes violating KKT (dashed verticals: twin-pair slip > 2h)",
        x: "t/T [-]",
        y: "KKT-violating share of crack-face nodes [%]",
    };
    let share_png = chart(dir, "kkt_share.png", labels, &share, &marks)?;
    let traction = per_run(runs, |r| {
        r.out
            .kkt
            .iter()
            .map(|k| (k.t / big_t, k.max_violating_traction / 1e3))
            .collect()
    });
    let labels = Labels {
        title: "Largest compressive traction on an open crack-face node (dashed: slip > 2h)",
        x: "t/T [-]",
        y: "largest violating traction [kPa]",
    };
    Ok(vec![
        share_png,
        chart(dir, "kkt_max_traction.png", labels, &traction, &slip_marks)?,
    ])
}

fn tips_vs_shear(dir: &Path, setup: &Setup, runs: &[ModelRun]) -> Result<Vec<PathBuf>> {
    let mut rows = Vec::new();
    let mut curves = Vec::new();
    for (i, r) in runs.iter().enumerate() {
        let rs = tip_shear_rows(setup, r);
        let pts = |f: fn(&TipShearRow) -> f64| rs.iter().map(|s| (s.shear_stress / 1e6, f(s))).collect();
        curves.push(Curve::nth(
            format!("{}: crack tip", r.model),
            pts(|s| s.tip_right_over_a),
            i,
            Dash::Solid,
        ));
        curves.push(Curve::nth(
            format!("{}: cohesive-zone tip", r.model),
            pts(|s| s.cz_tip_right_over_a),
            i,
            Dash::Dashed,
        ));
        rows.extend(rs);
    }
    let junction = setup.x_over_a(setup.weak_right[1]);
    let marks = [Mark::Horizontal(
        junction,
        BLACK,
        format!("weak/strong junction x = {junction}a"),
    )];
    let labels = Labels {
        title: "Right crack tip and cohesive-zone tip against the far-field shear (Figure E.16)",
        x: "far-field shear σ_xy [MPa]",
        y: "(x − x_c)/a [-]",
    };
    Ok(vec![
        chart(dir, "figE16_tips_vs_shear.png", labels, &curves, &marks)?,
        write_rows(&dir.join("figE16_tips_vs_shear.csv"), &rows)?,
    ])
}

fn energy_ratio(
    dir: &Path,
    setup: &Setup,
    scenes: &[(&str, fem::Scene)],
    runs: &[ModelRun],
    summaries: &[SinusoidSummary],
) -> Result<Vec<PathBuf>> {
    let mut rows = Vec::new();
    let mut curves = Vec::new();
    for (i, (r, (_, scene))) in runs.iter().zip(scenes).enumerate() {
        let rs = ratio_rows(&r.model, scene, &r.out);
        let pts = rs.iter().map(|e| (e.t_over_t, e.kinetic_over_internal)).collect();
        curves.push(Curve::nth(format!("{}: measured", r.model), pts, i, Dash::Solid));
        rows.extend(rs);
    }
    if let Some((_, scene)) = scenes.first() {
        let estimate = rows
            .iter()
            .filter(|e| e.run == runs[0].model)
            .map(|e| {
                (
                    e.t_over_t,
                    crate::quasi_static::estimate(scene, e.t_over_t * setup.duration),
                )
            })
            .collect();
        curves.push(Curve::nth(
            "imposed quasi-static motion alone",
            estimate,
            5,
            Dash::Dashed,
        ));
    }
    let delay = QUASI_STATIC_AFTER_ONSET_OVER_T * setup.duration;
    let mut marks = time_marks(setup, summaries, |s| s.onset + delay);
    marks.push(Mark::Horizontal(
        LIMIT,
        BLACK,
        format!("{} % (App. B)", 100.0 * LIMIT),
    ));
    for (c, s) in curves.iter_mut().zip(summaries) {
        c.label = format!(
            "{}: from onset + 0.05 T (dashed) to T at most {:.1} %; whole run {:.0} %",
            s.model,
            100.0 * s.max_kinetic_over_internal_quasi_static,
            100.0 * s.max_kinetic_over_internal
        );
    }
    let title = "Kinetic over internal energy (Appendix B, Figure B.14b)";
    let chart = LineChart {
        labels: Labels {
            title,
            x: "t/T [-]",
            y: "E_kin/E_int [-]",
        },
        curves: &curves,
        marks: &marks,
        shading: None,
        log: LogAxes { x: false, y: true },
        y_range: Some(RATIO_AXIS),
    };
    let png = dir.join("figB14b_energy_ratio.png");
    plot::draw(&png, &chart)?;
    Ok(vec![
        png,
        write_rows(&dir.join("figB14b_energy_ratio.csv"), &rows)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;
    use fem::{EnergyRecord, KktRecord, ResidualStressRecord, RunOutput, TipRecord};

    use crate::sinusoid::setup::tests::setup;

    /// 20 samples over T; the crack grows from a after t = T/2.
    fn run(model: &str, share: f64) -> ModelRun {
        let s = setup();
        let (a, big_t) = (s.half_length, s.duration);
        let t = |k: usize| big_t * k as f64 / 19.0;
        let tip = |k: usize| a * (1.0 + (t(k) / big_t - 0.5).max(0.0));
        let energy = |k: usize| EnergyRecord {
            t: t(k),
            kinetic: 1e-3 * k as f64,
            strain: if k == 0 { 0.0 } else { 1.0 },
            ..EnergyRecord::default()
        };
        ModelRun {
            model: model.into(),
            out: RunOutput {
                tips: (0..20)
                    .map(|k| TipRecord {
                        t: t(k),
                        tip_right: tip(k),
                        tip_left: -tip(k),
                        cz_tip_right: tip(k) + 0.01,
                        cz_tip_left: -tip(k) - 0.01,
                    })
                    .collect(),
                energy: (0..20).map(energy).collect(),
                residual_stress: (0..20)
                    .map(|k| ResidualStressRecord {
                        t: t(k),
                        residual_stress: 100.0 * k as f64,
                    })
                    .collect(),
                kkt: (0..20)
                    .map(|k| KktRecord {
                        t: t(k),
                        crack_face_nodes: 100,
                        compressive_nodes: 10,
                        violating_nodes: (100.0 * share) as usize,
                        violating_share: share,
                        max_violating_traction: 1e3,
                        mismatch_nodes: 5,
                        max_slip: s.element_size * k as f64 / 5.0,
                    })
                    .collect(),
                ..RunOutput::default()
            },
            wall_s: 1.0,
            failure: None,
        }
    }

    #[test]
    fn time_figures_render_and_write_their_data() {
        let dir = std::env::temp_dir().join(format!("compare-sinusoid-fig-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let s = setup();
        let runs = [run("standard", 0.2), run("hybrid", 0.0)];
        let summaries: Vec<_> = runs.iter().map(|r| super::super::setup::row(&s, r).0).collect();
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/sinusoidal-interface.toml");
        let scene = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        let scenes = [("standard", scene.clone()), ("hybrid", scene)];
        let files = time_figures(&dir, &s, &scenes, &runs, &summaries).unwrap();
        let names: Vec<String> = files
            .iter()
            .map(|f| f.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            [
                "fig12_residual_stress.png",
                "figE16_tips_vs_shear.png",
                "figE16_tips_vs_shear.csv",
                "figB14b_energy_ratio.png",
                "figB14b_energy_ratio.csv",
                "kkt_share.png",
                "kkt_max_traction.png"
            ]
        );
        let text = std::fs::read_to_string(dir.join("figE16_tips_vs_shear.csv")).unwrap();
        assert!(text.starts_with("model,t,shear_stress,tip_right_over_a,cz_tip_right_over_a\n"));
        // the shear is the scene's ramp: 0 at t = 0, its final value at T
        let last = text.lines().nth(20).unwrap();
        assert!(last.starts_with("standard,"), "{last}");
        let shear: f64 = last.split(',').nth(2).unwrap().parse().unwrap();
        assert!((shear - s.shear.value(s.duration)).abs() < 1e-9 * shear.abs());
        let text = std::fs::read_to_string(dir.join("figB14b_energy_ratio.csv")).unwrap();
        assert!(text.starts_with("run,t_over_T,kinetic_over_internal,quasi_static_estimate\n"));
        assert_eq!(
            text.lines().count(),
            1 + 2 * 19,
            "samples without strain energy are left out"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
