//! The speed/accuracy trade: each model at four resolutions, each point in its own child
//! process so that its wall time and peak memory (VmHWM) are its own.
//!
//! FE: h ≈ 4, 2, 1, 0.5 mm, rounded to h = a/round(a/h) so the pre-crack tips and the domain
//! edges stay on nodes (4 mm → a/31 = 4.03 mm). Spectral: the power-of-two N nearest to X/h
//! (N = 1024 … 8192 for X = 30a), at the FE time step of the same point. `--sizes` sweeps other
//! nominal sizes.
//!
//! The points run as children of `compare sweep`, or anywhere else: [`scale_out`] writes them out
//! as independent jobs and reads their results back.

#[cfg(feature = "cli")]
pub mod cli;
pub mod scale_out;

use crate::runner::{Job, Keep, Reporter, fem_tips, run_fem, run_spectral, spectral_tips};
use crate::series::{Series, mean_speed, onset};
use crate::study::Study;
use anyhow::{Context, Result, anyhow};
use serde::{Deserialize, Serialize};

/// Nominal FE element sizes of the sweep [m], coarse to fine.
pub const NOMINAL_SIZES: [f64; 4] = [4e-3, 2e-3, 1e-3, 0.5e-3];

/// One value of `--sizes`: a nominal element size [m], finite and > 0 (the command line's
/// parser, so that its error names the option).
pub fn parse_size(text: &str) -> Result<f64, String> {
    let h: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("{text:?} is not a number; give sizes in metres, e.g. 4e-3,2e-3"))?;
    if h.is_finite() && h > 0.0 {
        Ok(h)
    } else {
        Err(format!("{h} is not a size; give finite sizes > 0 m"))
    }
}

/// The nominal sizes [m] of `--sizes` ordered coarse to fine, once each: a size listed twice,
/// or two sizes whose points would share files, are refused naming the option.
pub fn sizes(given: &[f64]) -> Result<Vec<f64>> {
    anyhow::ensure!(!given.is_empty(), "--sizes: give at least one size [m]");
    for (k, &h) in given.iter().enumerate() {
        anyhow::ensure!(
            h.is_finite() && h > 0.0,
            "--sizes: {h} is not a size; give finite sizes > 0 m"
        );
        if let Some(&g) = given[..k]
            .iter()
            .find(|&&g| point_tag(Model::Fem, g) == point_tag(Model::Fem, h))
        {
            if g == h {
                anyhow::bail!("--sizes: {h} is listed twice (each point writes its own files)");
            }
            anyhow::bail!(
                "--sizes: {g} and {h} m would write the same files ({}); give sizes further apart",
                point_tag(Model::Fem, h)
            );
        }
    }
    let mut sorted = given.to_vec();
    sorted.sort_by(|a, b| b.total_cmp(a));
    Ok(sorted)
}

/// The name of a point in its file names: `<model>_<nominal h in mm>mm` (`fem_4mm`, `spectral_0.5mm`).
pub fn point_tag(model: Model, nominal: f64) -> String {
    format!("{}_{}mm", model.tag(), nominal * 1e3)
}

/// The label of a point in messages: `sweep fem h = 0.004 m`.
pub fn point_label(model: Model, nominal: f64) -> String {
    format!("sweep {} h = {nominal} m", model.tag())
}

/// Which model a sweep point runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Model {
    /// The FE hybrid model.
    Fem,
    /// The spectral boundary-integral model.
    Spectral,
}

impl Model {
    /// Lower-case name, as on the command line and in file names.
    pub fn tag(self) -> &'static str {
        match self {
            Model::Fem => "fem",
            Model::Spectral => "spectral",
        }
    }
}

/// One measured point, a row of `sweep.csv`; the error columns are NaN until [`with_errors`]
/// fills them.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Point {
    /// Model.
    pub model: Model,
    /// Nominal FE element size of the point [m].
    pub nominal_size: f64,
    /// Actual grid spacing: FE element size or spectral Δx [m].
    pub spacing: f64,
    /// Time step [s].
    pub time_step: f64,
    /// Wall time of the run [s].
    pub wall_s: f64,
    /// Peak resident memory of the process [bytes] (Linux VmHWM).
    pub peak_memory_bytes: f64,
    /// Onset time [s] (half-length advance of 0.05 a).
    pub onset: f64,
    /// Mean tip speed between 1.2a and 1.9a [m/s].
    pub mean_speed: f64,
    /// |onset − onset_finest| / T [-].
    pub onset_error_over_t: f64,
    /// |v − v_finest| / v_finest [-].
    pub speed_error_rel: f64,
    /// Why the onset or the speed is NaN (e.g. "tip never reached 1.9a"); empty when measured.
    pub note: String,
}

