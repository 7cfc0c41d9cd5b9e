//! Step 6 of docs/fem-model.md §9: node-to-segment contact (hybrid model only), with the contact work
//! W_con += Σ ⟨f_con⟩·(u_{n+1} − u_n) and the friction dissipation.

use crate::contact::{self, ContactSummary};
use crate::model::state::{ContactPart, Model, State, Workspace};
use nalgebra::Vector2;

/// The positions x_{n+1} of Γ_det's nodes (only those are read by `resolve`) and, with
/// `contact_friction = "failed_only"`, which nodes have no friction this step.
pub(crate) fn prepare(model: &Model, state: &State, ws: &mut Workspace) {
    let (Some(_), Some(row), Some(_)) = (
        &model.interface.contact,
        &model.interface.row,
        state.contact.as_ref(),
    ) else {
        return;
    };
    for &n in row.minus.iter().chain(row.plus.iter()) {
        let n = n as usize;
        ws.x[n] = model.bulk.x0[n] + state.u[n];
    }
    if model.interface.friction_failed_only {
        failed_faces_only(row, &state.facets, &mut ws.frictionless);
    }
}

/// Detection and the contact law at the positions `x` into `f_con`; touches nothing the bulk
/// forces read or write, so it can run beside them.
pub(crate) fn detect(
    model: &Model,
    cp: Option<&mut ContactPart>,
    tied_twin: &[u32],
    x: &[Vector2<f64>],
    frictionless: &[bool],
    f_con: &mut [Vector2<f64>],
) -> Option<ContactSummary> {
    let (Some(params), Some(cp)) = (&model.interface.contact, cp) else {
        return None;
    };
    model.interface.row.as_ref()?;
    Some(contact::resolve(
        params,
        &mut cp.surface,
        x,
        tied_twin,
        frictionless,
        &mut cp.state,
        &mut cp.ws,
        f_con,
    ))
}

/// Adds the contact forces of [`detect`] into `ws.f`, with the contact work
/// W_con += Σ ⟨f_con⟩·(u_{n+1} − u_n) and the friction dissipation.
pub(crate) fn apply(model: &Model, state: &mut State, ws: &mut Workspace, summary: Option<ContactSummary>) {
    let (Some(summary), Some(row), Some(cp)) = (summary, &model.interface.row, state.contact.as_mut()) else {
        return;
    };
    state.energy.friction += summary.friction_dissipation;
    cp.max_penetration = summary.max_penetration;
    cp.dropped_step = summary.dropped;
    cp.dropped_total += summary.dropped as u64;
    let mut work = 0.0;
    for (slot, &node) in row.minus.iter().chain(row.plus.iter()).enumerate() {
        let n = node as usize;
        let fc = ws.f_con[n];
        let du = state.u[n] - ws.row_u_old[slot];
        work += 0.5 * (cp.f_prev[slot] + fc).dot(&du);
        cp.f_prev[slot] = fc;
        ws.f[n] += fc;
        ws.f_con[n] = Vector2::zeros();
    }
    state.energy.contact_work += work;
}

/// `contact_friction = "failed_only"`: friction is off on a node of column i unless every facet
/// touching the column is a pre-crack or a cohesive element that has fully failed (damage 1 at
/// both Gauss points), i.e. friction acts only where the interface has broken (paper §3.2). Called
/// before the step's cohesive law: the damage is that of the start of the step.
///
/// Per node, not per Gauss point, by measurement (docs/cases.md, decision 5): a rule that asks
/// only the Gauss point nearest the node on each side to have failed put the μ = 0.3 onset of the
/// centre crack 0.0032 T (h = 1 mm) and 0.0024 T (0.5 mm) from the spectral model's, this one
/// 0.0022 T and 0.0025 T.
fn failed_faces_only(
    row: &crate::mesh::interfaces::InterfaceRow,
    facets: &crate::model::state::Facets,
    frictionless: &mut [bool],
) {
    for i in 0..row.minus.len() {
        let broken = column_broken(row, facets, i);
        frictionless[row.minus[i] as usize] = !broken;
        frictionless[row.plus[i] as usize] = !broken;
    }
    // a junction's copy lies on several columns: friction only where all of them are broken
    for cols in &row.junctions {
        for &i in cols {
            let i = i as usize;
            if !column_broken(row, facets, i) {
                frictionless[row.minus[i] as usize] = true;
                frictionless[row.plus[i] as usize] = true;
            }
        }
    }
}

/// Every facet touching column i is a pre-crack or an inserted cohesive element broken at both
/// Gauss points.
fn column_broken(
    row: &crate::mesh::interfaces::InterfaceRow,
    facets: &crate::model::state::Facets,
    i: usize,
) -> bool {
    use crate::mesh::interfaces::FacetKind;
    row.column_facets(i).all(|c| match row.kind[c] {
        FacetKind::PreCrack => true,
        FacetKind::Cohesive => facets.inserted[c] && facets.gauss[c].iter().all(|g| g.damage >= 1.0),
        FacetKind::Plain => false,
    })
}
