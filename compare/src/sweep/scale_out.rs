//! A sweep whose points run outside this process. `sweep --emit DIR` writes one self-contained
//! scene per point, one shell command per point (`jobs.txt`), a Slurm job-array script and a
//! manifest; each point then runs anywhere (`xargs`, GNU `parallel`, a cluster) and writes its
//! result to its own file; `sweep --collect DIR` reads every result back, refuses to go on while
//! any is missing or failed, and writes what the in-process sweep writes.
//!
//! A point's scene is the user's scene file unchanged, with the point (model, nominal size, the
//! resolution it gives and its command) appended as comments: nothing can be lost in a
//! translation, the lines of messages are those of the user's file, and the resolution is applied
//! by `sweep-point --size` exactly as in the in-process sweep. The command lines name the
//! executable and every file by absolute path, so they run unchanged from any working directory of
//! this machine, or of another that sees the same paths (a shared file system).

use super::{Model, Point, point_args, point_csv, point_label, point_tag, read_point};
use crate::study::Study;
use anyhow::{Context, Result, anyhow, bail};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The manifest of an emitted sweep, in its folder: what `--collect` expects.
pub const MANIFEST: &str = "sweep-manifest.toml";
/// One shell command line per point, in the manifest's order.
pub const JOBS: &str = "jobs.txt";
/// The Slurm job-array script: array task i runs line i of [`JOBS`].
pub const SBATCH: &str = "sweep.sbatch";
/// The folder of the points' scene files.
pub const SCENES: &str = "scenes";
/// The folder of the points' result files.
pub const POINTS: &str = "points";
/// Appended to a result file's name: the file a failed point writes instead, with the error.
pub const FAILED_SUFFIX: &str = ".failed";

/// What `sweep --emit` wrote and `sweep --collect` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Run duration T of the scene [s]: the scale of the onset errors.
    pub duration: f64,
    /// The points, in the order of the lines of `jobs.txt` (point i runs on line i + 1).
    pub points: Vec<Entry>,
}

/// One point of a [`Manifest`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Model.
    pub model: Model,
    /// Nominal FE element size [m].
    pub nominal_size: f64,
    /// The point's scene file, relative to the sweep's folder.
    pub scene: String,
    /// The point's result file, relative to the sweep's folder.
    pub result: String,
}

/// Where an emitted sweep goes, checked before anything is written.
#[derive(Debug, Clone)]
pub struct Target {
    /// The sweep's folder, absolute.
    pub dir: PathBuf,
    /// The `compare` executable the jobs run, absolute.
    pub exe: PathBuf,
}

/// `path` as one word of a job line: characters that `sh`, `xargs` (which strips quotes and
/// splits on blanks) or GNU `parallel` would read specially are refused rather than quoted, so a
/// line runs unchanged under every one of them.
fn word(what: &str, path: &Path) -> Result<String> {
    let text = path
        .to_str()
        .ok_or_else(|| anyhow!("{what} {}: the path is not UTF-8", path.display()))?;
    if let Some(c) = text
        .chars()
        .find(|&c| !(c.is_ascii_alphanumeric() || "/._-+,:@".contains(c)))
    {
        bail!(
            "{what} {text}: {c:?} cannot stand unquoted in a line of {JOBS}, which sh, xargs and \
             GNU parallel all read; use a path made of letters, digits and / . _ - + , : @ only"
        );
    }
    Ok(text.to_string())
}

/// The folder `--emit` names and the executable, checked before anything is written: both
/// absolute and fit for a job line, and no result of an earlier sweep in `<dir>/points/` (it
/// would be collected as this sweep's).
pub fn check(dir: &Path, exe: &Path) -> Result<Target> {
    preflight::paths::explicit(dir).map_err(|e| anyhow!(e.replace("--out", "--emit")))?;
    let dir = std::path::absolute(dir).with_context(|| format!("--emit {}", dir.display()))?;
    word("--emit", &dir)?;
    word("the compare executable", exe)?;
    let points = dir.join(POINTS);
    if let Ok(entries) = std::fs::read_dir(&points) {
        let mut names: Vec<String> = entries
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        if !names.is_empty() {
            bail!(
                "--emit {}: {} holds the results of an earlier sweep ({}); collect them, or emit \
                 into another folder",
                dir.display(),
                points.display(),
                names.join(", ")
            );
        }
    }
    Ok(Target {
        dir,
        exe: exe.to_path_buf(),
    })
}

