//! ParaView field output (`[fem.paraview]`): the files hold the run's own state, the collection
//! lists every snapshot in time order, a bad interval is refused before any work, the CSV records
//! do not change when fields are on, and VTK itself reads the files (`tests/vtk/check_fields.py`,
//! run when Python's `vtk` module is there; required when `CI_REQUIRE_VTK=1`).
//!
//! One small centre crack (contact with friction, cohesive insertion) is run once for the tests
//! that read its files; samples and snapshots share their interval, so each snapshot has records
//! of the same step to compare with.

use fem::output::paraview::read_vtu;
use fem::records::fields::{FieldPiece, FieldValues};
use fem::{FieldSink, FieldSnapshot, ParaviewWriter, RunOutput, Scene};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;
use std::sync::atomic::AtomicBool;

const PROBES: &str = "probes = [[0.005, 0.003], [-0.012, -0.002]]";

fn scene_text(fields: bool) -> String {
    let base = preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), "tiny-fem-center-crack");
    let text = base.replace(
        "output_interval = 1e-5          # s",
        &format!("output_interval = 5e-5\n{PROBES}"),
    );
    assert_ne!(text, base, "the scene's output_interval line changed");
    if fields {
        format!("{text}\n[fem.paraview]\ninterval = 5e-5\n")
    } else {
        text
    }
}

struct Run {
    scene: Scene,
    out: RunOutput,
    dir: PathBuf,
}

/// The scene run once with fields on, its files in `dir`.
fn with_fields() -> &'static Run {
    static RUN: OnceLock<Run> = OnceLock::new();
    RUN.get_or_init(|| {
        let scene = Scene::from_toml_str(&scene_text(true)).unwrap();
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("paraview-fields");
        let _ = std::fs::remove_dir_all(&dir);
        let steps = fem::estimate(&scene).steps;
        let mut writer = ParaviewWriter::new(&dir, steps).unwrap();
        let out =
            fem::run_with_fields(&scene, &mut |_, _| {}, &AtomicBool::new(false), Some(&mut writer)).unwrap();
        writer.finish().unwrap();
        Run { scene, out, dir }
    })
}

/// (time [s], bulk file, crack file) of each `<DataSet>` pair of `fields.pvd`, in file order.
fn collection(dir: &Path) -> Vec<(f64, PathBuf, PathBuf)> {
    let text = std::fs::read_to_string(dir.join("fields.pvd")).unwrap();
    let attr = |line: &str, name: &str| -> String {
        let start = line.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        line[start..].split('"').next().unwrap().to_string()
    };
    let entries: Vec<(f64, String, PathBuf)> = text
        .lines()
        .filter(|l| l.trim_start().starts_with("<DataSet"))
        .map(|l| {
            (
                attr(l, "timestep").parse().unwrap(),
                attr(l, "part"),
                dir.join(attr(l, "file")),
            )
        })
        .collect();
    entries
        .chunks(2)
        .map(|pair| {
            assert_eq!(pair.len(), 2, "a snapshot without its crack piece");
            assert_eq!((pair[0].1.as_str(), pair[1].1.as_str()), ("0", "1"));
            assert_eq!(
                pair[0].0, pair[1].0,
                "the two parts of a snapshot at different times"
            );
            (pair[0].0, pair[0].2.clone(), pair[1].2.clone())
        })
        .collect()
}

fn scalars<'p>(values: Option<&'p FieldValues>, name: &str) -> &'p [f64] {
    match values {
        Some(FieldValues::Scalars(v)) => v,
        other => panic!("{name}: {other:?}"),
    }
}

fn vectors<'p>(values: Option<&'p FieldValues>, name: &str) -> &'p [[f64; 2]] {
    match values {
        Some(FieldValues::Vectors(v)) => v,
        other => panic!("{name}: {other:?}"),
    }
}

/// Index of the point at reference position (x, y) (the first: − copy on the interface row).
fn point_at(piece: &FieldPiece, x: f64, y: f64) -> usize {
    piece
        .points
        .iter()
        .position(|p| p[0] == x && p[1] == y)
        .unwrap_or_else(|| panic!("no point at ({x}, {y})"))
}

