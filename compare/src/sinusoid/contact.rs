//! Paper Figure 11 from a snapshot: σ_yy along the upper face of the right weak branch (crack
//! faces only), the true contact zone (signed distance < 0) shaded and the nodes that carry a
//! compressive traction marked. In the standard model tractions also act where the faces are open.

use super::setup::{Setup, Snapshot};
use crate::output::write_rows;
use crate::plot::{self, Curve, Dash, Labels, PALETTE, Shading};
use anyhow::Result;
use plotters::style::RGBColor;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Shaded intervals around the nodes at `x` (increasing) flagged `inside`: each node covers half
/// the distance to each neighbour, at most half the median spacing (so a node next to a gap in
/// the samples does not cover the gap); touching intervals merge.
pub fn node_intervals(x: &[f64], inside: &[bool]) -> Vec<(f64, f64)> {
    let mut d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    d.sort_by(f64::total_cmp);
    let cap = 0.5 * d.get(d.len() / 2).copied().unwrap_or(0.0);
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (i, _) in inside.iter().enumerate().filter(|(_, f)| **f) {
        let left = i.checked_sub(1).map_or(cap, |j| (0.5 * (x[i] - x[j])).min(cap));
        let right = x.get(i + 1).map_or(cap, |xn| (0.5 * (xn - x[i])).min(cap));
        let (a, b) = (x[i] - left, x[i] + right);
        match out.last_mut() {
            Some(last) if a <= last.1 + 1e-12 * cap.max(f64::MIN_POSITIVE) => last.1 = b,
            _ => out.push((a, b)),
        }
    }
    out
}

/// One crack-face node of the right weak branch (`fig11_sigma_y_contact_<model>.csv`).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ContactRow {
    /// Reference x [m].
    pub x: f64,
    /// (x − x_c)/a [-].
    pub x_over_a: f64,
    /// σ_yy/σ_c^s at the node [-].
    pub syy_over_sigma_c: f64,
    /// True signed distance to the opposing face (> 0 open, < 0 in contact) [m].
    pub gap: f64,
    /// gap < 0.
    pub in_contact: bool,
    /// Compressive traction the node carries over σ_c^s [-] (plotted as its negative).
    pub compressive_traction_over_sigma_c: f64,
}

/// The Figure 11 rows of snapshot `k`: crack-face nodes of the right weak branch by x.
pub fn contact_rows(setup: &Setup, out: &fem::RunOutput, k: usize) -> Vec<ContactRow> {
    let mut rows: Vec<ContactRow> = out
        .profiles
        .iter()
        .filter(|p| p.snapshot == k && p.crack_face)
        .filter(|p| p.x >= setup.weak_right[0] && p.x <= setup.weak_right[1])
        .map(|p| ContactRow {
            x: p.x,
            x_over_a: setup.x_over_a(p.x),
            syy_over_sigma_c: p.syy / setup.sigma_c_strong,
            gap: p.gap,
            in_contact: p.gap < 0.0,
            compressive_traction_over_sigma_c: p.compressive_traction / setup.sigma_c_strong,
        })
        .collect();
    rows.sort_by(|a, b| a.x.total_cmp(&b.x));
    rows
}

/// One shaded contact interval (`fig11_contact_zones_<model>.csv`).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ZoneRow {
    /// Start (x − x_c)/a [-].
    pub x0_over_a: f64,
    /// End (x − x_c)/a [-].
    pub x1_over_a: f64,
}

/// Draws Figure 11 of one snapshot and writes its data; returns the files written.
pub fn contact_profile(dir: &Path, setup: &Setup, snap: &Snapshot) -> Result<Vec<PathBuf>> {
    let rows = contact_rows(setup, &snap.run.out, snap.k);
    let xs: Vec<f64> = rows.iter().map(|r| r.x_over_a).collect();
    let flags: Vec<bool> = rows.iter().map(|r| r.in_contact).collect();
    let zones = node_intervals(&xs, &flags);
    let curves = [
        Curve {
            label: "σyy/σc,strong on the upper face".into(),
            points: rows.iter().map(|r| (r.x_over_a, r.syy_over_sigma_c)).collect(),
            color: PALETTE[0],
            dash: Dash::Solid,
        },
        Curve {
            label: "−(compressive traction)/σc,strong at nodes carrying one".into(),
            points: rows
                .iter()
                .filter(|r| r.compressive_traction_over_sigma_c > 0.0)
                .map(|r| (r.x_over_a, -r.compressive_traction_over_sigma_c))
                .collect(),
            color: PALETTE[1],
            dash: Dash::Markers,
        },
    ];
    let shading = Shading {
        label: "true contact (gap < 0)".into(),
        intervals: zones.clone(),
        color: RGBColor(215, 215, 215),
    };
    let (m, t_over_t) = (&snap.run.model, snap.t_over_t);
    let png = dir.join(format!("fig11_sigma_y_contact_{m}.png"));
    let title = format!("Right weak branch, crack faces, {m} model, t/T = {t_over_t:.3}");
    let labels = Labels {
        title: &title,
        x: "(x − x_c)/a [-]",
        y: "σyy/σc,strong [-]",
    };
    plot::line_chart_shaded(&png, labels, &curves, &[], Some(&shading))?;
    let zone_rows: Vec<ZoneRow> = zones
        .iter()
        .map(|&(a, b)| ZoneRow {
            x0_over_a: a,
            x1_over_a: b,
        })
        .collect();
    Ok(vec![
        png,
        write_rows(&dir.join(format!("fig11_sigma_y_contact_{m}.csv")), &rows)?,
        write_rows(&dir.join(format!("fig11_contact_zones_{m}.csv")), &zone_rows)?,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contact_zones_span_half_the_node_spacing_and_merge() {
        let x = [1.0, 1.1, 1.2, 1.3, 1.4, 1.6, 1.7];
        let inside = [false, true, true, false, true, true, false];
        let z = node_intervals(&x, &inside);
        assert_eq!(z.len(), 3, "{z:?}");
        assert!(
            (z[0].0 - 1.05).abs() < 1e-12 && (z[0].1 - 1.25).abs() < 1e-12,
            "{z:?}"
        );
        // the gap 1.4 -> 1.6 is wider than the median spacing: each side covers only 0.05
        assert!(
            (z[1].0 - 1.35).abs() < 1e-12 && (z[1].1 - 1.45).abs() < 1e-12,
            "{z:?}"
        );
        assert!(
            (z[2].0 - 1.55).abs() < 1e-12 && (z[2].1 - 1.65).abs() < 1e-12,
            "{z:?}"
        );
        let z = node_intervals(&x, &[true, false, false, false, false, false, true]);
        assert!(
            (z[0].0 - 0.95).abs() < 1e-12 && (z[1].1 - 1.75).abs() < 1e-12,
            "{z:?}"
        );
        assert!(node_intervals(&x, &[false; 7]).is_empty());
    }
}
