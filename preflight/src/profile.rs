//! The table both models' commands print at the end of a run: where the time went, phase by
//! phase.

/// One row of a time profile.
#[derive(Debug, Clone, Copy)]
pub struct Row<'a> {
    /// The phase's name.
    pub phase: &'a str,
    /// Wall time spent in it [s].
    pub seconds: f64,
    /// It ran beside the others (on another thread): listed after the total, not summed into it.
    pub beside: bool,
}

/// The profile as an aligned text table: phase, seconds, share of the total, µs per step and ns
/// per unit-step, over `steps` steps of `units` units (elements, grid points), the last column
/// headed `unit_label` (e.g. `ns/elem-step`). Phases run beside the others follow the total.
pub fn table(rows: &[Row<'_>], steps: u64, units: u64, unit_label: &str) -> String {
    let total: f64 = rows.iter().filter(|r| !r.beside).map(|r| r.seconds).sum();
    let per = |s: f64, n: f64| if n > 0.0 { s / n } else { f64::NAN };
    let width = unit_label.len() + 2;
    let line = |name: &str, s: f64| {
        format!(
            "{:<18} {:>9.3} {:>6.1}% {:>10.1} {:>width$.2}\n",
            name,
            s,
            100.0 * per(s, total),
            1e6 * per(s, steps as f64),
            1e9 * per(s, steps as f64 * units as f64)
        )
    };
    let mut out = format!(
        "{:<18} {:>9} {:>7} {:>10} {:>width$}\n",
        "phase", "s", "share", "us/step", unit_label
    );
    for r in rows.iter().filter(|r| !r.beside) {
        out += &line(r.phase, r.seconds);
    }
    out += &line("total", total);
    for r in rows.iter().filter(|r| r.beside) {
        out += &line(&format!("{}, beside", r.phase), r.seconds);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_total_leaves_out_what_ran_beside_and_the_columns_follow_the_label() {
        let rows = [
            Row {
                phase: "forces",
                seconds: 3.0,
                beside: false,
            },
            Row {
                phase: "contact",
                seconds: 2.0,
                beside: true,
            },
            Row {
                phase: "law",
                seconds: 1.0,
                beside: false,
            },
        ];
        let t = table(&rows, 1000, 500, "ns/elem-step");
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(
            lines[0],
            "phase                      s   share    us/step   ns/elem-step"
        );
        assert_eq!(
            lines[1],
            "forces                 3.000   75.0%     3000.0        6000.00"
        );
        assert_eq!(
            lines[3],
            "total                  4.000  100.0%     4000.0        8000.00"
        );
        assert_eq!(
            lines[4],
            "contact, beside        2.000   50.0%     2000.0        4000.00"
        );
        assert!(
            table(&rows, 1, 1, "ns/point-step")
                .starts_with("phase                      s   share    us/step   ns/point-step")
        );
    }
}
