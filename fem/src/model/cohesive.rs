//! Cohesive element forces (docs/fem-model.md §3.2): 2 + 2 nodes, 2-point Gauss, normal from the
//! current mid-line, traction from the pure law, scatter f⁺ −= (L₀/2) N T, f⁻ += (L₀/2) N T.

use crate::law::cohesive::{self, ClosingTreatment, CohesiveState, LinearCohesive};
use crate::mesh::interfaces::InterfaceRow;
use crate::model::state::{ElementForces, Facets, Model};
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
    let [a, b] = row.facet_columns(c);
    let xa = 0.5 * (pos(row.plus[a]) + pos(row.minus[a]));
    let xb = 0.5 * (pos(row.plus[b]) + pos(row.minus[b]));
    let t = (xb - xa).normalize();
    sign * Vector2::new(-t.y, t.x)
}

/// Adds the forces of every inserted cohesive element to `f`, updates the Gauss states, the
/// cumulative cohesive work E_coh,tot += (L₀/2)⟨T⟩·ΔΔ [J/m] and the failure times.
/// Returns the work increment [J/m]. The same as [`update`] then [`scatter`].
pub(crate) fn assemble(
    model: &Model,
    facets: &mut Facets,
    u: &[Vector2<f64>],
    f: &mut [Vector2<f64>],
    t: f64,
) -> f64 {
    each_element(model, facets, u, t, |row, c, forces| {
        add_forces(row, c, &forces, f)
    })
}

/// [`assemble`] without the forces' scatter: the Gauss states, work densities and failure times
/// updated, each active element's forces into `forces` (cleared first; its capacity is the row's
/// facets, so nothing is allocated), in the order of `facets.active`. Reads u only at the nodes
/// of the active facets. Returns the work increment [J/m].
pub(crate) fn update(
    model: &Model,
    facets: &mut Facets,
    u: &[Vector2<f64>],
    t: f64,
    forces: &mut Vec<ElementForces>,
) -> f64 {
    forces.clear();
    each_element(model, facets, u, t, |_, _, element_forces| {
        forces.push(element_forces)
    })
}

/// Every active element in the order of `facets.active`: its law updated, its forces handed to
/// `take` (with the row and the facet); returns the sum of their work increments [J/m].
fn each_element(
    model: &Model,
    facets: &mut Facets,
    u: &[Vector2<f64>],
    t: f64,
    mut take: impl FnMut(&InterfaceRow, usize, ElementForces),
) -> f64 {
    let Some(row) = &model.interface.row else {
        return 0.0;
    };
    let mut work = 0.0;
    for k in 0..facets.active.len() {
        let c = facets.active[k] as usize;
        let law = &model.interface.laws[model.interface.facet_law[c] as usize];
        let (forces, w) = element(model, row, law, facets, c, u, t);
        work += w;
        take(row, c, forces);
    }
    work
}

/// Adds the forces [`update`] computed to `f`, element by element in its order: the additions of
/// [`assemble`], in the same order.
pub(crate) fn scatter(model: &Model, facets: &Facets, forces: &[ElementForces], f: &mut [Vector2<f64>]) {
    let Some(row) = &model.interface.row else {
        return;
    };
    for (&c, element_forces) in facets.active.iter().zip(forces) {
        add_forces(row, c as usize, element_forces, f);
    }
}

fn add_forces(row: &InterfaceRow, c: usize, forces: &ElementForces, f: &mut [Vector2<f64>]) {
    for (&n, force) in element_nodes(row, c).iter().zip(forces) {
        f[n] += force;
    }
}

/// Nodes [a⁺, b⁺, a⁻, b⁻] of facet c's element.
fn element_nodes(row: &InterfaceRow, c: usize) -> [usize; 4] {
    let [a, b] = row.facet_columns(c);
    [row.plus[a], row.plus[b], row.minus[a], row.minus[b]].map(|n| n as usize)
}