#[test]
fn the_files_hold_the_state_the_records_saw() {
    // The files are binary float64 and the snapshot is computed from the same state at the same
    // step as the sample's records, by the same formulas for the contact fields: the values must
    // be equal to the last bit, so the tolerance is zero.
    let run = with_fields();
    let snaps = collection(&run.dir);
    let sample_times: Vec<f64> = run.out.tips.iter().map(|r| r.t).collect();
    let snapshot_times: Vec<f64> = snaps.iter().map(|s| s.0).collect();
    assert_eq!(snapshot_times, sample_times, "one snapshot per sample");
    let h = run.scene.fem.element_size;
    let x0 = run.scene.fem.x_range[0];
    let (mut damaged, mut pressed) = (0, 0);
    for (t, bulk_file, crack_file) in &snaps {
        let bulk = read_vtu(bulk_file).unwrap();
        let u = vectors(bulk.point_array("displacement"), "displacement");
        let v = vectors(bulk.point_array("velocity"), "velocity");
        let probes: Vec<_> = run.out.probes.iter().filter(|p| p.t == *t).collect();
        assert_eq!(probes.len(), 2, "t = {t}");
        for p in probes {
            let k = point_at(&bulk, p.x, p.y);
            assert_eq!(
                (u[k], v[k]),
                ([p.ux, p.uy], [p.vx, p.vy]),
                "probe {} at t = {t}",
                p.probe
            );
        }
        let crack = read_vtu(crack_file).unwrap();
        let np = crack.points.len() / 2;
        let nf = crack.num_cells() / 2;
        // damage: the mean of the facet's two Gauss points of interface.csv, on both faces
        let damage = scalars(crack.cell_array("damage"), "damage");
        let records: Vec<_> = run.out.interface.iter().filter(|r| r.t == *t).collect();
        for pair in records.chunks(2) {
            let c = ((pair[0].x - x0) / h).floor() as usize;
            let mean = 0.5 * (pair[0].damage + pair[1].damage);
            assert_eq!((damage[c], damage[nf + c]), (mean, mean), "facet {c} at t = {t}");
            damaged += usize::from(mean > 0.0);
        }
        // contact at the upper-face nodes: faces.csv; the + copies are the second half of the points
        let normal = scalars(crack.point_array("contact_normal_traction"), "normal");
        let tangential = scalars(crack.point_array("contact_tangential_traction"), "tangential");
        let penetration = scalars(crack.point_array("contact_penetration"), "penetration");
        for f in run.out.faces.iter().filter(|f| f.t == *t) {
            let k = np + ((f.x - x0) / h).round() as usize;
            assert_eq!(crack.points[k][0], f.x);
            assert_eq!(
                (normal[k], tangential[k], penetration[k]),
                (f.normal_traction, f.tangential_traction, f.penetration),
                "x = {} at t = {t}",
                f.x
            );
            pressed += usize::from(f.normal_traction > 0.0);
        }
    }
    // not vacuous: the run inserts cohesive elements and presses the pre-crack faces together
    assert!(damaged > 0 && pressed > 0, "damaged {damaged}, pressed {pressed}");
}

#[test]
fn the_collection_lists_every_snapshot_in_time_order() {
    let run = with_fields();
    let snaps = collection(&run.dir);
    let p = run.scene.fem.paraview.unwrap();
    let dt = run.scene.time_step();
    assert_eq!(snaps.len() as u64, p.count(dt, run.out.steps));
    assert_eq!(snaps[0].0, 0.0);
    assert!(snaps.windows(2).all(|w| w[1].0 > w[0].0), "times must increase");
    // the last one is the final state, T rounded up to a whole step (f64 sums of dt: 1e-12 of T)
    let last = snaps.last().unwrap().0;
    assert!((last - run.out.steps as f64 * dt).abs() <= 1e-12 * last, "{last}");
    for (_, bulk, crack) in &snaps {
        assert!(bulk.is_file() && crack.is_file(), "{}", bulk.display());
    }
    let files = std::fs::read_dir(run.dir.join("fields")).unwrap().count();
    assert_eq!(files, 2 * snaps.len(), "fields/ holds exactly the listed files");
}

