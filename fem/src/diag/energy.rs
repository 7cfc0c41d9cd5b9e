//! Energy record and balance residual (docs/fem-model.md §8.3):
//! W_ext + W_con = E_kin + E_strain + E_coh,tot + E_damp + E_abs up to O(Δt²).

use crate::model::cohesive::reversible_energy;
use crate::model::state::{Model, State, Workspace};
use crate::records::EnergyRecord;

/// Kinetic energy ½ Σ m |v|² [J/m].
pub(crate) fn kinetic(model: &Model, state: &State) -> f64 {
    0.5 * crate::model::reduce::ordered_sum(state.v.len(), |i| model.bulk.mass[i] * state.v[i].norm_squared())
}

/// Energy record at the current state (`ws.strain_energy` must be from this step).
pub(crate) fn record(model: &Model, state: &State, ws: &Workspace) -> EnergyRecord {
    let e = &state.energy;
    let kinetic = kinetic(model, state);
    let strain = ws.strain_energy;
    let rev = reversible_energy(model, &state.facets);
    let residual =
        e.boundary_work + e.contact_work - (kinetic + strain + e.cohesive_total + e.damping + e.absorbed);
    EnergyRecord {
        t: state.t,
        contact_stored: contact_stored(model, state),
        kinetic,
        strain,
        cohesive: e.cohesive_total,
        cohesive_dissipated: e.cohesive_total - rev,
        friction_dissipated: e.friction,
        damping_removed: e.damping,
        contact_work: e.contact_work,
        boundary_work: e.boundary_work,
        absorbed_work: e.absorbed,
        residual,
    }
}

/// Energy in the contact penalty springs, Σ w A (½ ε_n p² + T²/(2 ε_t)) over the slaves in
/// contact [J/m] (w = ½, Algorithm 1's averaging weight).
fn contact_stored(model: &Model, state: &State) -> f64 {
    let (Some(p), Some(cp)) = (&model.interface.contact, &state.contact) else {
        return 0.0;
    };
    let c = &cp.state;
    let w = crate::contact::AVERAGING_WEIGHT;
    c.in_node_order()
        .map(|(_, n)| n)
        .filter(|n| n.in_contact)
        .map(|n| {
            let t = n.tangential_traction;
            w * n.area * (0.5 * p.eps_n * n.penetration.powi(2) + t * t / (2.0 * p.eps_t))
        })
        .sum()
}

/// The friction audit of every slave that ever slid or carried friction.
pub(crate) fn friction_records(model: &Model, state: &State) -> Vec<crate::records::FrictionRecord> {
    let Some(cp) = &state.contact else {
        return Vec::new();
    };
    let c = &cp.state;
    c.in_node_order()
        .filter(|(_, n)| n.friction_work != 0.0 || n.coulomb_work != 0.0)
        .map(|(i, n)| crate::records::FrictionRecord {
            x: model.bulk.x0[i].x,
            y: model.bulk.x0[i].y,
            friction_work: n.friction_work,
            coulomb_work: n.coulomb_work,
        })
        .collect()
}
