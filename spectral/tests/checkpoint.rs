//! Checkpoints and restart (`--checkpoint-every`, `--resume`; `spectral::run_checkpointed`): a run
//! stopped half way and resumed from its checkpoint writes the same files, byte for byte, as a
//! run that never stopped — on both convolution paths, for one material and for two, whatever
//! the thread count; a run killed outright resumes from its last periodic checkpoint; a
//! checkpoint of another scene, or none, is refused before any work; a checkpoint that cannot be
//! written stops the run as a failed output does.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use preflight::checkpoint::{FILE, Header, Writer};
use spectral::{RunError, RunOutput, Scene};

/// A scratch folder of this test file, emptied.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("spectral-checkpoint-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The §7.7 crack of `tiny-spectral-andrews` cut to 256 points on a 32 m period and 20 time units
/// (640 steps), with friction and Prakash regularisation (σ̃ has a history), field snapshots, the
/// given convolution path (`fast_f32`: the fast one, its states in single precision) and, when
/// `split`, a bottom half-space 1.44 times lighter (c_s 20 % higher; the bimaterial path, one
/// operator per half-space). The direct path gets kernel_cutoff = 2 so that the ring buffers of
/// most modes wrap during the run.
fn scene_text(convolution: &str, split: bool) -> String {
    let mut t: toml::Table =
        preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), "tiny-spectral-andrews")
            .parse()
            .unwrap();
    let set = |t: &mut toml::Table, path: &str, v: toml::Value| {
        let (table, key) = path.split_once('.').unwrap();
        t.get_mut(table)
            .unwrap()
            .as_table_mut()
            .unwrap()
            .insert(key.into(), v);
    };
    set(&mut t, "loading.duration", 20.0.into());
    let mut shear = t["loading"]["shear"].as_table().unwrap().clone();
    shear.insert("final".into(), 0.5.into());
    set(&mut t, "loading.shear", shear.into());
    set(&mut t, "friction.friction_coeff", 0.1.into());
    set(&mut t, "spectral.grid_points", 256.into());
    set(&mut t, "spectral.length", 32.0.into());
    set(&mut t, "spectral.t_star", 0.5.into());
    set(&mut t, "spectral.output_interval", 0.1.into());
    set(&mut t, "spectral.field_output_interval", 0.5.into());
    // "fast_f32": the fast path with its states stored in single precision
    let (convolution, storage) = match convolution {
        "fast_f32" => ("fast", Some("f32")),
        other => (other, None),
    };
    set(&mut t, "spectral.convolution", convolution.into());
    if let Some(storage) = storage {
        set(&mut t, "spectral.fast_storage", storage.into());
    }
    if convolution == "direct" {
        set(&mut t, "spectral.kernel_cutoff", 2.0.into());
    }
    if split {
        let top = t.remove("material").unwrap();
        let mut bottom = top.as_table().unwrap().clone();
        bottom.insert("density".into(), (1.0 / 1.44).into());
        let mut m = toml::Table::new();
        m.insert("top".into(), top);
        m.insert("bottom".into(), bottom.into());
        t.insert("material".into(), m.into());
    }
    toml::to_string(&t).unwrap()
}

/// What a checkpoint of `text` says before its first write (as `spectral` writes it).
fn header(text: &str, scene: &Scene) -> Header {
    Header::new("spectral", "test", text, Vec::new(), scene.last_step() + 1)
}

/// The files `write_csv` writes for `out`, by name.
fn csv_files(out: &RunOutput, dir: &Path) -> Vec<(String, Vec<u8>)> {
    let files = spectral::write_csv(out, dir).unwrap();
    files
        .iter()
        .map(|f| {
            (
                f.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(f).unwrap(),
            )
        })
        .collect()
}

