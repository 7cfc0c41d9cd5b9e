//! What the comparison and `converged` print at their end: the table of metrics with their
//! verdicts, the runs' warnings, where the files went, and the closing line that decides the
//! exit code.

use super::GateReport;
use super::metrics::{Verdict, open_metrics};
use anyhow::{Result, anyhow};
use std::path::Path;

/// Prints the end of a comparison written to `dir`; true when every metric passes or fails as
/// listed in `open` (METRIC@MU).
pub fn print_report(report: &GateReport, dir: &Path, open: &[String]) -> Result<bool> {
    print_table(&report.verdicts, open);
    crate::runner::print_warnings(&report.warnings);
    println!("\n{} files written to {}", report.files.len(), dir.display());
    verdict_line(&report.verdicts, open)
}

/// The table of metrics: value, tolerance and verdict (`yes`, `NO`, or `open` for a failing
/// metric listed in `open`), with the metric's note.
pub fn print_table(verdicts: &[Verdict], open: &[String]) {
    println!(
        "\n{:<38} {:>8} {:>12} {:>10} {:>6}",
        "metric", "mu", "value", "tolerance", "pass"
    );
    for v in verdicts {
        let line = format!(
            "{:<38} {:>8} {:>12.5} {:>10} {:>6} {}",
            v.metric,
            v.mu,
            v.value,
            v.tolerance,
            match (v.pass, open.contains(&format!("{}@{}", v.metric, v.mu))) {
                (true, _) => "yes",
                (false, true) => "open",
                (false, false) => "NO",
            },
            v.note
        );
        println!("{}", line.trim_end());
    }
}

/// The closing line; true when every metric passes or fails as listed in `open` (METRIC@MU).
pub fn verdict_line(verdicts: &[Verdict], open: &[String]) -> Result<bool> {
    let failing = open_metrics(verdicts, open).map_err(|e| anyhow!(e))?;
    Ok(closing_line(&failing, open, "docs/cases.md"))
}

/// Prints the closing line from the keys of the `failing` metrics and those listed `open`, whose
/// decisions `docs` tells; true when every failing one is listed (the comparison's and the suite's
/// exit code).
pub fn closing_line(failing: &[String], open: &[String], docs: &str) -> bool {
    let closed = failing.iter().filter(|f| !open.contains(f)).count();
    match (failing.len(), closed) {
        (0, _) => println!("all metrics within tolerance"),
        (n, 0) => println!(
            "{n} metric(s) FAIL, all open (decision pending, {docs}): {}",
            failing.join(", ")
        ),
        (n, c) => println!("{n} metric(s) FAIL ({c} not open)"),
    }
    closed == 0
}
