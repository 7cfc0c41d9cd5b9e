//! Checkpoint and restart (docs/checkpoints.md): a run stopped part-way and resumed from its
//! checkpoint writes the same files, byte for byte, as the run that never stopped — on the
//! structured grid (whose one-pass sweep leaves the next step's predictor in the state between
//! steps), on a Gmsh mesh with two interface chains, and with ParaView snapshots; and through the
//! command line after a SIGKILL between two checkpoints.

use fem::{FieldSink, ParaviewWriter, Scene};
use preflight::checkpoint::{self, Header, Writer};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("checkpoint-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn scene_text(name: &str) -> String {
    preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), name)
}

fn scene(text: &str) -> Scene {
    Scene::from_toml_str_in(text, &Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")).unwrap()
}

fn header(text: &str, steps: u64) -> Header {
    Header::new("fem", "test", text, Vec::new(), steps)
}

/// Every file of `dir` (ParaView snapshots in `fields/` included), by name, with its bytes.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in [dir.to_path_buf(), dir.join("fields")] {
        let Ok(entries) = std::fs::read_dir(&sub) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            if p.is_file() && name != checkpoint::FILE && !name.starts_with('.') {
                out.push((
                    format!("{}/{name}", sub.display()).replace(&dir.display().to_string(), ""),
                    std::fs::read(&p).unwrap(),
                ));
            }
        }
    }
    out.sort();
    out
}

fn assert_same_files(a: &Path, b: &Path) {
    let (fa, fb) = (files(a), files(b));
    let names = |f: &[(String, Vec<u8>)]| f.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&fa), names(&fb));
    for ((name, x), (_, y)) in fa.iter().zip(&fb) {
        assert!(
            x == y,
            "{name} differs between the run that never stopped and the resumed one"
        );
    }
}

/// Runs `text` three ways, each writing its files: whole into `whole/`; stopped at about
/// `stop_at` of its steps with a checkpoint written at every chance (into `stopped/`); resumed
/// from that checkpoint to the end (into `stopped/` again, as `--resume` does). Returns the
/// step the checkpoint was taken at and the total.
fn stop_and_resume(name: &str, text: &str, stop_at: f64) -> (u64, u64) {
    let dir = scratch(name);
    let (whole, stopped) = (dir.join("whole"), dir.join("stopped"));
    let s = scene(text);
    let total = fem::estimate(&s).steps;
    let paraview = s.fem.paraview.is_some();
    let sink = |d: &Path| paraview.then(|| ParaviewWriter::new(d, total).unwrap());

    let mut fields = sink(&whole);
    let out = fem::run_with_fields(
        &s,
        &mut |_, _| {},
        &AtomicBool::new(false),
        fields.as_mut().map(|w| w as &mut dyn FieldSink),
    )
    .unwrap();
    fem::write_csv(&out, &whole).unwrap();
    if let Some(w) = &fields {
        w.finish().unwrap();
    }

    std::fs::create_dir_all(&stopped).unwrap();
    let stop = AtomicBool::new(false);
    let mut writer = Writer::new(&stopped, 1e-9, header(text, total));
    let mut fields = sink(&stopped);
    let partial = fem::run_checkpointed(
        &s,
        &mut |done, total| {
            if done as f64 >= stop_at * total as f64 {
                stop.store(true, Ordering::Relaxed);
            }
        },
        &stop,
        fields.as_mut().map(|w| w as &mut dyn FieldSink),
        Some(&mut writer),
        None,
    );
    let Err(fem::RunError::Interrupted { step, partial, .. }) = partial else {
        panic!("the run did not stop on request: {partial:?}")
    };
    // the stopped run's own files, as the command writes them; the resumed run replaces them
    fem::write_csv(&partial, &stopped).unwrap();
    if let Some(w) = &fields {
        w.finish().unwrap();
    }
    let resumed = checkpoint::read(&stopped, &header(text, total)).unwrap();
    assert_eq!(resumed.header.step, step, "the checkpoint is that of the stop");
    let mut fields = sink(&stopped);
    let out = fem::run_checkpointed(
        &s,
        &mut |_, _| {},
        &AtomicBool::new(false),
        fields.as_mut().map(|w| w as &mut dyn FieldSink),
        None,
        Some(&resumed),
    )
    .unwrap();
    fem::write_csv(&out, &stopped).unwrap();
    if let Some(w) = &fields {
        w.finish().unwrap();
    }
    assert_same_files(&whole, &stopped);
    (step, total)
}

/// The centre crack on the grid: pre-crack faces in contact with friction (σ̃ and the slip
/// history), insertion, the Westergaard field. The stop falls on an unsampled step, after which
/// the free nodes already hold the next predictor: a checkpoint without that flag would apply
/// the predictor twice.
#[test]
fn a_resumed_grid_run_writes_the_files_of_the_run_that_never_stopped() {
    let text = scene_text("tiny-fem-center-crack");
    let (step, total) = stop_and_resume("grid", &text, 0.6);
    assert!(step > total / 2 && step < total, "{step} of {total}");
    let every = 1e-5 / scene(&text).time_step();
    assert!(
        (step as f64 / every).fract().abs() > 1e-9,
        "the stop should fall between samples: step {step}"
    );
}

