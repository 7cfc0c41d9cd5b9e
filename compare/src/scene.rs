//! Scene variants by editing the TOML text before either model parses it, so both models
//! always read the same problem and the harness never reaches into a model's internals.

use anyhow::{Context, Result, anyhow};

/// A dotted key (`"friction.friction_coeff"`) and its new value; `None` removes the key.
pub type Override<'a> = (&'a str, Option<toml::Value>);

/// Returns `text` with the dotted keys set (or removed); missing tables are created.
pub fn with_overrides(text: &str, overrides: &[Override]) -> Result<String> {
    let mut table: toml::Table = text.parse().context("the scene is not valid TOML")?;
    for (key, value) in overrides {
        let mut parts: Vec<&str> = key.split('.').collect();
        let last = parts
            .pop()
            .filter(|s| !s.is_empty())
            .ok_or_else(|| anyhow!("empty override key"))?;
        let mut t = &mut table;
        for p in parts {
            t = t
                .entry(p)
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .ok_or_else(|| anyhow!("override {key}: `{p}` is not a table"))?;
        }
        match value {
            Some(v) => t.insert(last.to_string(), v.clone()),
            None => t.remove(last),
        };
    }
    Ok(toml::to_string(&table)?)
}

/// Reads `[compare].friction_coeffs` [-], the friction values the harness runs.
pub fn friction_coeffs(text: &str) -> Result<Vec<f64>> {
    let table: toml::Table = text.parse().context("the scene is not valid TOML")?;
    let list = table
        .get("compare")
        .and_then(|c| c.get("friction_coeffs"))
        .and_then(|v| v.as_array())
        .ok_or_else(|| anyhow!("compare.friction_coeffs: missing; expected a list of numbers >= 0"))?;
    let mus = list
        .iter()
        .map(|v| v.as_float().or_else(|| v.as_integer().map(|i| i as f64)))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| anyhow!("compare.friction_coeffs: expected numbers"))?;
    if mus.is_empty() || mus.iter().any(|m| !(m.is_finite() && *m >= 0.0)) {
        return Err(anyhow!(
            "compare.friction_coeffs = {mus:?} out of range; allowed: a non-empty list of finite values >= 0"
        ));
    }
    Ok(mus)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_set_and_remove_nested_keys() {
        let out = with_overrides(
            "[a]\nx = 1.0\ny = 2\n",
            &[
                ("a.x", Some(toml::Value::Float(3.5))),
                ("a.y", None),
                ("b.z", Some(toml::Value::Integer(4))),
            ],
        )
        .unwrap();
        let t: toml::Table = out.parse().unwrap();
        assert_eq!(t["a"]["x"].as_float(), Some(3.5));
        assert!(t["a"].get("y").is_none());
        assert_eq!(t["b"]["z"].as_integer(), Some(4));
    }

    #[test]
    fn friction_list_is_read_and_checked() {
        assert_eq!(
            friction_coeffs("[compare]\nfriction_coeffs = [0, 0.3]\n").unwrap(),
            vec![0.0, 0.3]
        );
        let e = friction_coeffs("[compare]\nfriction_coeffs = [-0.1]\n").unwrap_err();
        assert!(e.to_string().contains("compare.friction_coeffs"), "{e}");
        assert!(friction_coeffs("name = 'x'\n").is_err());
    }
}