fn peak_memory_bytes() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.split_whitespace().next()?.parse::<f64>().ok())
        .map_or(f64::NAN, |kib| kib * 1024.0)
}

/// Every point's study (FE, then spectral, at each nominal size [m] of `sizes` in its order),
/// validated before any run.
pub fn plan(study: &Study, sizes: &[f64]) -> Result<Vec<(Model, f64, Study)>> {
    study.spectral()?;
    let mut out = Vec::new();
    for model in [Model::Fem, Model::Spectral] {
        for &h in sizes {
            let point = study.at_resolution(h)?;
            if model == Model::Spectral {
                point
                    .spectral()?
                    .with_time_step(point.fem.time_step())
                    .with_context(|| format!("the spectral model at the FE step of h = {h} m"))?;
            }
            out.push((model, h, point));
        }
    }
    Ok(out)
}

/// Every point of `plan` against the study's budget, and the output folder claimed, before the
/// first child starts.
pub fn preflight(
    study: &Study,
    plan: &[(Model, f64, Study)],
    dir: &std::path::Path,
) -> Result<(crate::runner::Plan, preflight::paths::Claim)> {
    let labels: Vec<String> = plan.iter().map(|(m, h, _)| point_label(*m, *h)).collect();
    let spectral_scenes = plan
        .iter()
        .filter(|(m, _, _)| *m == Model::Spectral)
        .map(|(_, _, p)| Ok(p.spectral()?.with_time_step(p.fem.time_step())?))
        .collect::<Result<Vec<_>>>()?;
    let fems: Vec<(&str, &fem::Scene)> = labels
        .iter()
        .zip(plan)
        .filter(|(_, (m, _, _))| *m == Model::Fem)
        .map(|(l, (_, _, p))| (l.as_str(), &p.fem))
        .collect();
    let spectrals: Vec<(&str, &spectral::Scene)> = labels
        .iter()
        .zip(plan)
        .filter(|(_, (m, _, _))| *m == Model::Spectral)
        .map(|(l, _)| l.as_str())
        .zip(&spectral_scenes)
        .collect();
    crate::runner::preflight(study, &fems, &spectrals, dir)
}

/// Runs one point in this process (the child side of the sweep) at the scene's own friction
/// coefficient and writes its tip history to `<dir>/tips_<model>_<nominal h in mm>mm.csv`
/// (header `t,tip_right,tip_left,cz_tip_right,cz_tip_left`). A run that goes unstable keeps its
/// full output in `<dir>/<model>_<h>mm/` and fails the point.
pub fn run_point(
    study: &Study,
    model: Model,
    nominal: f64,
    dir: &std::path::Path,
    rep: &dyn Reporter,
) -> Result<Point> {
    let point = study.at_resolution(nominal)?;
    let case = point.case();
    let dt = point.fem.time_step();
    let tag = point_tag(model, nominal);
    let sub = dir.join(&tag);
    let (tips, spacing, wall_s) = match model {
        Model::Fem => {
            let job = Job {
                scene: &point.fem,
                label: &tag,
                dir: &sub,
                keep: Keep::OnFailure,
            };
            let f = run_fem(job, rep)?;
            f.warnings.iter().for_each(|w| eprintln!("warning: {w}"));
            let wall = f.wall_s;
            (fem_tips(&f.completed()?), point.fem.fem.element_size, wall)
        }
        Model::Spectral => {
            let scene = point.spectral()?.with_time_step(dt)?;
            let job = Job {
                scene: &scene,
                label: &tag,
                dir: &sub,
                keep: Keep::OnFailure,
            };
            let f = run_spectral(job, rep)?;
            let wall = f.wall_s;
            (spectral_tips(&f.completed()?), scene.grid_spacing(), wall)
        }
    };
    std::fs::create_dir_all(dir)?;
    crate::output::write_rows(&dir.join(format!("tips_{tag}.csv")), &tips)?;
    let l = Series::half_length(&tips);
    Ok(Point {
        model,
        nominal_size: nominal,
        spacing,
        time_step: dt,
        wall_s,
        peak_memory_bytes: peak_memory_bytes(),
        onset: onset(&l, case.half_length).unwrap_or(f64::NAN),
        mean_speed: mean_speed(&l, case.half_length).unwrap_or(f64::NAN),
        note: crate::gate::metrics::lacks(model.tag(), &l, case.half_length, true).unwrap_or_default(),
        onset_error_over_t: f64::NAN,
        speed_error_rel: f64::NAN,
    })
}

