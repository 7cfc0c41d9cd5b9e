//! CSV files of the harness, with the exact names and headers docs/outputs.md documents.

use crate::series::TipRow;
use anyhow::{Context, Result};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// File-name form of a friction coefficient: `0` for 0.0, `0.3` for 0.3.
pub fn mu_tag(mu: f64) -> String {
    format!("{mu}")
}

/// Writes `rows` as CSV with a header from the record's field names, whole or not at all
/// (`preflight::save`): the error names the file.
pub fn write_rows<R: Serialize>(path: &Path, rows: &[R]) -> Result<PathBuf> {
    preflight::save::atomically(path, |file| {
        let mut w = csv::Writer::from_writer(file);
        for r in rows {
            w.serialize(r).map_err(std::io::Error::other)?;
        }
        w.flush()
    })
    .context("writing a result table")?;
    Ok(path.to_path_buf())
}

/// `<model>_mu<μ>.csv` with header `t,tip_right,tip_left,cz_tip_right,cz_tip_left`.
pub fn write_tips(dir: &Path, model: &str, mu: f64, rows: &[TipRow]) -> Result<PathBuf> {
    write_rows(&dir.join(format!("{model}_mu{}.csv", mu_tag(mu))), rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_and_names_are_the_documented_ones() {
        let dir = std::env::temp_dir().join(format!("compare-output-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let row = TipRow {
            t: 0.0,
            tip_right: 0.125,
            tip_left: -0.125,
            cz_tip_right: 0.13,
            cz_tip_left: -0.13,
        };
        let p = write_tips(&dir, "fem", 0.0, &[row]).unwrap();
        assert!(p.ends_with("fem_mu0.csv"));
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(
            text.starts_with("t,tip_right,tip_left,cz_tip_right,cz_tip_left\n"),
            "{text}"
        );
        assert!(
            write_tips(&dir, "spectral", 0.3, &[row])
                .unwrap()
                .ends_with("spectral_mu0.3.csv")
        );
    }
}
