//! One whole explicit step, reported per element-step (Throughput::Elements), on the three kinds
//! of bulk mesh, side by side:
//! - the paper's centre crack at paper resolution (500 × 250 identical Q4: the stencil), pre-crack
//!   faces in contact, μ = 0.3;
//! - the sinusoidal interface (750 × 250 vertical-sided Q4 of a mapped mesh: forces on the fly);
//! - the centre crack on the Gmsh triangle mesh (43 138 T3: the unstructured edge kernel);
//! - the centre crack's grid written to MSH (`fem::grid_as_msh`) and read back as a Gmsh mesh: the
//!   same 125 000 squares as the first, through the unstructured Q4 edge kernel.
//!
//! Bulk forces, cohesive law, contact, boundary, the corrector (fused with the next predictor away
//! from the interface) and the insertion check. Each state is first advanced through 0.46 T (faces pressed
//! and slipping, the crack running), and keeps advancing while measured; no step of the run is
//! sampled.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use preflight::testing::time_on_awake_pool;

fn scene_path(file: &str) -> String {
    format!("{}/../scenes/{file}", env!("CARGO_MANIFEST_DIR"))
}

fn bench_scene(c: &mut Criterion, name: &str, file: &str) {
    let scene = fem::Scene::from_file(std::path::Path::new(&scene_path(file))).unwrap();
    bench_built(c, name, &scene);
}

fn bench_built(c: &mut Criterion, name: &str, scene: &fem::Scene) {
    let (model, mut state, mut ws) = fem::build(scene).unwrap();
    let warm = (0.46 * scene.duration() / model.time_step()) as usize;
    let mut g = c.benchmark_group("step");
    g.throughput(Throughput::Elements(model.num_elements() as u64));
    // advanced to 0.46 T the first time criterion runs the routine: a mesh the filter leaves out
    // is built (a second or so) but not advanced (most of a minute)
    let mut warmed = false;
    g.bench_function(name, |b| {
        if !warmed {
            for _ in 0..warm {
                fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap();
            }
            warmed = true;
        }
        b.iter_custom(|iters| {
            time_on_awake_pool(iters, || {
                fem::solver::central_difference::step(&model, &mut state, &mut ws, false).unwrap()
            })
        })
    });
    g.finish();
}

/// The centre crack with its grid written to MSH and read back: a Gmsh mesh of the same squares,
/// its pre-crack and interface named by the file's physical groups.
fn center_crack_on_gmsh_quads() -> fem::Scene {
    let text = std::fs::read_to_string(scene_path("center-crack.toml")).unwrap();
    let built_in = fem::Scene::from_toml_str(&text).unwrap();
    let dir = std::env::temp_dir().join(format!("fem-step-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("center-crack-q4.msh");
    std::fs::write(&file, fem::grid_as_msh(&built_in).unwrap()).unwrap();
    let grid_keys = ["x_range", "y_range", "element_size"];
    let kept: Vec<&str> = text
        .lines()
        .filter(|l| !grid_keys.iter().any(|k| l.starts_with(k)))
        .collect();
    let meshed = format!(
        "{}\n[fem.mesh]\nfile = \"{}\"\npre_crack = [\"crack\"]\ninterface = [\"interface\"]\n",
        kept.join("\n"),
        file.display()
    );
    let scene = fem::Scene::from_toml_str(&meshed).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    scene
}

fn bench(c: &mut Criterion) {
    bench_scene(c, "center_crack_500x250", "center-crack.toml");
    bench_scene(c, "sinusoid_mapped_750x250", "sinusoidal-interface.toml");
    bench_scene(c, "center_crack_tri_43138", "center-crack-tri.toml");
    bench_built(c, "center_crack_gmsh_q4_500x250", &center_crack_on_gmsh_quads());
}

criterion_group!(benches, bench);
criterion_main!(benches);
