//! Read-only observers of the state that emit the output records.

pub(crate) mod energy;
pub(crate) mod fields;
pub(crate) mod section4;
pub(crate) mod tips;
pub(crate) mod tractions;

use crate::model::state::{Model, State, Workspace};
use crate::records::{BoundaryRecord, ProbeRecord, ResidualStressRecord, RunOutput};
use nalgebra::Vector2;

/// An observer of sampled states.
pub trait Observer {
    /// Called at every sample time with the current state.
    fn observe(&mut self, model: &Model, state: &State, ws: &Workspace);
}

/// The observer that fills a `RunOutput` with every record.
pub struct Recorder<'a> {
    /// Destination.
    pub out: &'a mut RunOutput,
}

impl Observer for Recorder<'_> {
    fn observe(&mut self, model: &Model, state: &State, ws: &Workspace) {
        let out = &mut *self.out;
        out.tips.extend(tips::tips(model, state));
        tips::crack_records(model, state, &mut out.cracks);
        tips::crack_tip_records(model, state, &mut out.crack_tips);
        tips::interface_records(model, state, &mut out.interface);
        let mean = tractions::face_records(model, state, &mut out.faces);
        if state.contact.is_some() {
            out.contact.push(mean);
        }
        out.energy.push(energy::record(model, state, ws));
        section4(model, state, out);
        boundary_records(model, state, &mut out.boundary);
        for (k, &n) in model.observed.probes.iter().enumerate() {
            let n = n as usize;
            let (x, u, v) = (model.bulk.x0[n], state.u[n], state.v[n]);
            out.probes.push(ProbeRecord {
                t: state.t,
                probe: k,
                x: x.x,
                y: x.y,
                ux: u.x,
                uy: u.y,
                vx: v.x,
                vy: v.y,
            });
        }
    }
}

/// One record per part of `[fem.boundary]`: the mean displacement of its nodes and the sum of the
/// reactions and loads of the DOFs it holds or loads and of its dashpots' forces, each summed in
/// the DOFs' fixed order.
fn boundary_records(model: &Model, state: &State, out: &mut Vec<BoundaryRecord>) {
    let parts = &model.boundary.parts;
    let first = out.len();
    for (k, nodes) in parts.nodes.iter().enumerate() {
        let u: Vector2<f64> = nodes.iter().map(|&n| state.u[n as usize]).sum();
        let u = u / nodes.len().max(1) as f64;
        out.push(BoundaryRecord {
            t: state.t,
            part: k as u16,
            ux: u.x,
            uy: u.y,
            fx: 0.0,
            fy: 0.0,
        });
    }
    let mut add = |part: u16, dof: u8, f: f64| {
        let r = &mut out[first + part as usize];
        if dof == 0 { r.fx += f } else { r.fy += f }
    };
    for ((p, &part), &r) in model
        .boundary
        .prescribed
        .iter()
        .zip(&parts.prescribed)
        .zip(&state.presc_r)
    {
        add(part, p.dof, r);
    }
    for ((p, &part), &f) in model
        .boundary
        .neumann
        .iter()
        .zip(&parts.neumann)
        .zip(&state.neumann_f)
    {
        add(part, p.dof, f);
    }
    for (d, f) in model.boundary.dashpots.iter().zip(&state.dashpot_f) {
        add(d.part, 0, f.x);
        add(d.part, 1, f.y);
    }
}

/// The Section 4 diagnostics the scene declares (none by default).
fn section4(model: &Model, state: &State, out: &mut RunOutput) {
    let d = &model.observed.diagnostics;
    if let Some(range) = d.residual_stress_x {
        out.residual_stress.push(ResidualStressRecord {
            t: state.t,
            residual_stress: section4::residual_stress(model, state, range),
        });
    }
    if d.kkt_metric {
        out.kkt.push(section4::kkt(model, state));
    }
    let k = out.snapshot_times.len();
    if k < d.snapshot_times.len() && state.t >= d.snapshot_times[k] - 0.5 * model.dt {
        section4::snapshot(
            model,
            state,
            k,
            d.snapshot_window,
            &mut out.fields,
            &mut out.profiles,
        );
        out.snapshot_times.push(state.t);
    }
}
