//! A run's evolving state as its checkpoint holds it (`preflight::checkpoint`; `--checkpoint-every`,
//! `--resume`): everything the remaining steps read, and the records so far. A resumed run
//! rebuilds the model from the scene (`solver::build`: grid, law, kernels, weights or
//! sum-of-exponentials fit, FFT plans) and copies this state into the buffers it built, so that
//! the time loop allocates nothing more and continues from the very bits the stopped run had.
//!
//! What the state is (docs/spectral-model.md §4.2, one step: u^n → f^n → law → v^n, T^n →
//! u^{n+1}), taken after step n − 1 and the update u^n = u^{n−1} + Δt v^{n−1}:
//! - the face displacements u^n (§4.2 step 7);
//! - every grid point's [`Point`]: strengths and state (§5.1, irreversible), the regularised
//!   normal stress σ̃ (§5.3, eq. 14), and the last step's tractions and velocities;
//! - the convolution history of each half-space operator (both when `[material]` is split,
//!   §2.1): the direct path's ring buffers of past spectra with their write positions and count
//!   (§4.1), or the fast path's recursion states s_{j,p} (§4.3);
//! - the loop's position ([`Cursor`]) and the records so far (tips, contact means, field
//!   snapshots; the cost figures in stats.csv follow from the scene and the step).
//!
//! Nothing else carries over a step: the FFT, spectra and mode-sum buffers and the traction
//! buffer f are written by each step before that step reads them.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};

use crate::elastodynamics::{FaceFields, OperatorState};
use crate::error::RunError;
use crate::history::fill;
use crate::law::point::Point;
use crate::output::{ContactMeanRecord, FieldRecord, RunOutput, TipRecord};
use crate::solver::{Model, State, Workspace};

/// Where the time loop stands between two steps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct Cursor {
    /// Steps done: the next step to solve is n = `next_step` (t_n = n Δt) [-].
    pub next_step: u64,
    /// Index k of the next contact-means sample, taken at the first step with
    /// t ≥ k · `output_interval` [-].
    pub next_contact: u64,
    /// Index k of the next field snapshot, taken at the first step with
    /// t ≥ k · `field_output_interval` [-].
    pub next_field: u64,
}

impl Cursor {
    /// The start of a run.
    pub const START: Cursor = Cursor {
        next_step: 0,
        next_contact: 0,
        next_field: 0,
    };
}

/// The checkpoint's body: borrowed from the running state when written, owned when read back.
#[derive(Debug, Serialize, Deserialize)]
pub(crate) struct Saved<'a> {
    /// Where the loop stands.
    pub cursor: Cursor,
    /// Face displacements u^n [m].
    pub u: Cow<'a, FaceFields>,
    /// Per-point interface state, one per grid point.
    pub points: Cow<'a, [Point]>,
    /// The operator's convolution history.
    pub operator: OperatorState<'a>,
    /// Tip records so far, one per step done.
    pub tips: Cow<'a, [TipRecord]>,
    /// Contact-means records so far.
    pub contact: Cow<'a, [ContactMeanRecord]>,
    /// Field-snapshot records so far.
    pub fields: Cow<'a, [FieldRecord]>,
}

/// Time of the last step done [s] (0 before the first).
fn time_of(model: &Model, at: Cursor) -> f64 {
    at.next_step.saturating_sub(1) as f64 * model.dt
}

/// Writes the checkpoint of the state after step `at.next_step − 1` (the error names the file).
pub(crate) fn write(
    writer: &mut preflight::checkpoint::Writer,
    model: &Model,
    st: &State,
    ws: &Workspace,
    out: &RunOutput,
    at: Cursor,
) -> std::io::Result<()> {
    // exhaustive: a field added to the state is a compile error here until it is saved or said
    // to be rebuilt
    let State { u, points } = st;
    // the clock times this process's steps only
    let Workspace { half, f: _, clock: _ } = ws;
    let RunOutput {
        time_step: _,
        grid_spacing: _,
        tips,
        contact,
        fields,
        stats: _,
        profile: _,
        work: _,
    } = out;
    let saved = Saved {
        cursor: at,
        u: Cow::Borrowed(u),
        points: Cow::Borrowed(points),
        operator: half.saved(),
        tips: Cow::Borrowed(tips),
        contact: Cow::Borrowed(contact),
        fields: Cow::Borrowed(fields),
    };
    writer.write(at.next_step, time_of(model, at), &saved)
}

/// Restores the state of `resumed` into a freshly built model's state, workspace and records
/// (whose buffers keep their allocation) and returns where the loop resumes.
pub(crate) fn restore(
    resumed: &preflight::checkpoint::Resumed,
    st: &mut State,
    ws: &mut Workspace,
    out: &mut RunOutput,
) -> Result<Cursor, RunError> {
    let refused = |why: String| RunError::Resume {
        message: format!(
            "{}: its state does not fit the model this scene builds: {why}",
            preflight::checkpoint::FILE
        ),
    };
    let saved: Saved<'static> = resumed.state().map_err(|message| RunError::Resume { message })?;
    // exhaustive on both sides: a new field is a compile error, not a silent omission
    let Saved {
        cursor,
        u,
        points,
        operator,
        tips,
        contact,
        fields,
    } = saved;
    if cursor.next_step != resumed.header.step {
        return Err(refused(format!(
            "its header says step {}, its state step {}",
            resumed.header.step, cursor.next_step
        )));
    }
    let State {
        u: u_now,
        points: points_now,
    } = st;
    let FaceFields {
        top_x,
        top_y,
        bottom_x,
        bottom_y,
    } = u_now;
    fill(top_x, &u.top_x, "top x displacements").map_err(refused)?;
    fill(top_y, &u.top_y, "top y displacements").map_err(refused)?;
    fill(bottom_x, &u.bottom_x, "bottom x displacements").map_err(refused)?;
    fill(bottom_y, &u.bottom_y, "bottom y displacements").map_err(refused)?;
    fill(points_now, &points, "grid points").map_err(refused)?;
    // f is written by every step before it is read; the clock times this process's steps only
    let Workspace { half, f: _, clock: _ } = ws;
    half.restore(&operator).map_err(refused)?;
    let RunOutput {
        time_step: _,
        grid_spacing: _,
        tips: tips_now,
        contact: contact_now,
        fields: fields_now,
        stats,
        profile: _,
        work: _,
    } = out;
    if tips.len() as u64 != cursor.next_step {
        return Err(refused(format!(
            "{} tip records for {} steps",
            tips.len(),
            cursor.next_step
        )));
    }
    // reserved for the whole run by the caller: no reallocation
    tips_now.extend_from_slice(&tips);
    contact_now.extend_from_slice(&contact);
    fields_now.extend_from_slice(&fields);
    stats.steps = cursor.next_step;
    stats.last_step = cursor.next_step.saturating_sub(1);
    Ok(cursor)
}
