//! A sweep run outside the `compare` process: `sweep --emit` writes the points as jobs, the jobs
//! run under `xargs` (or a Slurm array task), `sweep --collect` reads their results. Every test
//! sweeps `scenes/tiny-sweep.toml` at `--sizes 2e-3,1e-3`: four points of well under a second.

use preflight::testing::{Trial, scene_text};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SIZES: &str = "2e-3,1e-3";

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/tiny-sweep.toml")
}

/// A fresh folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("compare-sweep-scale-out-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn compare(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_compare"))
        .args(args)
        .output()
        .unwrap()
}

fn succeeded(what: &str, o: Output) -> Output {
    assert!(
        o.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    o
}

fn emit(dir: &Path) {
    let scene = scene();
    succeeded(
        "sweep --emit",
        compare(&[
            "sweep",
            "--scene",
            scene.to_str().unwrap(),
            "--sizes",
            SIZES,
            "--emit",
            dir.to_str().unwrap(),
        ]),
    );
}

/// Every file `--emit` wrote, by name, with its bytes.
fn emitted_files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut files: Vec<PathBuf> = ["jobs.txt", "sweep.sbatch", "sweep-manifest.toml"]
        .iter()
        .map(|n| dir.join(n))
        .collect();
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(dir.join("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    scenes.sort();
    files.extend(scenes);
    files
        .into_iter()
        .map(|f| {
            let bytes = std::fs::read(&f).unwrap();
            (f, bytes)
        })
        .collect()
}

fn collect(dir: &Path) -> Output {
    compare(&["sweep", "--collect", dir.to_str().unwrap()])
}

/// The rows of a `sweep.csv` with the measured cost columns (wall time, peak memory) removed.
fn without_costs(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut rd = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = rd.headers().unwrap().iter().map(String::from).collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&i| header[i] != "wall_s" && header[i] != "peak_memory_bytes")
        .collect();
    assert_eq!(keep.len() + 2, header.len(), "{header:?}");
    let rows = rd
        .records()
        .map(|r| {
            let r = r.unwrap();
            keep.iter().map(|&i| r[i].to_string()).collect()
        })
        .collect();
    (keep.iter().map(|&i| header[i].clone()).collect(), rows)
}

/// Exact equality, not a tolerance: the same binary runs the same points of the same scene, and
/// both models are deterministic (every output byte-identical between runs), so the emitted
/// sweep must reproduce the in-process one to the last digit: every column of `sweep.csv` and
/// every tip history. The two cost columns, wall time and peak memory, are measurements of two
/// different runs (and under `xargs -P 2` two points share the machine), so they cannot be
/// equal; they are left out of the comparison and only checked to be present.
#[test]
fn emitted_jobs_run_by_xargs_and_collected_reproduce_the_in_process_sweep() {
    let root = scratch("same");
    let scene = scene();
    let inside = root.join("in-process");
    succeeded(
        "sweep",
        compare(&[
            "sweep",
            "--scene",
            scene.to_str().unwrap(),
            "--sizes",
            SIZES,
            "--out",
            inside.to_str().unwrap(),
        ]),
    );

    let dir = root.join("emitted");
    emit(&dir);
    let first = emitted_files(&dir);
    emit(&dir);
    assert_eq!(
        emitted_files(&dir),
        first,
        "the same input must emit the same bytes"
    );
    let jobs = std::fs::read_to_string(dir.join("jobs.txt")).unwrap();
    assert_eq!(jobs.lines().count(), 4, "{jobs}");
    assert!(
        jobs.lines().all(|l| l.starts_with(env!("CARGO_BIN_EXE_compare"))),
        "{jobs}"
    );
    // each point's scene is the user's file unchanged, the point appended as comments
    let original = std::fs::read_to_string(&scene).unwrap();
    for name in ["fem_2mm", "fem_1mm", "spectral_2mm", "spectral_1mm"] {
        let copy = std::fs::read_to_string(dir.join("scenes").join(format!("{name}.toml"))).unwrap();
        assert!(copy.starts_with(&original), "{name}");
    }

    // from another working directory: the lines depend on none
    let run = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "xargs -P 2 -I{{}} sh -c {{}} < {}",
            dir.join("jobs.txt").display()
        ))
        .current_dir("/")
        .output()
        .unwrap();
    succeeded("xargs -P 2", run);
    succeeded("sweep --collect", collect(&dir));

    let (header, rows) = without_costs(&inside.join("sweep.csv"));
    let (emitted_header, emitted_rows) = without_costs(&dir.join("sweep.csv"));
    assert_eq!(emitted_header, header);
    assert_eq!(rows.len(), 4);
    assert_eq!(emitted_rows, rows);
    assert!(dir.join("sweep_error_vs_wall_time.png").exists());
    for name in ["fem_2mm", "fem_1mm", "spectral_2mm", "spectral_1mm"] {
        let tips = format!("tips_{name}.csv");
        assert_eq!(
            std::fs::read(dir.join(&tips)).unwrap(),
            std::fs::read(inside.join(&tips)).unwrap(),
            "{tips}"
        );
    }
}

