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

/// Returns `text` with dotted keys (`"fem.eps_n"`) set to new values; a `None` value removes the key.
/// Intermediate tables are created when missing. (The harness's own edit, so tests vary scenes
/// exactly the way `compare` does.)
pub fn with_overrides(text: &str, overrides: &[(&str, Option<toml::Value>)]) -> String {
    compare::scene::with_overrides(text, overrides).unwrap_or_else(|e| panic!("scene override: {e:#}"))
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