/// The failure record of the result file `result`: `<result>.failed`.
pub fn failure_path(result: &Path) -> PathBuf {
    let mut name = result.as_os_str().to_os_string();
    name.push(FAILED_SUFFIX);
    PathBuf::from(name)
}

/// Writes `bytes` to `path` through a hidden temporary file in the same folder and a rename, so
/// that `path` either holds all of them or does not exist (a killed job leaves no half file).
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    use std::io::Write;
    let name = path
        .file_name()
        .ok_or_else(|| anyhow!("{}: not a file name", path.display()))?;
    let tmp = path.with_file_name(format!(".{}.tmp-{}", name.to_string_lossy(), std::process::id()));
    let mut f = std::fs::File::create(&tmp).with_context(|| format!("creating {}", tmp.display()))?;
    f.write_all(bytes)
        .and_then(|()| f.sync_all())
        .with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
}

/// Checks before the run that the result file `--result` can be written: a file name, its folder
/// created, writable.
pub fn prepare_result(result: &Path) -> Result<()> {
    if result.as_os_str().is_empty() || result.file_name().is_none() {
        bail!("--result {:?}: give a file name", result.display().to_string());
    }
    let parent = result.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(parent) = parent {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("--result {}: creating its folder", result.display()))?;
    }
    let probe = result.with_file_name(format!(".probe-{}", std::process::id()));
    std::fs::write(&probe, b"")
        .and_then(|()| std::fs::remove_file(&probe))
        .with_context(|| format!("--result {}: its folder is not writable", result.display()))
}

/// Writes a finished point to its result file (atomically) and removes the failure record of an
/// earlier attempt.
pub fn write_result(result: &Path, p: &Point) -> Result<()> {
    write_atomically(result, &point_csv(p)?)?;
    remove_if_present(&failure_path(result))
}

/// Records a failed point: its earlier result, if any, is removed (it would be collected as this
/// attempt's), then `<result>.failed` is written (atomically) with the error.
pub fn write_failure(result: &Path, error: &str) -> Result<()> {
    remove_if_present(result)?;
    write_atomically(
        &failure_path(result),
        format!("{}\n", error.trim_end()).as_bytes(),
    )
}

fn remove_if_present(path: &Path) -> Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("removing {}", path.display()))
        }
        _ => Ok(()),
    }
}

/// The command line of one point: the executable, `sweep-point` with the point's model, size and
/// budget, its scene, the sweep's folder for its tip history, its result file.
fn job_line(target: &Target, model: Model, nominal: f64, budget: preflight::Budget) -> Result<String> {
    let tag = point_tag(model, nominal);
    let dir = word("--emit", &target.dir)?;
    Ok(format!(
        "{} sweep-point {} --scene {dir}/{SCENES}/{tag}.toml --out {dir} --result {dir}/{POINTS}/{tag}.csv",
        word("the compare executable", &target.exe)?,
        point_args(model, nominal, budget).join(" "),
    ))
}

