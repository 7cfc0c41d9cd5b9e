//! One explicit central-difference step in the order of docs/fem-model.md §9: predictor, prescribed
//! values, bulk + cohesive + contact + external forces, tied-pair accelerations, corrector,
//! insertion, 0.99 velocity scaling, energy bookkeeping. No I/O, no allocation.

use crate::model::state::{Model, State, Workspace};
use crate::model::{bulk, cohesive, insertion};
use crate::scene::DampingSet;
use rayon::prelude::*;
use std::time::Instant;

/// Where the stability guard fired.
#[derive(Debug, Clone, Copy)]
pub struct Blowup {
    /// Node id with a non-finite or runaway velocity.
    pub node: usize,
}

/// Advances the state by one step Δt. `sample`: also compute the strain energy into the workspace.
pub fn step(model: &Model, state: &mut State, ws: &mut Workspace, sample: bool) -> Result<(), Blowup> {
    let dt = model.dt;
    let t1 = state.t + dt;
    for (v, r) in ws.ramp_values.iter_mut().zip(&model.ramps) {
        *v = r.value(t1);
    }
    save_row_displacements(model, state, ws);
    predictor(state, dt);
    prescribe(model, state, ws, dt);
    bulk::internal_forces(&model.grid, &model.stiffness, &state.u, &mut ws.f);
    if sample {
        ws.strain_energy = bulk::strain_energy(&state.u, &ws.f);
    }
    let clock = Instant::now();
    state.energy.cohesive_total += cohesive::assemble(model, &mut state.facets, &state.u, &mut ws.f, t1);
    ws.cohesive_seconds += clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    super::contact_step::contact(model, state, ws);
    ws.contact_seconds += clock.elapsed().as_secs_f64();
    external_forces(model, state, ws);
    reactions(model, state, ws);
    combine_tied(model, state, ws);
    let vmax2 = corrector(model, state, ws, dt);
    restore_prescribed(model, state);
    state.step += 1;
    state.t = t1;
    let clock = Instant::now();
    insertion::check_and_insert(
        model,
        &mut state.facets,
        &mut state.tied_twin,
        state.contact.as_mut(),
        &state.u,
        t1,
    );
    ws.cohesive_seconds += clock.elapsed().as_secs_f64();
    damping(model, state);
    let limit = 10.0 * model.cd;
    if vmax2.is_nan() || vmax2 > limit * limit {
        let node = state
            .v
            .iter()
            .position(|v| v.norm().is_nan() || v.norm() > limit)
            .unwrap_or(0);
        return Err(Blowup { node });
    }
    Ok(())
}

fn save_row_displacements(model: &Model, state: &State, ws: &mut Workspace) {
    if let (Some(row), Some(_)) = (&model.iface, &state.contact) {
        let m = row.minus.len();
        for i in 0..m {
            ws.row_u_old[i] = state.u[row.minus[i] as usize];
            ws.row_u_old[m + i] = state.u[row.plus[i] as usize];
        }
    }
}

/// u += Δt v + ½Δt² a; v* = v + ½Δt a (every node; prescribed DOFs are overwritten next).
fn predictor(state: &mut State, dt: f64) {
    state
        .u
        .par_iter_mut()
        .zip(state.v.par_iter_mut())
        .zip(state.a.par_iter())
        .for_each(|((u, v), a)| {
            *u += dt * *v + 0.5 * dt * dt * *a;
            *v += 0.5 * dt * *a;
        });
}

/// u = ū(t_{n+1}) and v = (ū(t_{n+1}) − ū(t_n))/Δt on prescribed DOFs (docs/fem-model.md §2, §9 step 3).
fn prescribe(model: &Model, state: &mut State, ws: &Workspace, dt: f64) {
    for (k, p) in model.prescribed.iter().enumerate() {
        let ubar = p.value(&ws.ramp_values);
        let n = p.node as usize;
        let d = p.dof as usize;
        state.u[n][d] = ubar;
        state.v[n][d] = (ubar - state.presc_u[k]) / dt;
    }
}

fn external_forces(model: &Model, state: &mut State, ws: &mut Workspace) {
    for (k, p) in model.neumann.iter().enumerate() {
        let fnew = p.value(&ws.ramp_values);
        let n = p.node as usize;
        let d = p.dof as usize;
        // work of the nodal force over the increment just taken (trapezoidal); v holds v* = (u_{n+1} − u_n)/Δt
        let du = model.dt * state.v[n][d];
        state.energy.boundary_work += 0.5 * (state.neumann_f[k] + fnew) * du;
        state.neumann_f[k] = fnew;
        ws.f[n][d] += fnew;
    }
}

