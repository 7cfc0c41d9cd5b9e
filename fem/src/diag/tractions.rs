//! Contact fields on the upper face Γ1 ∪ Γ⁺coh (docs/fem-model.md §8.2): per-node records and the
//! area-weighted means T̄ⁿ = Σ A p_N / Σ A, T̄ᵗ = Σ A |T| / Σ A over contacting nodes.

use crate::mesh::interfaces::FacetKind;
use crate::model::state::{Model, State};
use crate::records::{ContactMeanRecord, FaceRecord};

/// Whether column i of the interface row touches a pre-crack or cohesive facet.
fn on_face(model: &Model, i: usize) -> bool {
    let row = model.interface.row.as_ref().expect("invariant: interface row");
    row.column_facets(i).any(|c| row.kind[c] != FacetKind::Plain)
}

/// Appends one record per upper-face node and returns the means.
pub(crate) fn face_records(model: &Model, state: &State, out: &mut Vec<FaceRecord>) -> ContactMeanRecord {
    let t = state.t;
    let mut mean = ContactMeanRecord {
        t,
        mean_normal_traction: 0.0,
        mean_tangential_traction: 0.0,
        max_penetration: 0.0,
        dropped_contacts_step: 0,
        dropped_contacts_total: 0,
    };
    let (Some(row), Some(cp)) = (&model.interface.row, &state.contact) else {
        return mean;
    };
    mean.dropped_contacts_step = cp.dropped_step;
    mean.dropped_contacts_total = cp.dropped_total;
    let cs = &cp.state;
    let (mut area, mut sn, mut st) = (0.0, 0.0, 0.0);
    for i in 0..row.plus.len() {
        if !on_face(model, i) {
            continue;
        }
        let n = row.plus[i] as usize;
        let c = cs.at(n);
        let (p, pn, tt) = if c.in_contact {
            (c.penetration, c.normal_pressure, c.tangential_traction.abs())
        } else {
            (0.0, 0.0, 0.0)
        };
        out.push(FaceRecord {
            t,
            // the + node's own x on a grid (the upper block may be offset), else the interface coordinate
            x: if model.grid().is_some() {
                model.bulk.x0[n].x
            } else {
                row.coord[i]
            },
            penetration: p,
            normal_traction: pn,
            tangential_traction: tt,
            chain: (row.num_chains() > 1).then_some(row.chain[i]),
        });
        if c.in_contact {
            area += c.area;
            sn += c.area * pn;
            st += c.area * tt;
            mean.max_penetration = mean.max_penetration.max(p);
        }
    }
    if area > 0.0 {
        mean.mean_normal_traction = sn / area;
        mean.mean_tangential_traction = st / area;
    }
    mean
}