/// The point's scene file: the user's `text` unchanged, then comments naming the source, the
/// point, its resolution and its command.
fn point_scene(
    text: &str,
    source: &Path,
    point: &Study,
    model: Model,
    nominal: f64,
    line: usize,
    cmd: &str,
) -> Result<String> {
    let printable: String = source
        .display()
        .to_string()
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect();
    let mut s = text.to_string();
    if !s.is_empty() && !s.ends_with('\n') {
        s.push('\n');
    }
    let dt = point.fem.time_step();
    let resolution = match model {
        Model::Fem => format!(
            "FE element size h = {:e} m, time step {dt:e} s",
            point.fem.fem.element_size
        ),
        Model::Spectral => {
            let sp = point.spectral()?.with_time_step(dt)?;
            format!(
                "spectral grid N = {} (dx = {:e} m) at the FE time step {dt:e} s",
                sp.grid_points,
                sp.grid_spacing()
            )
        }
    };
    write!(
        s,
        "\n# ---- sweep point, appended by `compare sweep --emit` ----\n\
         # The lines above are, unchanged, {printable}\n\
         # (line numbers in messages are that file's).\n\
         # Point: {label}\n\
         # Resolution, applied by `--size {nominal}`: {resolution}\n\
         # Run by line {line} of {JOBS}:\n\
         # {cmd}\n",
        label = point_label(model, nominal),
    )?;
    Ok(s)
}

/// The Slurm job-array script of `n` jobs.
fn sbatch(target: &Target, n: usize, plan: &crate::runner::Plan) -> Result<String> {
    let dir = word("--emit", &target.dir)?;
    Ok(format!(
        "#!/bin/sh\n\
         # Slurm job array of the sweep in {dir}, written by `compare sweep --emit`: array task i\n\
         # runs line i of {JOBS}. Submit with `sbatch {dir}/{SBATCH}`; once every task has ended,\n\
         # `compare sweep --collect {dir}` writes sweep.csv, or names every point without a result.\n\
         # Estimates: the largest point holds about {mem}, the longest runs about {time} on 2\n\
         # cores; add the --partition, --time or --mem lines your cluster asks for below.\n\
         #SBATCH --job-name=compare-sweep\n\
         #SBATCH --array=1-{n}\n\
         #SBATCH --ntasks=1\n\
         #SBATCH --cpus-per-task=2\n\
         #SBATCH --output={dir}/slurm-%A_%a.out\n\
         task=${{SLURM_ARRAY_TASK_ID:?submit this script with sbatch}}\n\
         line=$(sed -n \"${{task}}p\" {dir}/{JOBS})\n\
         [ -n \"$line\" ] || {{ echo \"{JOBS} has no line $task\" >&2; exit 1; }}\n\
         exec sh -c \"$line\"\n",
        mem = preflight::budget::human(plan.largest_bytes),
        time = preflight::budget::duration(plan.longest_seconds),
    ))
}

/// Writes the emitted sweep of `points` (from [`super::plan`], checked by [`super::preflight`])
/// into `target`: `scenes/<tag>.toml` per point, `jobs.txt`, `sweep.sbatch`, the manifest, and
/// an empty `points/`. `text` is the scene file `source` as read, `study` parsed from it. Returns
/// the files written. The same input writes the same bytes.
pub fn emit(
    target: &Target,
    study: &Study,
    text: &str,
    source: &Path,
    points: &[(Model, f64, Study)],
    plan: &crate::runner::Plan,
) -> Result<Vec<PathBuf>> {
    let source = std::path::absolute(source).unwrap_or_else(|_| source.to_path_buf());
    let scenes = target.dir.join(SCENES);
    std::fs::create_dir_all(&scenes).with_context(|| format!("creating {}", scenes.display()))?;
    std::fs::create_dir_all(target.dir.join(POINTS))
        .with_context(|| format!("creating {}", target.dir.join(POINTS).display()))?;
    let mut files = Vec::new();
    let mut jobs = String::new();
    let mut entries = Vec::new();
    for (i, (model, h, point)) in points.iter().enumerate() {
        let tag = point_tag(*model, *h);
        let cmd = job_line(target, *model, *h, study.budget)?;
        let scene_text = point_scene(text, &source, point, *model, *h, i + 1, &cmd)?;
        // the copy must read as the user's file did
        Study::from_toml_str(&scene_text, &tag)
            .with_context(|| format!("the scene of {} does not read back", point_label(*model, *h)))?;
        let scene = scenes.join(format!("{tag}.toml"));
        write_atomically(&scene, scene_text.as_bytes())?;
        files.push(scene);
        jobs.push_str(&cmd);
        jobs.push('\n');
        entries.push(Entry {
            model: *model,
            nominal_size: *h,
            scene: format!("{SCENES}/{tag}.toml"),
            result: format!("{POINTS}/{tag}.csv"),
        });
    }
    let manifest = Manifest {
        duration: study.fem.duration(),
        points: entries,
    };
    let header = "# Written by `compare sweep --emit`; read by `compare sweep --collect`. Point i runs on\n\
                  # line i of jobs.txt; duration [s], nominal_size [m]; paths relative to this folder.\n";
    for (name, body) in [
        (JOBS, jobs),
        (SBATCH, sbatch(target, points.len(), plan)?),
        (MANIFEST, format!("{header}{}", toml::to_string(&manifest)?)),
    ] {
        let path = target.dir.join(name);
        write_atomically(&path, body.as_bytes())?;
        files.push(path);
    }
    Ok(files)
}

