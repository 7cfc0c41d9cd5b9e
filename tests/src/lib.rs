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
/// Intermediate tables are created when missing.
pub fn with_overrides(text: &str, overrides: &[(&str, Option<toml::Value>)]) -> String {
    let mut table: toml::Table = text.parse().expect("invariant: scene files are valid TOML");
    for (key, value) in overrides {
        let mut parts: Vec<&str> = key.split('.').collect();
        let last = parts.pop().expect("invariant: non-empty key");
        let mut t = &mut table;
        for p in parts {
            t = t
                .entry(p)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .unwrap_or_else(|| panic!("{key}: {p} is not a table"));
        }
        match value {
            Some(v) => {
                t.insert(last.to_string(), v.clone());
            }
            None => {
                t.remove(last);
            }
        }
    }
    toml::to_string(&table).expect("invariant: a TOML table serialises")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_set_and_remove_nested_keys() {
        let text = "[a]\nx = 1.0\ny = 2\n";
        let out = with_overrides(
            text,
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
