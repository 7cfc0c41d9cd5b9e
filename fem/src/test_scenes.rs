//! Test helper: the text of a scene file of the repository's `scenes/` folder.

/// `scenes/<name>.toml` as text (panics if missing: a test set-up error).
pub(crate) fn scene_text(name: &str) -> String {
    let path = format!("{}/../scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}