#[test]
fn the_csv_records_do_not_change_with_fields_on() {
    let run = with_fields();
    let off = fem::run(&Scene::from_toml_str(&scene_text(false)).unwrap()).unwrap();
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("paraview-csv");
    let _ = std::fs::remove_dir_all(&root);
    let on_files = fem::write_csv(&run.out, &root.join("on")).unwrap();
    let off_files = fem::write_csv(&off, &root.join("off")).unwrap();
    assert_eq!(on_files.len(), off_files.len());
    for (a, b) in on_files.iter().zip(&off_files) {
        assert_eq!(a.file_name(), b.file_name());
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{} differs with fields on",
            a.display()
        );
    }
    assert!(!root.join("off").join("fields.pvd").exists());
}

#[test]
fn a_snapshot_that_cannot_be_written_stops_the_run_with_the_records_kept() {
    struct Full;
    impl FieldSink for Full {
        fn snapshot(&mut self, s: FieldSnapshot) -> std::io::Result<()> {
            if s.step > 0 {
                return Err(std::io::Error::other("no space left on device"));
            }
            Ok(())
        }
    }
    let scene = Scene::from_toml_str(&scene_text(true)).unwrap();
    let e =
        fem::run_with_fields(&scene, &mut |_, _| {}, &AtomicBool::new(false), Some(&mut Full)).unwrap_err();
    let fem::RunError::FieldOutput {
        step,
        message,
        partial,
        ..
    } = e
    else {
        panic!("expected FieldOutput: {e}");
    };
    let every = scene.fem.paraview.unwrap().every(scene.time_step());
    assert_eq!(step, every, "stopped at the first snapshot after t = 0");
    assert!(message.contains("no space left"), "{message}");
    assert_eq!(partial.steps, every);
    assert!(!partial.tips.is_empty());
}

#[test]
fn a_bad_interval_is_refused_before_any_work_with_its_key_and_line() {
    let text = scene_text(false) + "\n[fem.paraview]\ninterval = 0.0\n";
    let t = preflight::testing::Trial::new(env!("CARGO_TARGET_TMPDIR"), "paraview-bad-interval", &text);
    let e = t.refused(
        Command::new(env!("CARGO_BIN_EXE_fem"))
            .arg(&t.scene)
            .arg("--out")
            .arg(&t.out),
    );
    let line = preflight::testing::line_containing(&text, "interval = 0.0");
    assert!(
        e.contains(&format!("line {line}: fem.paraview.interval = 0 out of range")),
        "{e}"
    );
}

/// A Python with the `vtk` module: `VTK_PYTHON` when set (and only it), else `python3`, else
/// `/usr/bin/python3` (Debian's `python3-vtk9` installs for the system Python, which a version
/// manager may shadow).
fn python_with_vtk() -> Option<String> {
    let candidates = match std::env::var("VTK_PYTHON") {
        Ok(py) => vec![py],
        Err(_) => vec!["python3".to_string(), "/usr/bin/python3".to_string()],
    };
    candidates.into_iter().find(|py| {
        Command::new(py)
            .args(["-c", "import vtk"])
            .output()
            .is_ok_and(|o| o.status.success())
    })
}

#[test]
fn vtk_reads_the_files() {
    let Some(python) = python_with_vtk() else {
        let message = "vtk_reads_the_files: SKIPPED: no Python with the vtk module (install Debian's \
                       python3-vtk9, or set VTK_PYTHON); .ci/run installs it and sets CI_REQUIRE_VTK=1";
        assert!(
            std::env::var("CI_REQUIRE_VTK").as_deref() != Ok("1"),
            "CI_REQUIRE_VTK=1 but {message}"
        );
        // straight to the terminal: the test harness captures println!, and a skip must be seen
        writeln!(std::io::stderr(), "{message}").unwrap();
        return;
    };
    let run = with_fields();
    let probe = run.out.probes.last().unwrap();
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/vtk/check_fields.py");
    let snapshots = collection(&run.dir).len().to_string();
    // {:?} prints the shortest decimal that reads back as the same f64: the script compares exactly
    let point = [probe.x, probe.y, probe.ux, probe.uy].map(|v| format!("{v:?}"));
    let o = Command::new(&python)
        .arg(&script)
        .arg(&run.dir)
        .args(["--snapshots", &snapshots, "--point"])
        .args(&point)
        .output()
        .unwrap();
    let said = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.status.success(), "{python} {}: {said}", script.display());
    assert!(said.contains("vtk check:") && said.contains("ok"), "{said}");
    writeln!(std::io::stderr(), "vtk_reads_the_files: {}", said.trim()).unwrap();
}
