//! Energy record and balance residual (docs/fem-model.md §8.3):
//! W_ext + W_con = E_kin + E_strain + E_coh,tot + E_damp up to O(Δt²).

use crate::model::cohesive::reversible_energy;
use crate::model::state::{Model, State, Workspace};
use crate::output::EnergyRecord;
use rayon::prelude::*;

/// Kinetic energy ½ Σ m |v|² [J/m].
pub(crate) fn kinetic(model: &Model, state: &State) -> f64 {
    0.5 * state
        .v
        .par_iter()
        .zip(model.mass.par_iter())
        .map(|(v, m)| m * v.norm_squared())
        .sum::<f64>()
}

/// Energy record at the current state (`ws.strain_energy` must be from this step).
pub(crate) fn record(model: &Model, state: &State, ws: &Workspace) -> EnergyRecord {
    let e = &state.energy;
    let kinetic = kinetic(model, state);
    let strain = ws.strain_energy;
    let rev = reversible_energy(model, &state.facets);
    let residual = e.boundary_work + e.contact_work - (kinetic + strain + e.cohesive_total + e.damping);
    EnergyRecord {
        t: state.t,
        kinetic,
        strain,
        cohesive: e.cohesive_total,
        cohesive_dissipated: e.cohesive_total - rev,
        friction_dissipated: e.friction,
        damping_removed: e.damping,
        contact_work: e.contact_work,
        boundary_work: e.boundary_work,
        residual,
    }
}
