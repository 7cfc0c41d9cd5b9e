//! Reproducibility: the same scene gives byte-identical output files, run after run and whatever
//! the number of threads. Each model runs its tiny scene twice on one thread and twice on two
//! (rayon pools of 1 and 2 workers, as `RAYON_NUM_THREADS=1` and `=2` would give), writes its
//! CSV files, and every file is compared byte for byte with the first run's; a fifth run uses three
//! threads, which splits the work unevenly. Sums over nodes that associate their terms in a
//! thread-dependent order (a plain parallel `sum()`) fail this test.

use std::collections::BTreeMap;
use std::path::Path;

/// Every file of `dir`, by name.
fn files(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

/// Runs `write(dir)` for 1, 1, 2, 2 and 3 threads into fresh folders and asserts identical files.
fn assert_identical(name: &str, write: impl Fn(&Path) + Sync) {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("determinism-{name}"));
    let _ = std::fs::remove_dir_all(&root);
    let mut first: Option<BTreeMap<String, Vec<u8>>> = None;
    for (k, threads) in [1, 1, 2, 2, 3].into_iter().enumerate() {
        let dir = root.join(format!("run{k}-threads{threads}"));
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| write(&dir));
        let got = files(&dir);
        match &first {
            None => {
                assert!(got.len() >= 3, "{name}: only {:?}", got.keys());
                first = Some(got);
            }
            Some(f) => {
                assert_eq!(
                    f.keys().collect::<Vec<_>>(),
                    got.keys().collect::<Vec<_>>(),
                    "{name}"
                );
                for (file, bytes) in f {
                    assert!(
                        got[file] == *bytes,
                        "{name}: {file} differs in run {k} ({threads} threads)"
                    );
                }
            }
        }
    }
}

#[cfg(feature = "fem")]
#[test]
fn fem_output_is_identical_between_runs_and_thread_counts() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/tiny-fem-center-crack.toml"),
    )
    .unwrap();
    let scene = fem::Scene::from_toml_str(&text).unwrap();
    assert_identical("fem", |dir| {
        let out = fem::run(&scene).unwrap();
        fem::write_csv(&out, dir).unwrap();
    });
}

/// The centre crack on its triangle mesh (`scenes/center-crack-tri.toml`, 21 693 nodes: 16 tiles
/// of the edge-based bulk kernel, so two and three threads split them), loaded ten times faster
/// for 1.5 ms so that facets are inserted at the pre-crack tips and contact closes on its faces
/// within a short run.
#[cfg(feature = "fem")]
#[test]
fn fem_output_on_a_gmsh_mesh_is_identical_between_runs_and_thread_counts() {
    use toml::Value;
    let text = validation::with_overrides(
        &validation::scene_text("center-crack-tri"),
        &[
            ("loading.duration", Some(Value::Float(1.5e-3))),
            ("loading.shear.final", Some(Value::Float(1.2e6))),
            ("loading.shear.ramp_end", Some(Value::Float(1.5e-3))),
            ("loading.normal.ramp_end", Some(Value::Float(4e-4))),
        ],
    );
    let scene = fem::Scene::from_toml_str_in(&text, &validation::repo_root().join("scenes")).unwrap();
    assert_identical("fem-mesh", |dir| run_through_insertion(&scene, dir));
}

/// A P wave through a bar of two materials on a Gmsh mesh of rectangles
/// (`scenes/tiny-fem-bimaterial.toml`, 1 005 nodes of unstructured Q4: 4 tiles of the edge-based
/// bulk kernel, so two and three threads split them, the second material's blocks among them).
#[cfg(feature = "fem")]
#[test]
fn fem_output_on_a_gmsh_quadrangle_mesh_is_identical_between_runs_and_thread_counts() {
    let text = validation::scene_text("tiny-fem-bimaterial");
    let scene = fem::Scene::from_toml_str_in(&text, &validation::repo_root().join("scenes")).unwrap();
    assert_identical("fem-quad-mesh", |dir| {
        let out = fem::run(&scene).unwrap();
        fem::write_csv(&out, dir).unwrap();
    });
}

/// The rough interface on its mapped mesh (`scenes/tiny-fem-rough-interface.toml`, 150 × 50
/// elements of their own shapes: 4 bands of the one-pass sweep, each element row's forces
/// computed once and summed into its two layers, so two and three threads split the bands
/// unevenly).
#[cfg(feature = "fem")]
#[test]
fn fem_output_on_a_mapped_mesh_is_identical_between_runs_and_thread_counts() {
    let scene = fem::Scene::from_toml_str(&validation::scene_text("tiny-fem-rough-interface")).unwrap();
    assert_identical("fem-mapped", |dir| run_through_insertion(&scene, dir));
}

/// Runs `scene`, checks that it inserted a facet (so the cohesive path ran) and writes its CSVs
/// into `dir`.
#[cfg(feature = "fem")]
fn run_through_insertion(scene: &fem::Scene, dir: &Path) {
    let out = fem::run(scene).unwrap();
    let inserted = out
        .arrivals
        .iter()
        .filter(|a| a.insertion_time.is_finite())
        .count();
    assert!(
        inserted > 0,
        "no facet inserted: the run does not reach the cohesive path"
    );
    fem::write_csv(&out, dir).unwrap();
}

#[cfg(feature = "spectral")]
#[test]
fn spectral_output_is_identical_between_runs_and_thread_counts() {
    let text = validation::scene_text("tiny-spectral-andrews");
    spectral_output_identical("spectral", &text, spectral::FastStorage::F64);
}

/// The same scene with the fast path's states kept in single precision
/// (`spectral.fast_storage = "f32"`).
#[cfg(feature = "spectral")]
#[test]
fn spectral_output_with_single_precision_states_is_identical_between_runs_and_thread_counts() {
    let text = validation::scene_text("tiny-spectral-andrews").replacen(
        "[spectral]",
        "[spectral]\nfast_storage = \"f32\"",
        1,
    );
    spectral_output_identical("spectral-f32", &text, spectral::FastStorage::F32);
}

/// [`assert_identical`] on the spectral run of the scene `text`, whose fast path keeps its states
/// as `storage` says.
#[cfg(feature = "spectral")]
fn spectral_output_identical(name: &str, text: &str, storage: spectral::FastStorage) {
    let scene = spectral::Scene::from_toml_str(text).unwrap();
    assert_eq!(scene.fast_storage, storage, "the scene's storage");
    assert_identical(name, |dir| {
        let out = spectral::run(&scene).unwrap();
        spectral::write_csv(&out, dir).unwrap();
    });
}