/// Boundary work of the prescribed DOFs, W_ext += ⟨R_s⟩ (ū_{n+1} − ū_n) + Δ(½ m v̄²), with the
/// static reaction R_s = −f (the force the support applies against the internal, contact and
/// cohesive forces) and v̄ = (ū_{n+1} − ū_n)/Δt.
///
/// # Deviation
/// Integrating the whole reaction R = m ā − f by the trapezoidal rule (docs/fem-model.md §8.3) is
/// the plain choice. Its inertial part m ā, with the backward-difference acceleration
/// ā = (v̄_{n+1} − v̄_n)/Δt, then differs from the kinetic-energy change of the node by
/// ½ m (ā² − v̄ j̄) Δt² per step, which sums to an O(Δt) error (first order, measured: 1.8e-4 J/m at
/// the end of the small scene's 0.1 ms normal ramp at α = 0.95, halving with α). The work of m ā on
/// a node whose motion is imposed is exactly the change of its kinetic energy, so that part is
/// booked exactly; the residual is then O(Δt²).
fn reactions(model: &Model, state: &mut State, ws: &Workspace) {
    for (k, p) in model.prescribed.iter().enumerate() {
        let n = p.node as usize;
        let d = p.dof as usize;
        let ubar = state.u[n][d];
        let vbar = state.v[n][d];
        let r = -ws.f[n][d];
        let inertia = 0.5 * model.mass[n] * (vbar * vbar - state.presc_v[k] * state.presc_v[k]);
        state.energy.boundary_work += 0.5 * (state.presc_r[k] + r) * (ubar - state.presc_u[k]) + inertia;
        state.presc_r[k] = r;
        state.presc_u[k] = ubar;
        state.presc_v[k] = vbar;
    }
}

/// Tied pairs move as one node: f⁻, f⁺ ← (f⁻ + f⁺) m^∓/(m⁻ + m⁺), so a = (f⁻+f⁺)/(m⁻+m⁺) on both.
fn combine_tied(model: &Model, state: &State, ws: &mut Workspace) {
    let Some(row) = &model.iface else { return };
    for i in 0..row.minus.len() {
        let (m, p) = (row.minus[i] as usize, row.plus[i] as usize);
        if state.tied_twin[m] != p as u32 {
            continue;
        }
        let (mm, mp) = (model.mass[m], model.mass[p]);
        let sum = ws.f[m] + ws.f[p];
        ws.f[m] = sum * (mm / (mm + mp));
        ws.f[p] = sum * (mp / (mm + mp));
    }
}

/// a = f/m, v = v* + ½Δt a; returns max |v|² (∞ if any velocity is not finite).
fn corrector(model: &Model, state: &mut State, ws: &Workspace, dt: f64) -> f64 {
    state
        .a
        .par_iter_mut()
        .zip(state.v.par_iter_mut())
        .zip(ws.f.par_iter().zip(model.mass.par_iter()))
        .map(|((a, v), (f, m))| {
            *a = *f / *m;
            *v += 0.5 * dt * *a;
            let v2 = v.norm_squared();
            if v2.is_finite() { v2 } else { f64::INFINITY }
        })
        .reduce(|| 0.0, f64::max)
}

fn restore_prescribed(model: &Model, state: &mut State) {
    for (k, p) in model.prescribed.iter().enumerate() {
        let n = p.node as usize;
        let d = p.dof as usize;
        state.v[n][d] = state.presc_v[k];
        state.a[n][d] = 0.0;
    }
}

/// Velocity scaling v ← c v on the damped set (docs/fem-model.md §6): contact slaves and cohesive nodes,
/// both twins of a tied pair, every free component (a prescribed component keeps its imposed
/// velocity, the other is damped like its neighbours'); the removed energy goes to E_damp.
fn damping(model: &Model, state: &mut State) {
    let Some(row) = &model.iface else { return };
    if model.damping == DampingSet::None {
        return;
    }
    let c = model.damping_factor;
    let in_contact = |n: usize| state.contact.as_ref().is_some_and(|cp| cp.state.in_contact[n]);
    let mut removed = 0.0;
    for i in 0..row.minus.len() {
        let (m, p) = (row.minus[i] as usize, row.plus[i] as usize);
        let inserted = state.facets.column_insert_time[i];
        let recent = |window: f64| state.t - inserted < window;
        let (coh, contact) = match model.damping {
            DampingSet::None => (false, false),
            DampingSet::ContactOnly => (false, true),
            DampingSet::Inserted { window } => (recent(window), false),
            DampingSet::ContactAndInserted { window } => (recent(window), true),
            DampingSet::AllCohesive => (!inserted.is_nan(), true),
        };
        let tied = state.tied_twin[m] == p as u32;
        let (mut dm, mut dp) = (coh || contact && in_contact(m), coh || contact && in_contact(p));
        if tied {
            dm |= dp;
            dp = dm;
        }
        for (node, on) in [(m, dm), (p, dp)] {
            if !on {
                continue;
            }
            for d in 0..2 {
                if !model.fixed_dof[node][d] {
                    let v = state.v[node][d];
                    removed += 0.5 * model.mass[node] * (1.0 - c * c) * v * v;
                    state.v[node][d] *= c;
                }
            }
        }
    }
    state.energy.damping += removed;
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;

    #[test]
    fn stability_guard_names_the_node() {
        let scene = Scene::from_toml_str(&crate::test_scenes::scene_text("tiny-fem-center-crack")).unwrap();
        let (model, mut state, mut ws) = crate::build(&scene).unwrap();
        super::step(&model, &mut state, &mut ws, false).unwrap();
        let interior = model.grid.node(5, 7) as usize;
        state.v[interior].x = f64::NAN;
        let err = super::step(&model, &mut state, &mut ws, false).unwrap_err();
        assert!(
            state.v[err.node].x.is_nan() || state.v[err.node].y.is_nan(),
            "node {}",
            err.node
        );
        let (model, mut state, mut ws) = crate::build(&scene).unwrap();
        state.v[interior] = nalgebra::Vector2::new(20.0 * model.cd, 0.0);
        let err = super::step(&model, &mut state, &mut ws, false).unwrap_err();
        assert!(
            state.v[err.node].norm() > 10.0 * model.cd,
            "|v| > 10 c_d is refused at node {}",
            err.node
        );
    }
}