/// Gmsh meshes: an arc-shaped interface sheared with friction (contact history on a curved
/// surface), and two interface chains (records with a chain column), stopped while the cracks
/// grow.
#[test]
fn a_resumed_mesh_run_writes_the_files_of_the_run_that_never_stopped() {
    for (name, at) in [("tiny-fem-arc-shear", 0.6), ("tiny-fem-two-chains", 0.7)] {
        let (step, total) = stop_and_resume(name, &scene_text(name), at);
        assert!(step > total / 2 && step < total, "{name}: {step} of {total}");
    }
}

/// ParaView snapshots: those after the checkpoint are written by the resumed run, and the
/// collection lists every snapshot of the whole run once.
#[test]
fn a_resumed_run_writes_the_snapshots_of_the_run_that_never_stopped() {
    let text =
        scene_text("tiny-fem-center-crack").replace("[fem]\n", "[fem.paraview]\ninterval = 1e-4\n\n[fem]\n");
    stop_and_resume("paraview", &text, 0.45);
}

/// `fem` with `args`, to its end.
fn fem(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_fem"))
        .args(args)
        .output()
        .unwrap()
}

/// Modification time of `path`, if it exists.
fn modified(path: &Path) -> Option<std::time::SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// Through the command line: a run with `--checkpoint-every` is killed (SIGKILL, no chance to
/// write anything) after its second checkpoint, then `--resume` finishes it. Its folder then
/// holds the files of a run that never stopped, byte for byte, and no checkpoint. Before that,
/// a resume with a changed scene value and one with a changed mesh file are refused, naming
/// what changed. On the grid, and on a Gmsh mesh (an arc interface sheared with friction).
#[test]
fn a_killed_run_resumes_and_writes_the_files_of_the_run_that_never_stopped() {
    use std::os::unix::process::ExitStatusExt;
    let root = env!("CARGO_TARGET_TMPDIR");
    // ~1.5 s each on 2 cores: ten times what two checkpoints 0.05 s apart and a kill need
    let grid = scene_text("tiny-fem-center-crack").replace("element_size = 1e-3 ", "element_size = 2e-4 ");
    let mesh = scene_text("tiny-fem-arc-shear")
        .replace("duration = 0.3 ", "duration = 4.0 ")
        .replace("\"../meshes/arc.msh\"", "\"arc.msh\"");
    for (name, text) in [("cli-grid", grid), ("cli-mesh", mesh)] {
        let t = preflight::testing::Trial::new(root, &format!("checkpoint-{name}"), &text);
        let msh = t.dir.join("arc.msh");
        std::fs::copy(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../meshes/arc.msh"),
            &msh,
        )
        .unwrap();
        let whole = t.dir.join("whole");
        let o = fem(&[t.scene.as_os_str(), "--out".as_ref(), whole.as_os_str()]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

        let (mut child, _) = preflight::testing::started(
            Command::new(env!("CARGO_BIN_EXE_fem"))
                .arg(&t.scene)
                .arg("--out")
                .arg(&t.out)
                .args(["--checkpoint-every", "0.05"]),
        );
        let file = t.out.join(checkpoint::FILE);
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
        let first = loop {
            if let Some(m) = modified(&file) {
                break m;
            }
            assert!(
                std::time::Instant::now() < deadline,
                "{name}: no checkpoint written"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        };
        while modified(&file) == Some(first) {
            assert!(
                std::time::Instant::now() < deadline,
                "{name}: no second checkpoint"
            );
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        child.kill().unwrap();
        let status = child.wait().unwrap();
        assert_eq!(
            status.signal(),
            Some(libc::SIGKILL),
            "{name}: the run ended before the kill"
        );

        // a changed value and a changed mesh are refused, before any work
        let changed = t.dir.join("changed.toml");
        std::fs::write(
            &changed,
            text.replace("friction_coeff = 0.3 ", "friction_coeff = 0.4 "),
        )
        .unwrap();
        let o = fem(&[changed.as_os_str(), "--resume".as_ref(), t.out.as_os_str()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && o.stdout.is_empty(), "{name}: {stderr}");
        assert!(
            stderr.contains("the scene changed since the checkpoint: friction.friction_coeff: 0.3 → 0.4;"),
            "{name}: {stderr}"
        );
        if name == "cli-mesh" {
            let kept = std::fs::read(&msh).unwrap();
            std::fs::write(&msh, [&kept[..], b"\n"].concat()).unwrap();
            let o = fem(&[t.scene.as_os_str(), "--resume".as_ref(), t.out.as_os_str()]);
            let stderr = String::from_utf8_lossy(&o.stderr);
            assert!(!o.status.success() && o.stdout.is_empty(), "{stderr}");
            assert!(
                stderr.contains("arc.msh changed since the checkpoint"),
                "{stderr}"
            );
            std::fs::write(&msh, kept).unwrap();
        }

        let o = fem(&[t.scene.as_os_str(), "--resume".as_ref(), t.out.as_os_str()]);
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(
            o.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let at = stdout
            .split("resuming from the checkpoint at step ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|n| n.parse::<u64>().ok())
            .unwrap_or_else(|| panic!("{name}: {stdout}"));
        assert!(at > 0, "{name}: resumed at step {at}");
        // this process computed the steps after the checkpoint, and only those
        let total = fem::estimate(&Scene::from_toml_str_in(&text, &t.dir).unwrap()).steps;
        assert!(
            stdout.contains(&format!(
                "\n{} steps (steps {} to {total}, resumed)",
                total - at,
                at + 1
            )),
            "{name}: {stdout}"
        );
        assert!(!file.exists(), "{name}: a finished run keeps no checkpoint");
        assert_same_files(&whole, &t.out);
    }
}