/// No tolerance: a point either has its result file or is named. The points run through the
/// generated Slurm script (its `#SBATCH --array` range, one task per line of jobs.txt), with
/// `SLURM_ARRAY_TASK_ID` set as Slurm sets it.
#[test]
fn collect_names_every_point_without_a_result_and_writes_nothing() {
    let dir = scratch("missing");
    emit(&dir);
    let sbatch = std::fs::read_to_string(dir.join("sweep.sbatch")).unwrap();
    let tasks: usize = sbatch
        .lines()
        .find_map(|l| l.strip_prefix("#SBATCH --array=1-"))
        .expect("an array directive")
        .parse()
        .unwrap();
    assert_eq!(tasks, 4);
    for task in 1..=tasks {
        let o = Command::new("sh")
            .arg(dir.join("sweep.sbatch"))
            .env("SLURM_ARRAY_TASK_ID", task.to_string())
            .output()
            .unwrap();
        succeeded(&format!("array task {task}"), o);
    }

    // a result deleted: that point, and only it, is named
    std::fs::remove_file(dir.join("points/spectral_2mm.csv")).unwrap();
    let o = collect(&dir);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert!(
        e.contains("sweep spectral h = 0.002 m (points/spectral_2mm.csv): missing; line 3"),
        "{e}"
    );
    assert!(e.contains("1 of 4"), "{e}");
    assert!(
        !dir.join("sweep.csv").exists(),
        "collect wrote results with a point missing"
    );

    // a point whose run fails exits non-zero and leaves the reason, not a result
    std::fs::remove_file(dir.join("scenes/fem_1mm.toml")).unwrap();
    let line = std::fs::read_to_string(dir.join("jobs.txt"))
        .unwrap()
        .lines()
        .nth(1)
        .unwrap()
        .to_string();
    let o = Command::new("sh").arg("-c").arg(&line).output().unwrap();
    assert!(!o.status.success(), "{line}");
    assert!(!dir.join("points/fem_1mm.csv").exists());
    let o = collect(&dir);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{e}");
    assert!(e.contains("2 of 4"), "{e}");
    assert!(
        e.contains("sweep fem h = 0.001 m (points/fem_1mm.csv): failed (line 2 of jobs.txt)")
            && e.contains("fem_1mm.toml"),
        "{e}"
    );
    assert!(
        !e.contains("fem h = 0.002 m"),
        "a point with a result is named: {e}"
    );
    assert!(!dir.join("sweep.csv").exists());
}

/// No tolerance: every bad `--sizes` is refused, naming the option, before any point runs or
/// any folder is written (in the sweep and in `--emit`).
#[test]
fn bad_sizes_are_refused_naming_the_option() {
    let text = scene_text(env!("CARGO_MANIFEST_DIR"), "tiny-sweep");
    for (k, sizes) in ["0", "-1e-3", "2e-3,-1e-3", "inf", "NaN", "4 mm", "", "2e-3,2e-3"]
        .into_iter()
        .enumerate()
    {
        for emit in [false, true] {
            let t = Trial::new(
                env!("CARGO_TARGET_TMPDIR"),
                &format!("compare-sweep-sizes-{k}-{emit}"),
                &text,
            );
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_compare"));
            cmd.arg("sweep")
                .arg("--scene")
                .arg(&t.scene)
                .arg("--sizes")
                .arg(sizes)
                .arg(if emit { "--emit" } else { "--out" })
                .arg(&t.out);
            let e = t.refused(&mut cmd);
            assert!(e.contains("--sizes"), "--sizes {sizes:?}: {e}");
        }
    }
}
