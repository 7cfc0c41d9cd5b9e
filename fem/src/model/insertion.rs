//! Extrinsic insertion on declared cohesive facets (docs/fem-model.md §4, paper App. A): average of the
//! two neighbours' Gauss stresses extrapolated to each facet Gauss point; σ_eff = √(⟨σ_nn⟩₊² + τ²/β²);
//! insert when max_q σ_eff ≥ σ_c (or mean > σ_c); σ_c,eff = σ_eff, δ_c,eff = δ_c σ_c/σ_eff, T_ins = σ n.

use crate::law::cohesive::{CohesiveState, LinearCohesive};
use crate::mesh::interfaces::{FacetKind, InterfaceRow, NO_JUNCTION};
use crate::mesh::interfaces::{column_tied, tie_junction};
use crate::model::build::add_facet_faces;
use crate::model::cohesive::facet_gauss;
use crate::model::state::{ContactPart, Facets, Model, Reached};
use crate::model::stress::{self, Side};
use crate::scene::InsertionRule;
use nalgebra::Vector2;

/// Traction vector t_q = σ n_f [Pa] and effective stress σ_eff [Pa] at both Gauss points of facet c.
pub(crate) fn facet_tractions(
    model: &Model,
    row: &InterfaceRow,
    law: &LinearCohesive,
    c: usize,
    u: &[Vector2<f64>],
) -> [(Vector2<f64>, f64); 2] {
    let s = facet_gauss().map(|(s, _, _)| s);
    let sp = stress::facet_side(model, row, c, Side::Plus, u, s);
    let sm = stress::facet_side(model, row, c, Side::Minus, u, s);
    let n = row.normal[c];
    let tf = Vector2::new(n.y, -n.x);
    [0, 1].map(|q| {
        let (a, b) = (sp[q], sm[q]);
        let sig = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])];
        let t = Vector2::new(sig[0] * n.x + sig[2] * n.y, sig[2] * n.x + sig[1] * n.y);
        let (snn, tau) = (t.dot(&n), t.dot(&tf));
        let eff = (snn.max(0.0).powi(2) + (tau / law.beta).powi(2)).sqrt();
        (t, eff)
    })
}

/// Checks every candidate facet against σ_c under `u` and lists, in facet order, those that reach
/// it (`reached` is cleared first; its capacity is the row's facets, so nothing is allocated).
/// Reads the model, which facets are inserted and `u` only: it may run beside any phase that
/// writes neither, and [`insert_reached`] then does what checking and inserting facet by facet
/// would have done, since a facet's tractions do not depend on another's insertion.
pub(crate) fn check(model: &Model, facets: &Facets, u: &[Vector2<f64>], reached: &mut Vec<Reached>) {
    reached.clear();
    let Some(row) = &model.interface.row else {
        return;
    };
    if model.interface.laws.is_empty() {
        return;
    }
    for c in 0..row.num_facets() {
        if row.kind[c] != FacetKind::Cohesive || facets.inserted[c] {
            continue;
        }
        let law = &model.interface.laws[model.interface.facet_law[c] as usize];
        let tq = facet_tractions(model, row, law, c, u);
        let reach = match model.interface.insertion_rule {
            InsertionRule::Max => tq[0].1.max(tq[1].1) >= law.sigma_c,
            InsertionRule::Mean => 0.5 * (tq[0].1 + tq[1].1) > law.sigma_c,
        };
        if reach {
            reached.push((c as u32, tq));
        }
    }
}

/// Inserts the facets [`check`] listed, in its order, unties twins whose incident facets are all
/// open and extends Γ_det. Returns the number inserted.
pub(crate) fn insert_reached(
    model: &Model,
    facets: &mut Facets,
    tied_twin: &mut [u32],
    contact: Option<&mut ContactPart>,
    u: &[Vector2<f64>],
    t: f64,
    reached: &[Reached],
) -> usize {
    let Some(row) = &model.interface.row else {
        return 0;
    };
    let mut contact = contact;
    for (c, tq) in reached {
        let c = *c as usize;
        let law = &model.interface.laws[model.interface.facet_law[c] as usize];
        insert(model, row, law, facets, c, tq, u, t);
        let ends = row.facet_columns(c);
        for i in ends {
            facets.column_insert_time[i] = t;
        }
        if let Some(cp) = contact.as_deref_mut().filter(|_| model.interface.facet_detect[c]) {
            add_facet_faces(&mut cp.surface, row, c);
        }
        for i in ends {
            let j = row.col_junction[i];
            if j != NO_JUNCTION {
                tie_junction(row, &facets.inserted, j as usize, tied_twin);
            } else if !column_tied(row, &facets.inserted, i) {
                tied_twin[row.minus[i] as usize] = u32::MAX;
                tied_twin[row.plus[i] as usize] = u32::MAX;
            }
        }
    }
    reached.len()
}

#[allow(clippy::too_many_arguments)]
fn insert(
    model: &Model,
    row: &InterfaceRow,
    law: &LinearCohesive,
    facets: &mut Facets,
    c: usize,
    tq: &[(Vector2<f64>, f64); 2],
    u: &[Vector2<f64>],
    t: f64,
) {
    let centroid = |e: u32| {
        let nodes = model.element_nodes(e as usize);
        let nodes = nodes.as_slice();
        nodes
            .iter()
            .map(|&n| model.bulk.x0[n as usize] + u[n as usize])
            .sum::<Vector2<f64>>()
            / nodes.len() as f64
    };
    let n_plain = crate::model::cohesive::midline_normal(row, &model.bulk.x0, u, c, 1.0);
    let up = centroid(row.elem_plus[c]) - centroid(row.elem_minus[c]);
    facets.sign[c] = if n_plain.dot(&up) > 0.0 { 1.0 } else { -1.0 };
    for (q, &(traction, eff)) in tq.iter().enumerate() {
        facets.gauss[c][q] = CohesiveState::inserted(law, eff, traction);
        facets.prev_opening[c][q] = Vector2::zeros();
        facets.prev_traction[c][q] = traction;
    }
    facets.inserted[c] = true;
    facets.insert_time[c] = t;
    facets.active.push(c as u32);
}