/// Reads the manifest of the emitted sweep in `dir`.
pub fn read_manifest(dir: &Path) -> Result<Manifest> {
    let path = dir.join(MANIFEST);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        anyhow!(
            "--collect {}: no sweep was emitted there ({}: {e}); write one with `compare sweep --emit {}`",
            dir.display(),
            path.display(),
            dir.display()
        )
    })?;
    let manifest: Manifest =
        toml::from_str(&text).map_err(|e| anyhow!("--collect: {} does not read: {e}", path.display()))?;
    if manifest.points.is_empty() {
        bail!("--collect: {} lists no points", path.display());
    }
    Ok(manifest)
}

/// Every point of the sweep emitted into `dir`, in the manifest's order, with the manifest.
/// Refused, naming each one, while any point has no result, failed, or holds another point's
/// result.
pub fn collect(dir: &Path) -> Result<(Manifest, Vec<Point>)> {
    let manifest = read_manifest(dir)?;
    let mut points = Vec::new();
    let mut problems = Vec::new();
    for (i, e) in manifest.points.iter().enumerate() {
        let label = point_label(e.model, e.nominal_size);
        let result = dir.join(&e.result);
        match std::fs::read(&result) {
            Ok(bytes) => match read_point(&bytes) {
                Ok(p) if p.model == e.model && p.nominal_size == e.nominal_size => points.push(p),
                Ok(p) => problems.push(format!(
                    "{label} ({}): holds the result of {}",
                    e.result,
                    point_label(p.model, p.nominal_size)
                )),
                Err(err) => problems.push(format!("{label} ({}): unreadable: {err:#}", e.result)),
            },
            Err(err) if err.kind() == std::io::ErrorKind::NotFound => {
                let failed = failure_path(&result);
                problems.push(match std::fs::read_to_string(&failed) {
                    Ok(why) => format!(
                        "{label} ({}): failed (line {} of {JOBS}): {}",
                        e.result,
                        i + 1,
                        why.trim_end().replace('\n', "\n      ")
                    ),
                    Err(_) => format!(
                        "{label} ({}): missing; line {} of {JOBS} has not run, is still running or was killed",
                        e.result,
                        i + 1
                    ),
                });
            }
            Err(err) => problems.push(format!("{label} ({}): unreadable: {err}", e.result)),
        }
    }
    if !problems.is_empty() {
        bail!(
            "--collect {dir}: {k} of {n} sweep points have no result:\n  - {list}\nrun each again \
             (line L: `sed -n Lp {dir}/{JOBS} | sh`), then collect again",
            dir = dir.display(),
            k = problems.len(),
            n = manifest.points.len(),
            list = problems.join("\n  - ")
        );
    }
    Ok((manifest, points))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(model: Model, nominal_size: f64) -> Point {
        Point {
            model,
            nominal_size,
            spacing: nominal_size,
            time_step: 1e-6,
            wall_s: 1.0,
            peak_memory_bytes: 1e6,
            onset: 0.01,
            mean_speed: 120.0,
            onset_error_over_t: f64::NAN,
            speed_error_rel: f64::NAN,
            note: String::new(),
        }
    }

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("compare-scale-out-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn paths_that_a_job_line_cannot_carry_are_refused_naming_the_option() {
        assert_eq!(
            word("--emit", Path::new("/a/b-c_d.e/+f,g:h@i")).unwrap(),
            "/a/b-c_d.e/+f,g:h@i"
        );
        for bad in ["/a b", "/a'b", "/a\"b", "/a$b", "/a\\b", "/a;b", "/a\nb"] {
            let e = word("--emit", Path::new(bad)).unwrap_err().to_string();
            assert!(e.starts_with("--emit") && e.contains("unquoted"), "{e}");
        }
    }

    #[test]
    fn a_result_replaces_a_failure_and_a_failure_replaces_a_result() {
        let dir = scratch("records");
        let result = dir.join("points").join("fem_2mm.csv");
        prepare_result(&result).unwrap();
        write_failure(&result, "unstable\nat step 3").unwrap();
        assert!(!result.exists());
        assert_eq!(
            std::fs::read_to_string(failure_path(&result)).unwrap(),
            "unstable\nat step 3\n"
        );
        write_result(&result, &point(Model::Fem, 2e-3)).unwrap();
        assert!(!failure_path(&result).exists());
        let p = read_point(&std::fs::read(&result).unwrap()).unwrap();
        assert_eq!((p.model, p.nominal_size), (Model::Fem, 2e-3));
        write_failure(&result, "stopped").unwrap();
        assert!(!result.exists() && failure_path(&result).exists());
        // no temporary file is left behind
        let names: Vec<_> = std::fs::read_dir(result.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["fem_2mm.csv.failed"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_manifest_reads_back_exactly() {
        let m = Manifest {
            duration: 0.02,
            points: vec![Entry {
                model: Model::Spectral,
                nominal_size: 0.5e-3,
                scene: "scenes/spectral_0.5mm.toml".into(),
                result: "points/spectral_0.5mm.csv".into(),
            }],
        };
        let back: Manifest = toml::from_str(&toml::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    #[test]
    fn collect_names_every_point_without_a_result() {
        let dir = scratch("collect");
        let entry = |model, h: f64| Entry {
            model,
            nominal_size: h,
            scene: String::new(),
            result: format!("{POINTS}/{}.csv", point_tag(model, h)),
        };
        let m = Manifest {
            duration: 0.02,
            points: vec![
                entry(Model::Fem, 2e-3),
                entry(Model::Fem, 1e-3),
                entry(Model::Spectral, 2e-3),
                entry(Model::Spectral, 1e-3),
            ],
        };
        std::fs::write(dir.join(MANIFEST), toml::to_string(&m).unwrap()).unwrap();
        let res = |tag: &str| dir.join(POINTS).join(format!("{tag}.csv"));
        prepare_result(&res("fem_2mm")).unwrap();
        write_result(&res("fem_2mm"), &point(Model::Fem, 2e-3)).unwrap();
        write_failure(&res("fem_1mm"), "unstable at step 7").unwrap();
        write_result(&res("spectral_2mm"), &point(Model::Fem, 2e-3)).unwrap();
        let e = collect(&dir).unwrap_err().to_string();
        assert!(e.contains("3 of 4"), "{e}");
        assert!(
            e.contains("sweep fem h = 0.001 m") && e.contains("unstable at step 7"),
            "{e}"
        );
        assert!(
            e.contains("sweep spectral h = 0.002 m") && e.contains("holds the result of"),
            "{e}"
        );
        assert!(
            e.contains("sweep spectral h = 0.001 m") && e.contains("missing; line 4"),
            "{e}"
        );
        assert!(
            !e.contains("sweep fem h = 0.002 m ("),
            "the point with its result is named: {e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
