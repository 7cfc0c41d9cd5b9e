//! What the suite prints at its end: the table of metrics (`yes`, `NO`, or `open` for a failing
//! metric listed in `--open`), where the files went, and the closing line that decides the exit
//! code.

use super::{SuiteReport, SuiteRow};
use anyhow::{Result, bail};
use std::path::Path;

/// The key of a row in `--open`: `CASE:METRIC`.
fn key(r: &SuiteRow) -> String {
    format!("{}:{}", r.case, r.metric)
}

/// The failing rows' keys, after checking that every key of `open` names a row that fails (a
/// listed metric that passes is an error, so the list cannot outlive its cause).
pub fn open_rows(rows: &[SuiteRow], open: &[String]) -> Result<Vec<String>> {
    for o in open {
        match rows.iter().find(|r| key(r) == *o) {
            None => bail!("--open {o}: the suite has no such metric (CASE:METRIC as printed)"),
            Some(r) if r.pass => bail!(
                "--open {o}: the metric passes ({} {}); remove it from --open",
                r.value,
                r.tolerance
            ),
            Some(_) => {}
        }
    }
    Ok(rows.iter().filter(|r| !r.pass).map(key).collect())
}

/// Prints the metrics table and the files written; true when every metric passes or fails as
/// listed in `open` (`CASE:METRIC`: printed as `open`, out of the exit code).
pub fn print_report(report: &SuiteReport, dir: &Path, open: &[String]) -> Result<bool> {
    println!(
        "{:<16} {:<44} {:>10} {:>22} {:>6}",
        "case", "metric", "value", "tolerance", "pass"
    );
    for r in &report.rows {
        println!(
            "{:<16} {:<44} {:>10.5} {:>22} {:>6}",
            r.case,
            r.metric,
            r.value,
            r.tolerance,
            match (r.pass, open.contains(&key(r))) {
                (true, _) => "yes",
                (false, true) => "open",
                (false, false) => "NO",
            }
        );
    }
    println!(
        "\n{} files written to {} in {:.0} s",
        report.files.len(),
        dir.display(),
        report.wall_s
    );
    let failing = open_rows(&report.rows, open)?;
    Ok(crate::gate::verdict::closing_line(
        &failing,
        open,
        "docs/results.md",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--open` takes only rows that exist and fail; the failing keys come back whatever is open.
    #[test]
    fn open_lists_only_failing_rows() {
        let row = |case: &str, metric: &str, pass| SuiteRow {
            case: case.into(),
            metric: metric.into(),
            value: 1.0,
            tolerance: "<= 0.5".into(),
            pass,
        };
        let rows = [row("a", "x", true), row("a", "y", false), row("b", "x", false)];
        assert_eq!(
            open_rows(&rows, &[]).unwrap(),
            vec!["a:y".to_string(), "b:x".to_string()]
        );
        assert!(open_rows(&rows, &["a:y".into()]).is_ok());
        let passes = open_rows(&rows, &["a:x".into()]).unwrap_err().to_string();
        assert!(passes.contains("passes"), "{passes}");
        let missing = open_rows(&rows, &["c:x".into()]).unwrap_err().to_string();
        assert!(missing.contains("no such metric"), "{missing}");
    }
}
