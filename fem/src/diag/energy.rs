//! Energy record and balance residual (docs/fem-model.md §8.3):
//! W_ext + W_con = E_kin + E_strain + E_coh,tot + E_damp up to O(Δt²).

use crate::model::cohesive::reversible_energy;
use crate::model::state::{Model, State, Workspace};
use crate::output::EnergyRecord;

/// Kinetic energy ½ Σ m |v|² [J/m].
pub(crate) fn kinetic(model: &Model, state: &State) -> f64 {
    0.5 * crate::model::reduce::ordered_sum(state.v.len(), |i| model.mass[i] * state.v[i].norm_squared())
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
        contact_stored: contact_stored(model, state),
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

/// Energy in the contact penalty springs, Σ w A (½ ε_n p² + T²/(2 ε_t)) over the slaves in
/// contact [J/m] (w = ½, Algorithm 1's averaging weight).
fn contact_stored(model: &Model, state: &State) -> f64 {
    let (Some(p), Some(cp)) = (&model.contact, &state.contact) else {
        return 0.0;
    };
    let c = &cp.state;
    let w = crate::contact::AVERAGING_WEIGHT;
    (0..c.in_contact.len())
        .filter(|&i| c.in_contact[i])
        .map(|i| {
            let t = c.tangential_traction[i];
            w * c.area[i] * (0.5 * p.eps_n * c.penetration[i].powi(2) + t * t / (2.0 * p.eps_t))
        })
        .sum()
}

/// The friction audit of every slave that ever slid or carried friction.
pub(crate) fn friction_records(model: &Model, state: &State) -> Vec<crate::output::FrictionRecord> {
    let Some(cp) = &state.contact else {
        return Vec::new();
    };
    let c = &cp.state;
    (0..c.friction_work.len())
        .filter(|&i| c.friction_work[i] != 0.0 || c.coulomb_work[i] != 0.0)
        .map(|i| crate::output::FrictionRecord {
            x: model.x0[i].x,
            y: model.x0[i].y,
            friction_work: c.friction_work[i],
            coulomb_work: c.coulomb_work[i],
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::output::RunOutput;

    /// Frictionless pressed blocks under a step pressure, stepped by hand; with `tamper`, the normal
    /// penalty is halved halfway through, while the springs are loaded: a contact force that no
    /// potential describes. Returns the audit error.
    fn audit(tamper: bool) -> f64 {
        let text = crate::test_scenes::scene_text("tiny-fem-contact-pressure").replace(
            "ramp_start = 0.0, ramp_end = 0.001 }",
            "ramp_start = 0.0, ramp_end = 0.0 }",
        );
        let scene = crate::Scene::from_toml_str(&text).unwrap();
        let (mut model, mut state, mut ws) = crate::build(&scene).unwrap();
        let steps = (scene.duration() / model.dt) as u64;
        let mut out = RunOutput::default();
        for n in 1..=steps {
            if tamper && n == steps / 2 {
                model.contact.as_mut().expect("invariant: contact").eps_n *= 0.5;
            }
            crate::step(&model, &mut state, &mut ws, true).unwrap();
            out.energy.push(super::record(&model, &state, &ws));
        }
        out.contact_conservation_error()
    }

    #[test]
    fn a_non_conservative_penalty_fails_the_audit() {
        let (honest, tampered) = (audit(false), audit(true));
        // the audit's tolerance in the validation test (fem_contact_energy) is 1 %: the honest
        // penalty passes it (measured 3.1e-3), the tampered one must fail it (measured 3.4e-2)
        const TOL: f64 = 0.01;
        assert!(honest < TOL, "honest penalty: {honest}");
        assert!(
            tampered > TOL,
            "a penalty halved while loaded must be caught: {tampered}"
        );
    }
}
