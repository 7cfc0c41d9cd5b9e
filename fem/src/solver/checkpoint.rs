//! What a checkpoint of the FE model holds (docs/checkpoints.md, `preflight::checkpoint`): the
//! whole evolving [`State`] (nodal vectors, facet states, tied pairs, contact surface and
//! history, σ̃, energy totals, boundary history), whether the free nodes already hold the next
//! step's predictor ([`Workspace::predicted`]), the records so far, and which ParaView snapshots
//! were taken. The model itself is rebuilt from the scene, which the checkpoint's header pins.

use crate::diag::fields::Snapshots;
use crate::model::state::{Model, State, Workspace};
use crate::records::RunOutput;
use serde::{Deserialize, Serialize};

/// A checkpoint's body as written: borrowed from the running loop.
#[derive(Serialize)]
pub(crate) struct Saving<'a> {
    state: &'a State,
    predicted: bool,
    out: &'a RunOutput,
    snapshot_last: Option<u64>,
    snapshots_taken: Vec<(f64, Vec<String>)>,
}

/// A checkpoint's body as read back.
#[derive(Deserialize)]
pub(crate) struct Saved {
    state: State,
    predicted: bool,
    out: RunOutput,
    snapshot_last: Option<u64>,
    snapshots_taken: Vec<(f64, Vec<String>)>,
}

/// Writes the checkpoint of the state after step `state.step` with `writer` (the error names
/// the file).
pub(crate) fn write(
    writer: &mut preflight::checkpoint::Writer,
    state: &State,
    ws: &Workspace,
    out: &RunOutput,
    snapshots: &Snapshots,
) -> std::io::Result<()> {
    let body = Saving {
        state,
        predicted: ws.predicted,
        out,
        snapshot_last: snapshots.last_taken(),
        snapshots_taken: snapshots.taken(),
    };
    writer.write(state.step, state.t, &body)
}

/// Puts a checkpoint's body in place of a freshly built run's state, workspace flag, records and
/// snapshot list. The arrays keep the capacities the build gave them, so the time loop still
/// does not allocate. A body whose arrays do not fit the model (another mesh) is refused.
pub(crate) fn restore(
    saved: Saved,
    model: &Model,
    state: &mut State,
    ws: &mut Workspace,
    out: &mut RunOutput,
    snapshots: &mut Snapshots,
) -> Result<(), String> {
    let Saved {
        state: mut back,
        predicted,
        out: records,
        snapshot_last,
        snapshots_taken,
    } = saved;
    let nodes = model.num_nodes();
    let facets = state.facets.inserted.len();
    if back.u.len() != nodes
        || back.facets.inserted.len() != facets
        || back.contact.is_some() != state.contact.is_some()
    {
        return Err(format!(
            "the checkpoint holds {} nodes and {} interface facets, the model {nodes} and {facets}",
            back.u.len(),
            back.facets.inserted.len()
        ));
    }
    let back_step = back.step;
    keep_capacity(&mut back.facets.active, &state.facets.active);
    if let (Some(b), Some(s)) = (back.contact.as_mut(), state.contact.as_mut()) {
        b.surface.keep_capacity(&s.surface);
        b.ws = std::mem::take(&mut s.ws);
    }
    *state = back;
    ws.predicted = predicted;
    // the wall times of the run so far are not kept: those of the resumed part are printed
    let profile = std::mem::take(&mut out.profile);
    *out = records;
    out.profile = profile;
    out.resumed_from = back_step;
    snapshots
        .resume(snapshot_last, snapshots_taken)
        .map_err(|e| format!("the stopped run's later snapshots: {e}"))
}

/// Reserves in `v` the capacity `like` has, so that pushing up to it does not allocate.
pub(crate) fn keep_capacity<T>(v: &mut Vec<T>, like: &Vec<T>) {
    v.reserve(like.capacity().saturating_sub(v.len()));
}