fn element(
    model: &Model,
    row: &InterfaceRow,
    law: &LinearCohesive,
    facets: &mut Facets,
    c: usize,
    u: &[Vector2<f64>],
    t: f64,
) -> (ElementForces, f64) {
    let nodes = element_nodes(row, c);
    let un = nodes.map(|n| u[n]);
    let xn = nodes.map(|n| model.bulk.x0[n] + u[n]);
    let geometry = FacetGeometry {
        length: row.length[c],
        sign: facets.sign[c],
    };
    let mut states = facets.gauss[c];
    let out = element_forces(law, model.interface.closing, &geometry, &xn, &un, &mut states);
    let mut work = 0.0;
    for (q, state) in states.iter().enumerate() {
        // trapezoid ⟨T⟩·ΔΔ (Akantu): the discrete work of the nodal forces, which closes the balance
        let dw = 0.5
            * (out.traction[q] + facets.prev_traction[c][q])
                .dot(&(out.opening[q] - facets.prev_opening[c][q]));
        facets.work_density[c][q] += dw;
        work += 0.5 * geometry.length * dw;
        if state.damage >= 1.0 && facets.fail_time[c][q].is_nan() {
            facets.fail_time[c][q] = t;
        }
        facets.prev_opening[c][q] = out.opening[q];
        facets.prev_traction[c][q] = out.traction[q];
    }
    facets.gauss[c] = states;
    (out.force, work)
}

/// Reference length and orientation sign of a cohesive element.
#[derive(Debug, Clone, Copy)]
pub struct FacetGeometry {
    /// Reference length L₀ [m].
    pub length: f64,
    /// Sign s_e fixed at insertion so that n points from − into + [-].
    pub sign: f64,
}

/// Result of one cohesive element evaluation.
#[derive(Debug, Clone, Copy)]
pub struct CohesiveForces {
    /// Nodal forces on [a⁺, b⁺, a⁻, b⁻] [N/m].
    pub force: [Vector2<f64>; 4],
    /// Traction per Gauss point [Pa].
    pub traction: [Vector2<f64>; 2],
    /// Opening Δ = u⁺ − u⁻ per Gauss point [m].
    pub opening: [Vector2<f64>; 2],
}

/// One cohesive element (docs/fem-model.md §3.2), pure: nodes [a⁺, b⁺, a⁻, b⁻] with current positions
/// `x` [m] and displacements `u` [m]; normal from the current mid-line; Gauss states updated in place;
/// f⁺_k = −Σ_q (L₀/2) N_k T_q, f⁻_k = +Σ_q (L₀/2) N_k T_q.
pub fn element_forces(
    law: &LinearCohesive,
    closing: ClosingTreatment,
    geometry: &FacetGeometry,
    x: &[Vector2<f64>; 4],
    u: &[Vector2<f64>; 4],
    states: &mut [CohesiveState; 2],
) -> CohesiveForces {
    let xa = 0.5 * (x[0] + x[2]);
    let xb = 0.5 * (x[1] + x[3]);
    let tan = (xb - xa).normalize();
    let n = geometry.sign * Vector2::new(-tan.y, tan.x);
    let (open_a, open_b) = (u[0] - u[2], u[1] - u[3]);
    let half = 0.5 * geometry.length;
    let mut out = CohesiveForces {
        force: [Vector2::zeros(); 4],
        traction: [Vector2::zeros(); 2],
        opening: [Vector2::zeros(); 2],
    };
    for (q, &(_, n1, n2)) in facet_gauss().iter().enumerate() {
        let opening = n1 * open_a + n2 * open_b;
        let (traction, s) = cohesive::traction(law, closing, n, opening, states[q]);
        states[q] = s;
        out.traction[q] = traction;
        out.opening[q] = opening;
        let (fa, fb) = (half * n1 * traction, half * n2 * traction);
        out.force[0] -= fa;
        out.force[1] -= fb;
        out.force[2] += fa;
        out.force[3] += fb;
    }
    out
}

/// Reversible cohesive energy Σ (L₀/2) ½ T·Δ [J/m] of the inserted elements.
pub(crate) fn reversible_energy(model: &Model, facets: &Facets) -> f64 {
    let Some(row) = &model.interface.row else {
        return 0.0;
    };
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