/// Run A to the end; run B, writing a checkpoint at every progress report, stopped on request
/// half way (its last checkpoint is the one written at the stop); then B resumed from that
/// checkpoint on one thread: the resumed records are A's, file by file, byte by byte.
fn resumed_run_is_the_uninterrupted_one(name: &str, convolution: &str, split: bool) {
    let text = scene_text(convolution, split);
    let scene = Scene::from_toml_str(&text).unwrap();
    assert_eq!(scene.is_split(), split);
    let total = scene.last_step() + 1;
    let a = spectral::run(&scene).unwrap();
    // the crack runs: the state after the stop is not the state before it
    let (first, end) = (a.tips[0], *a.tips.last().unwrap());
    assert!(
        end.tip_right > first.tip_right + 1.0,
        "{name}: the crack does not grow ({first:?} → {end:?})"
    );

    let dir = scratch(name);
    let stop = AtomicBool::new(false);
    let mut writer = Writer::new(&dir, 1e-9, header(&text, &scene));
    let b = spectral::run_checkpointed(
        &scene,
        &mut |done, total| {
            if done >= total / 2 {
                stop.store(true, Ordering::Relaxed);
            }
        },
        &stop,
        Some(&mut writer),
        None,
    );
    let Err(RunError::Interrupted { step, .. }) = b else {
        panic!("{name}: run B did not stop: {b:?}");
    };
    assert!(writer.written() > 2, "{name}: {}", writer.summary());

    let resumed = preflight::checkpoint::read(&dir, &header(&text, &scene)).unwrap();
    let from = resumed.header.step;
    assert!(
        from > 0 && from < total,
        "{name}: resumed at step {from} of {total}"
    );
    assert_eq!(from, step + 1, "{name}: the checkpoint is the stop's");
    let pool = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let c = pool
        .install(|| {
            spectral::run_checkpointed(
                &scene,
                &mut |_, _| {},
                &AtomicBool::new(false),
                None,
                Some(&resumed),
            )
        })
        .unwrap();
    assert_eq!(c.stats.status, preflight::Status::Finished);
    let (da, dc) = (dir.join("a"), dir.join("c"));
    let (fa, fc) = (csv_files(&a, &da), csv_files(&c, &dc));
    assert_eq!(
        fa.iter().map(|f| &f.0).collect::<Vec<_>>(),
        fc.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    for ((file, x), (_, y)) in fa.iter().zip(&fc) {
        assert!(
            x == y,
            "{name}: {file} of the resumed run differs from the uninterrupted run's (see {} and {})",
            da.display(),
            dc.display()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_resumed_run_is_the_uninterrupted_run_fast_path() {
    resumed_run_is_the_uninterrupted_one("fast", "fast", false);
}

#[test]
fn a_resumed_run_is_the_uninterrupted_run_fast_path_states_in_single_precision() {
    resumed_run_is_the_uninterrupted_one("fast-f32", "fast_f32", false);
}

#[test]
fn a_resumed_run_is_the_uninterrupted_run_direct_path() {
    resumed_run_is_the_uninterrupted_one("direct", "direct", false);
}

#[test]
fn a_resumed_run_is_the_uninterrupted_run_two_materials_fast_path() {
    resumed_run_is_the_uninterrupted_one("split-fast", "fast", true);
}

#[test]
fn a_resumed_run_is_the_uninterrupted_run_two_materials_direct_path() {
    resumed_run_is_the_uninterrupted_one("split-direct", "direct", true);
}

/// A checkpoint that cannot be written (its folder is gone) stops the run at once as a failed
/// output, naming the file, with the records up to there.
#[test]
fn a_checkpoint_that_cannot_be_written_stops_the_run() {
    let text = scene_text("fast", false);
    let scene = Scene::from_toml_str(&text).unwrap();
    let dir = scratch("unwritable").join("gone");
    let mut writer = Writer::new(&dir, 1e-9, header(&text, &scene));
    let r = spectral::run_checkpointed(
        &scene,
        &mut |_, _| {},
        &AtomicBool::new(false),
        Some(&mut writer),
        None,
    );
    let Err(RunError::OutputFailed {
        step,
        message,
        partial,
        ..
    }) = r
    else {
        panic!("the run went on: {r:?}");
    };
    assert!(
        message.contains(&dir.join(FILE).display().to_string()),
        "{message}"
    );
    assert!(step < scene.last_step());
    assert_eq!(partial.stats.status, preflight::Status::OutputFailed);
    assert_eq!(partial.tips.len() as u64, step + 1);
}

/// The `spectral` command with `args`, its output once it ended.
fn spectral(args: &[&std::ffi::OsStr], threads: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_spectral"));
    cmd.args(args);
    if let Some(n) = threads {
        cmd.env("RAYON_NUM_THREADS", n);
    }
    cmd.output().unwrap()
}

/// The CSV files of an output folder, by name.
fn csv_in(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .map(|p| {
            (
                p.file_name().unwrap().to_string_lossy().into_owned(),
                std::fs::read(&p).unwrap(),
            )
        })
        .collect();
    files.sort();
    files
}

/// The `tiny-spectral-andrews` scene with friction, run four times as long (360 s of model time:
/// about 1.2 s of a release build on 2 cores of an AMD EPYC with AVX-512, long enough to be
/// killed after its first checkpoint), its text.
fn long_scene() -> String {
    preflight::testing::scene_text(env!("CARGO_MANIFEST_DIR"), "tiny-spectral-andrews")
        .replace("friction_coeff = 0.0 ", "friction_coeff = 0.1 ")
        .replace("t_star = 0.0 ", "t_star = 0.5 ")
        .replace("duration = 90.0 ", "duration = 360.0 ")
}

/// A run killed outright (SIGKILL: no last checkpoint) after its first periodic checkpoint, then
/// `--resume`d on one thread, writes the files of a run never stopped, byte for byte; the
/// finished resumed run removes its checkpoint.
#[test]
fn a_killed_command_resumes_to_the_uninterrupted_output() {
    let dir = scratch("killed");
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, long_scene()).unwrap();
    let (whole, killed) = (dir.join("whole"), dir.join("killed"));

    let mut child = Command::new(env!("CARGO_BIN_EXE_spectral"))
        .arg(&scene)
        .arg("--out")
        .arg(&killed)
        .args(["--checkpoint-every", "0.2"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !killed.join(FILE).exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no checkpoint after 60 s"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the run ended before it was killed: make the scene longer"
    );
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(csv_in(&killed).is_empty(), "a killed run writes no records");

    let resumed = spectral(
        &["--resume".as_ref(), killed.as_os_str(), scene.as_os_str()],
        Some("1"),
    );
    let stdout = String::from_utf8_lossy(&resumed.stdout);
    assert!(
        resumed.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
    let step: u64 = stdout
        .split("resuming from the checkpoint at step ")
        .nth(1)
        .and_then(|s| s.split_whitespace().next())
        .unwrap_or_else(|| panic!("no resuming line: {stdout}"))
        .parse()
        .unwrap();
    assert!(step > 0, "{stdout}");
    assert!(
        !killed.join(FILE).exists(),
        "the finished run left its checkpoint"
    );

    let reference = spectral(&[scene.as_os_str(), "--out".as_ref(), whole.as_os_str()], None);
    assert!(reference.status.success());
    let (a, b) = (csv_in(&whole), csv_in(&killed));
    assert_eq!(
        a.iter().map(|f| &f.0).collect::<Vec<_>>(),
        b.iter().map(|f| &f.0).collect::<Vec<_>>()
    );
    assert!(a.len() >= 3);
    for ((file, x), (_, y)) in a.iter().zip(&b) {
        assert!(
            x == y,
            "{file}: the resumed run's differs from the uninterrupted run's"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--resume` with the friction coefficient changed is refused before any work, naming the key
/// with its two values, and keeps the checkpoint; `--resume` of a folder with no checkpoint is
/// refused naming checkpoint.bin.
#[test]
fn a_resume_of_another_scene_or_of_no_checkpoint_is_refused() {
    use preflight::testing::{signalled, started};
    let dir = scratch("refused");
    let scene = dir.join("scene.toml");
    let text = long_scene();
    std::fs::write(&scene, &text).unwrap();
    let out = dir.join("out");
    // a run stopped on request writes its checkpoint at the stop
    let (child, plan) = started(
        Command::new(env!("CARGO_BIN_EXE_spectral"))
            .arg(&scene)
            .arg("--out")
            .arg(&out)
            .args(["--checkpoint-every", "100"]),
    );
    assert!(plan.contains("steps"), "{plan}");
    let stopped = signalled(child, &[libc::SIGTERM]);
    assert!(!stopped.status.success());
    let stdout = String::from_utf8_lossy(&stopped.stdout);
    assert!(stdout.contains("1 checkpoint(s) of "), "{stdout}");
    let checkpoint = std::fs::read(out.join(FILE)).unwrap();

    std::fs::write(
        &scene,
        text.replace("friction_coeff = 0.1 ", "friction_coeff = 0.2 "),
    )
    .unwrap();
    let o = spectral(&["--resume".as_ref(), out.as_os_str(), scene.as_os_str()], None);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(o.stdout.is_empty(), "{}", String::from_utf8_lossy(&o.stdout));
    assert!(stderr.contains("friction.friction_coeff: 0.1 → 0.2"), "{stderr}");
    assert_eq!(
        std::fs::read(out.join(FILE)).unwrap(),
        checkpoint,
        "the checkpoint changed"
    );

    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let o = spectral(&["--resume".as_ref(), empty.as_os_str(), scene.as_os_str()], None);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(o.stdout.is_empty(), "{}", String::from_utf8_lossy(&o.stdout));
    assert!(stderr.contains("no checkpoint.bin"), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}