/// Errors of every point against the finest point of its model.
pub fn with_errors(points: &[Point], duration: f64) -> Vec<Point> {
    points
        .iter()
        .map(|p| {
            let finest = points
                .iter()
                .filter(|q| q.model == p.model)
                .min_by(|a, b| a.spacing.total_cmp(&b.spacing))
                .expect("invariant: p itself is in the list");
            Point {
                onset_error_over_t: (p.onset - finest.onset).abs() / duration,
                speed_error_rel: (p.mean_speed - finest.mean_speed).abs() / finest.mean_speed,
                note: if p.note.is_empty() && !finest.note.is_empty() {
                    format!("errors against the finest point, whose {}", finest.note)
                } else {
                    p.note.clone()
                },
                ..p.clone()
            }
        })
        .collect()
}

/// The arguments of `compare sweep-point` for one point, after `--scene`, `--out` and
/// `--result`: the model, the nominal size [m] and the budget of the run (the in-process sweep
/// and the emitted jobs run exactly these).
pub fn point_args(model: Model, nominal: f64, budget: preflight::Budget) -> Vec<String> {
    vec![
        "--model".into(),
        model.tag().into(),
        "--size".into(),
        nominal.to_string(),
        "--max-memory".into(),
        (budget.max_bytes as f64 / (1u64 << 30) as f64).to_string(),
        "--max-steps".into(),
        budget.max_steps.to_string(),
    ]
}

/// Runs every point of `plan` as a child `compare sweep-point` process of the executable `exe`,
/// in the plan's order; `on_point` sees each point as it arrives.
pub fn run_children(
    exe: &std::path::Path,
    scene: &std::path::Path,
    dir: &std::path::Path,
    budget: preflight::Budget,
    plan: &[(Model, f64, Study)],
    stop: &std::sync::atomic::AtomicBool,
    on_point: &mut dyn FnMut(&Point),
) -> Result<Vec<Point>> {
    let mut points = Vec::new();
    let mut done = Vec::new();
    for &(model, h, _) in plan {
        let label = point_label(model, h);
        let child = std::process::Command::new(exe)
            .arg("sweep-point")
            .arg("--scene")
            .arg(scene)
            .arg("--out")
            .arg(dir)
            .args(point_args(model, h, budget))
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::inherit())
            .spawn()
            .with_context(|| format!("starting {}", exe.display()))?;
        let (status, stdout, stopped) =
            wait_forwarding_stop(child, stop).with_context(|| format!("{label}: waiting for its process"))?;
        if stopped {
            return Err(stopped_sweep(&label, &dir.join(point_tag(model, h)), &done));
        }
        if !status.success() {
            return Err(anyhow!("{label} failed ({status})"));
        }
        let p = read_point(&stdout).with_context(|| format!("{label}: reading its result"))?;
        done.push(dir.join(format!("tips_{}.csv", point_tag(model, h))));
        on_point(&p);
        points.push(p);
    }
    Ok(points)
}

