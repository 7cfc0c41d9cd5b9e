//! Cohesive element forces (fem-method §3.2): 2 + 2 nodes, 2-point Gauss, normal from the
//! current mid-line, traction from the pure law, scatter f⁺ −= (L₀/2) N T, f⁻ += (L₀/2) N T.

use crate::law::cohesive::{self, LinearCohesive};
use crate::mesh::interfaces::InterfaceRow;
use crate::model::state::{Facets, Model};
use nalgebra::Vector2;

/// Facet Gauss points s_q = ∓1/√3 and the shape functions (N₁, N₂) = ((1−s)/2, (1+s)/2) there.
pub(crate) fn facet_gauss() -> [(f64, f64, f64); 2] {
    let s = 1.0 / 3f64.sqrt();
    [
        (-s, 0.5 * (1.0 + s), 0.5 * (1.0 - s)),
        (s, 0.5 * (1.0 - s), 0.5 * (1.0 + s)),
    ]
}

/// Unit normal of facet c from the current mid-line, oriented by the sign fixed at insertion.
pub(crate) fn midline_normal(
    row: &InterfaceRow,
    x0: &[Vector2<f64>],
    u: &[Vector2<f64>],
    c: usize,
    sign: f64,
) -> Vector2<f64> {
    let pos = |n: u32| x0[n as usize] + u[n as usize];
    let xa = 0.5 * (pos(row.plus[c]) + pos(row.minus[c]));
    let xb = 0.5 * (pos(row.plus[c + 1]) + pos(row.minus[c + 1]));
    let t = (xb - xa).normalize();
    sign * Vector2::new(-t.y, t.x)
}

/// Adds the forces of every inserted cohesive element to `f`, updates the Gauss states, the
/// cumulative cohesive work E_coh,tot += (L₀/2)⟨T⟩·ΔΔ [J/m] and the failure times.
pub(crate) fn assemble(
    model: &Model,
    facets: &mut Facets,
    u: &[Vector2<f64>],
    f: &mut [Vector2<f64>],
    t: f64,
) -> f64 {
    let (Some(row), Some(law)) = (&model.iface, &model.law) else {
        return 0.0;
    };
    let mut work = 0.0;
    for k in 0..facets.active.len() {
        let c = facets.active[k] as usize;
        work += element(model, row, law, facets, c, u, f, t);
    }
    work
}

#[allow(clippy::too_many_arguments)]
fn element(
    model: &Model,
    row: &InterfaceRow,
    law: &LinearCohesive,
    facets: &mut Facets,
    c: usize,
    u: &[Vector2<f64>],
    f: &mut [Vector2<f64>],
    t: f64,
) -> f64 {
    let n = midline_normal(row, &model.grid.x0, u, c, facets.sign[c]);
    let (ap, bp, am, bm) = (
        row.plus[c] as usize,
        row.plus[c + 1] as usize,
        row.minus[c] as usize,
        row.minus[c + 1] as usize,
    );
    let (open_a, open_b) = (u[ap] - u[am], u[bp] - u[bm]);
    let half = 0.5 * row.length[c];
    let mut work = 0.0;
    for (q, &(_, n1, n2)) in facet_gauss().iter().enumerate() {
        let opening = n1 * open_a + n2 * open_b;
        let (traction, s) = cohesive::traction(law, model.closing, n, opening, facets.gauss[c][q]);
        work +=
            half * 0.5 * (traction + facets.prev_traction[c][q]).dot(&(opening - facets.prev_opening[c][q]));
        if s.damage >= 1.0 && facets.fail_time[c][q].is_nan() {
            facets.fail_time[c][q] = t;
        }
        facets.gauss[c][q] = s;
        facets.prev_opening[c][q] = opening;
        facets.prev_traction[c][q] = traction;
        let (fa, fb) = (half * n1 * traction, half * n2 * traction);
        f[ap] -= fa;
        f[bp] -= fb;
        f[am] += fa;
        f[bm] += fb;
    }
    work
}

/// Reversible cohesive energy Σ (L₀/2) ½ T·Δ [J/m] of the inserted elements.
pub(crate) fn reversible_energy(model: &Model, facets: &Facets) -> f64 {
    let Some(row) = &model.iface else { return 0.0 };
    facets
        .active
        .iter()
        .map(|&c| {
            let c = c as usize;
            (0..2)
                .map(|q| {
                    0.5 * row.length[c]
                        * cohesive::reversible_energy_density(
                            facets.prev_traction[c][q],
                            facets.prev_opening[c][q],
                        )
                })
                .sum::<f64>()
        })
        .sum()
}
