//! Shared helpers for the validation tests: scene loading with overrides, reference data.

use std::path::PathBuf;

/// Repository root (the parent of this crate's manifest directory).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("invariant: the tests crate lives one level below the repository root")
        .to_path_buf()
}

/// Text of `scenes/<name>.toml`.
pub fn scene_text(name: &str) -> String {
    let path = repo_root().join("scenes").join(format!("{name}.toml"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// Runs `scenes/<name>.toml` (relative paths resolved from `scenes/`) and prints its steps.
pub fn run_repo_scene(name: &str) -> (fem::Scene, fem::RunOutput) {
    let scene = fem::Scene::from_toml_str_in(&scene_text(name), &repo_root().join("scenes")).unwrap();
    let out = fem::run(&scene).unwrap();
    println!("{name}: {} steps of {:.4e} s", out.steps, out.time_step);
    (scene, out)
}

/// [`run_repo_scene`] once per scene for the whole test binary: the tests that read the same run
/// share it. Runs of different scenes go on in parallel (the lock is held only to find a scene's
/// cell, not while it runs).
pub fn shared_repo_run(name: &str) -> &'static (fem::Scene, fem::RunOutput) {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    type Cell = OnceLock<(fem::Scene, fem::RunOutput)>;
    static CELLS: OnceLock<Mutex<HashMap<String, &'static Cell>>> = OnceLock::new();
    let cell: &'static Cell = {
        let mut cells = CELLS
            .get_or_init(Default::default)
            .lock()
            .unwrap_or_else(|e| e.into_inner());
        cells
            .entry(name.to_string())
            .or_insert_with(|| Box::leak(Box::new(Cell::new())))
    };
    cell.get_or_init(|| run_repo_scene(name))
}

/// Total length [m] of the line elements of the physical curves `groups` of `meshes/<mesh>`.
pub fn curve_length(mesh: &str, groups: &[&str]) -> f64 {
    let mesh = fem::gmsh::UnstructuredMesh::read(&repo_root().join("meshes").join(mesh)).unwrap();
    groups
        .iter()
        .flat_map(|g| mesh.groups[*g].elements.iter())
        .map(|&l| {
            let [a, b] = mesh.lines[l].nodes;
            (mesh.positions[b] - mesh.positions[a]).norm()
        })
        .sum()
}

/// Fracture energy G_c = σ_c δ_c / 2 [J/m²] of the scene's `[interface]` law.
pub fn g_c(scene: &fem::Scene) -> f64 {
    let law = scene
        .interface
        .expect("invariant: the scene has an interface law");
    0.5 * law.sigma_c * law.delta_c
}

/// The audit's cohesive dissipation at the end of `out` against G_c × `length` [m] of cracked
/// interface: prints both and returns the relative error.
pub fn dissipation_error(scene: &fem::Scene, out: &fem::RunOutput, length: f64) -> f64 {
    let dissipated = out.energy.last().map_or(0.0, |e| e.cohesive_dissipated); // J/m
    let expect = g_c(scene) * length; // J/m
    let rel = dissipated / expect - 1.0;
    println!(
        "dissipated {dissipated:.2} J/m, G_c L = {expect:.2} J/m ({:+.3} %)",
        100.0 * rel
    );
    rel
}

/// Returns `text` with dotted keys (`"fem.eps_n"`) set to new values; a `None` value removes the key.
/// Intermediate tables are created when missing. The tests vary the small scenes this way; the
/// harness itself derives its runs from typed scenes instead.
pub fn with_overrides(text: &str, overrides: &[(&str, Option<toml::Value>)]) -> String {
    let mut table: toml::Table = text.parse().unwrap_or_else(|e| panic!("scene is not TOML: {e}"));
    for (key, value) in overrides {
        let mut parts: Vec<&str> = key.split('.').collect();
        let last = parts.pop().expect("invariant: split yields at least one part");
        let mut t = &mut table;
        for p in parts {
            t = t
                .entry(p)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .unwrap_or_else(|| panic!("override {key}: `{p}` is not a table"));
        }
        match value {
            Some(v) => t.insert(last.to_string(), v.clone()),
            None => t.remove(last),
        };
    }
    toml::to_string(&table).expect("invariant: a TOML table serialises")
}

/// Rows of `reference/<name>` deserialised as `R`.
pub fn reference_rows<R: serde::de::DeserializeOwned>(name: &str) -> Vec<R> {
    let path = repo_root().join("reference").join(name);
    let mut rd =
        csv::Reader::from_path(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    rd.deserialize()
        .collect::<Result<Vec<R>, _>>()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Worst energy-balance residual of an FE run relative to the boundary work, max over samples of
/// |residual| / W_ext(t) once W_ext exceeds 0.1 % of its final value (before that the ratio is
/// 0/0 noise). Returns (worst ratio, final W_ext [J/m]).
#[cfg(feature = "fem")]
pub fn worst_energy_residual(out: &fem::RunOutput) -> (f64, f64) {
    let w_final = out.energy.last().map_or(0.0, |e| e.boundary_work);
    let worst = out
        .energy
        .iter()
        .filter(|e| e.boundary_work > 1e-3 * w_final)
        .map(|e| e.residual.abs() / e.boundary_work)
        .fold(0.0f64, f64::max);
    (worst, w_final)
}

/// First time [s] a sampled (t [s], value) history crosses `level` upwards, linearly between the
/// two samples that bracket it (a wave front reaching a probe).
pub fn upward_crossing(v: &[(f64, f64)], level: f64) -> f64 {
    let i = v
        .windows(2)
        .position(|w| w[0].1 < level && w[1].1 >= level)
        .expect("the front reaches the probe");
    let ((t0, v0), (t1, v1)) = (v[i], v[i + 1]);
    t0 + (t1 - t0) * (level - v0) / (v1 - v0)
}

/// Mean of a sampled (t [s], value) history over t ∈ [from, to] [s]; at least 21 samples.
pub fn window_mean(v: &[(f64, f64)], from: f64, to: f64) -> f64 {
    let w: Vec<f64> = v
        .iter()
        .filter(|s| s.0 >= from && s.0 <= to)
        .map(|s| s.1)
        .collect();
    assert!(w.len() > 20, "window [{from}, {to}] s holds {} samples", w.len());
    w.iter().sum::<f64>() / w.len() as f64
}

#[cfg(test)]
mod tests {
    use super::with_overrides;

    #[test]
    fn overrides_set_and_remove_nested_keys() {
        let out = with_overrides(
            "[a]\nx = 1.0\ny = 2\n",
            &[
                ("a.x", Some(toml::Value::Float(3.5))),
                ("a.y", None),
                ("b.z", Some(toml::Value::Integer(4))),
            ],
        );
        let t: toml::Table = out.parse().unwrap();
        assert_eq!(t["a"]["x"].as_float(), Some(3.5));
        assert!(t["a"].get("y").is_none());
        assert_eq!(t["b"]["z"].as_integer(), Some(4));
    }
}