/// Waits for a sweep point's process; when `stop` is raised (Ctrl-C, SIGTERM to this process
/// only, as `kill` sends it) the child is sent SIGTERM, so that it stops at its next step and
/// writes its partial output, rather than running on to T. Returns its exit status, its stdout
/// and whether the sweep was stopped.
fn wait_forwarding_stop(
    mut child: std::process::Child,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<(std::process::ExitStatus, Vec<u8>, bool)> {
    use std::io::Read;
    let mut pipe = child
        .stdout
        .take()
        .ok_or_else(|| anyhow!("invariant: the child's stdout is piped"))?;
    // the child's answer is one CSV row: read on a thread so that a full pipe never blocks it
    let reader = std::thread::spawn(move || {
        let mut buf = Vec::new();
        pipe.read_to_end(&mut buf).map(|_| buf)
    });
    let mut forwarded = false;
    let status = loop {
        if let Some(status) = child.try_wait()? {
            break status;
        }
        if !forwarded && stop.load(std::sync::atomic::Ordering::Relaxed) {
            let pid = libc::pid_t::try_from(child.id()).context("child process id")?;
            // SAFETY: kill(2) on our own, not yet reaped child with a valid signal has no
            // memory effects.
            unsafe { libc::kill(pid, libc::SIGTERM) };
            forwarded = true;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    let stdout = reader
        .join()
        .map_err(|_| anyhow!("invariant: reading a pipe does not panic"))??;
    let stopped = forwarded || stop.load(std::sync::atomic::Ordering::Relaxed);
    Ok((status, stdout, stopped))
}

/// A sweep stopped on request: the point that was running and where its partial output went,
/// and the tip files of the points done before it.
fn stopped_sweep(label: &str, partial: &std::path::Path, done: &[std::path::PathBuf]) -> anyhow::Error {
    let before = if done.is_empty() {
        "no point had finished".to_string()
    } else {
        let names: Vec<String> = done.iter().map(|p| p.display().to_string()).collect();
        format!("the points done before it are in {}", names.join(", "))
    };
    anyhow!(
        "sweep stopped on request during {label}; its output up to there is in {}; {before}; \
         sweep.csv is not written",
        partial.display()
    )
}

/// One point as CSV (header + row): what a point prints on stdout or writes to its result file.
pub fn point_csv(p: &Point) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.serialize(p)?;
    w.into_inner().map_err(|e| anyhow!("{e}"))
}

/// The point of [`point_csv`]'s text: exactly one row, each number one a run can give (a point
/// file is read back from disk or from a child process: a damaged or edited one must not carry
/// NaN or inf into sweep.csv and the figure).
pub fn read_point(csv_text: &[u8]) -> Result<Point> {
    let mut rows = csv::Reader::from_reader(csv_text).into_deserialize::<Point>();
    let p = rows.next().ok_or_else(|| anyhow!("no point in it"))??;
    anyhow::ensure!(rows.next().is_none(), "more than one point in it");
    p.check()?;
    Ok(p)
}

impl Point {
    /// Refuses a number no run gives, naming its column: sizes and step finite and positive, the
    /// wall time finite and not negative; the onset and the speed finite, or NaN with the note
    /// saying why; the errors and the peak memory finite and not negative, or NaN (not
    /// measured); inf nowhere.
    fn check(&self) -> Result<()> {
        let positive = [
            ("nominal_size", self.nominal_size),
            ("spacing", self.spacing),
            ("time_step", self.time_step),
        ];
        for (name, v) in positive {
            anyhow::ensure!(v.is_finite() && v > 0.0, "{name} = {v}: a finite number > 0");
        }
        anyhow::ensure!(
            self.wall_s.is_finite() && self.wall_s >= 0.0,
            "wall_s = {}: a finite number >= 0",
            self.wall_s
        );
        for (name, v) in [("onset", self.onset), ("mean_speed", self.mean_speed)] {
            anyhow::ensure!(
                v.is_finite() || (v.is_nan() && !self.note.is_empty()),
                "{name} = {v}: a finite number, or NaN with a note saying why"
            );
        }
        for (name, v) in [
            ("peak_memory_bytes", self.peak_memory_bytes),
            ("onset_error_over_t", self.onset_error_over_t),
            ("speed_error_rel", self.speed_error_rel),
        ] {
            anyhow::ensure!(
                v.is_nan() || (v.is_finite() && v >= 0.0),
                "{name} = {v}: a finite number >= 0, or NaN (not measured)"
            );
        }
        Ok(())
    }
}

/// Prints one point as CSV (header + row) on stdout: the child's answer to its parent.
pub fn print_point(p: &Point) -> Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(&point_csv(p)?)?;
    out.flush()?;
    Ok(())
}

/// Writes `sweep.csv` and `sweep_error_vs_wall_time.png` (log–log axes) into `dir`.
pub fn write_results(dir: &std::path::Path, rows: &[Point]) -> Result<Vec<std::path::PathBuf>> {
    use crate::plot::{Curve, Dash, Labels, LineChart, LogAxes, draw};
    std::fs::create_dir_all(dir)?;
    let csv_path = crate::output::write_rows(&dir.join("sweep.csv"), rows)?;
    let mut curves = Vec::new();
    for (i, (model, name)) in [(Model::Fem, "FE"), (Model::Spectral, "spectral")]
        .into_iter()
        .enumerate()
    {
        let pick = |f: fn(&Point) -> f64| -> Vec<(f64, f64)> {
            rows.iter()
                .filter(|r| r.model == model)
                .map(|r| (r.wall_s, f(r)))
                .collect()
        };
        curves.push(Curve::nth(
            format!("{name}: onset error / T"),
            pick(|r| r.onset_error_over_t),
            i,
            Dash::Solid,
        ));
        curves.push(Curve::nth(
            format!("{name}: mean-speed rel. error"),
            pick(|r| r.speed_error_rel),
            i,
            Dash::Dashed,
        ));
    }
    let png = dir.join("sweep_error_vs_wall_time.png");
    let chart = LineChart {
        labels: Labels {
            title: "Error against the finest run of each model, against the run's cost",
            x: "wall time [s]",
            y: "error [-]",
        },
        curves: &curves,
        marks: &[],
        shading: None,
        log: LogAxes { x: true, y: true },
        y_range: None,
    };
    draw(&png, &chart)?;
    Ok(vec![csv_path, png])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point file with inf or an unexplained NaN is refused naming the column, so that it cannot
    /// flow into sweep.csv and the figure; a NaN onset with its note, as a run writes it, is read.
    #[test]
    fn a_point_with_a_number_no_run_gives_is_refused_naming_it() {
        let good = Point {
            model: Model::Fem,
            nominal_size: 1e-3,
            spacing: 1e-3,
            time_step: 1e-6,
            wall_s: 1.0,
            peak_memory_bytes: 1e6,
            onset: f64::NAN,
            mean_speed: 100.0,
            onset_error_over_t: f64::NAN,
            speed_error_rel: f64::NAN,
            note: "tip never moved 0.05a".into(),
        };
        assert!(read_point(&point_csv(&good).unwrap()).is_ok());
        type Damage = fn(&mut Point);
        let cases: [(&str, Damage); 5] = [
            ("wall_s = inf", |p| p.wall_s = f64::INFINITY),
            ("time_step = NaN", |p| p.time_step = f64::NAN),
            ("mean_speed = inf", |p| p.mean_speed = f64::INFINITY),
            ("onset = NaN: a finite number, or NaN with a note", |p| {
                p.note.clear()
            }),
            ("speed_error_rel = -inf", |p| {
                p.speed_error_rel = f64::NEG_INFINITY
            }),
        ];
        for (message, damage) in cases {
            let mut p = good.clone();
            damage(&mut p);
            let e = read_point(&point_csv(&p).unwrap()).unwrap_err().to_string();
            assert!(e.contains(message), "{message}: {e}");
        }
    }

    #[test]
    fn errors_are_measured_against_the_finest_point_of_each_model() {
        let p = |model, spacing, onset, mean_speed| Point {
            model,
            nominal_size: spacing,
            spacing,
            time_step: 1e-6,
            wall_s: 1.0,
            peak_memory_bytes: 1.0,
            onset,
            mean_speed,
            onset_error_over_t: f64::NAN,
            speed_error_rel: f64::NAN,
            note: String::new(),
        };
        let rows = with_errors(
            &[
                p(Model::Fem, 2e-3, 0.012, 120.0),
                p(Model::Fem, 1e-3, 0.011, 125.0),
                p(Model::Spectral, 1e-3, 0.0, 1.0),
            ],
            0.02,
        );
        assert!((rows[0].onset_error_over_t - 0.05).abs() < 1e-12);
        assert!((rows[0].speed_error_rel - 0.04).abs() < 1e-12);
        assert_eq!(rows[1].onset_error_over_t, 0.0);
        assert_eq!(rows[2].speed_error_rel, 0.0);
        // a finest point that never ran gives NaN errors, each with the reason
        let mut stalled = p(Model::Fem, 0.5e-3, f64::NAN, f64::NAN);
        stalled.note = "fem tip never reached 1.9a".into();
        let rows = with_errors(&[p(Model::Fem, 1e-3, 0.011, 125.0), stalled], 0.02);
        assert!(rows[0].onset_error_over_t.is_nan());
        assert!(
            rows[0].note.contains("finest point") && rows[0].note.contains("1.9a"),
            "{}",
            rows[0].note
        );
    }

    #[test]
    fn results_are_written_as_csv_and_png() {
        let p = |model, spacing, onset| Point {
            model,
            nominal_size: spacing,
            spacing,
            time_step: 1e-6,
            wall_s: spacing * 1e4,
            peak_memory_bytes: 1e6,
            onset,
            mean_speed: 120.0 + onset,
            onset_error_over_t: f64::NAN,
            speed_error_rel: f64::NAN,
            note: String::new(),
        };
        let pts = [
            p(Model::Fem, 2e-3, 0.012),
            p(Model::Fem, 1e-3, 0.011),
            p(Model::Spectral, 1e-3, 0.01),
        ];
        let dir = std::env::temp_dir().join(format!("compare-sweep-test-{}", std::process::id()));
        let files = write_results(&dir, &with_errors(&pts, 0.02)).unwrap();
        let text = std::fs::read_to_string(&files[0]).unwrap();
        assert!(
            text.starts_with("model,nominal_size,spacing,time_step,wall_s,"),
            "{text}"
        );
        assert_eq!(text.lines().count(), 4);
        assert!(std::fs::metadata(&files[1]).unwrap().len() > 1000);
    }
}
