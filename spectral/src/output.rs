//! Output records and CSV writers (serde + csv); the only module that writes files.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::profile::{Profile, StepWork};

/// One sample of the crack-tip history (docs/solver-api.md). Positions are x coordinates [m] in the
/// scene frame (the pre-crack spans center_x ± half_length); t [s] is the time at which the
/// displacements that define the tips hold (t_n = n Δt, docs/spectral-model.md §8.8), unshifted.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TipRecord {
    /// Time t [s].
    pub t: f64,
    /// Right crack tip: last point of the contiguous fully broken set (state 2 or 3) walking right
    /// from the centre [m].
    pub tip_right: f64,
    /// Left crack tip [m].
    pub tip_left: f64,
    /// Right cohesive-zone tip: last point of the contiguous set with state ≥ 1 [m].
    pub cz_tip_right: f64,
    /// Left cohesive-zone tip [m].
    pub cz_tip_left: f64,
}

/// Contact means at one output time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactMeanRecord {
    /// Time t [s].
    pub t: f64,
    /// Far-field shear s_xy(t) [Pa].
    pub far_field_shear: f64,
    /// Far-field normal stress s_yy(t) [Pa] (< 0 compression).
    pub far_field_normal: f64,
    /// Contacting points on the pre-crack [-].
    pub contact_points: u32,
    /// Of those, points slipping [-].
    pub slipping_points: u32,
    /// Mean |T_2| over contacting pre-crack points [Pa].
    pub mean_normal_traction: f64,
    /// Mean |T_1| over contacting pre-crack points [Pa].
    pub mean_tangential_traction: f64,
    /// Largest signed T_2 over all contacting points [Pa] (≤ 0: never tensile); 0 if none.
    pub max_contact_normal_traction: f64,
    /// Largest interpenetration max(0, −δ_n) over the interface [m] at time t.
    pub max_penetration: f64,
}

/// Space-time field sample at one grid point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FieldRecord {
    /// Time t [s].
    pub t: f64,
    /// Grid point x [m].
    pub x: f64,
    /// Slip δ_t = u^+_1 − u^-_1 [m].
    pub slip: f64,
    /// Opening δ_n = u^+_2 − u^-_2 [m].
    pub opening: f64,
    /// Damage 1 − σ_s/σ_max [-].
    pub damage: f64,
    /// Point state: 0 intact, 1 cohesive, 2 broken, 3 broken in contact [-].
    pub state: u8,
    /// Shear traction T_1 [Pa].
    pub shear_traction: f64,
    /// Normal traction T_2 [Pa] (> 0 tension).
    pub normal_traction: f64,
    /// Top-face velocity, x [m/s].
    pub vx_top: f64,
    /// Top-face velocity, y [m/s].
    pub vy_top: f64,
    /// Bottom-face velocity, x [m/s].
    pub vx_bottom: f64,
    /// Bottom-face velocity, y [m/s].
    pub vy_bottom: f64,
}

/// Cost figures of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct RunStats {
    /// Steps solved (n = 0..=last) [-].
    pub steps: u64,
    /// Grid points N [-].
    pub grid_points: u64,
    /// Σ_j L_j stored history steps (direct path) [-].
    pub history_entries: u64,
    /// Bytes of history state streamed per step with full windows [B].
    pub bytes_per_step: u64,
    /// Exponential terms per kernel (fast path; 0 for direct) [-].
    pub exp_terms: u64,
    /// Fast path kernel-fit max error relative to max|K| [-].
    pub fit_error: f64,
    /// How the run ended: `finished` (it reached T), `interrupted` or `unstable`; every file of
    /// a run that did not finish ends at `last_step`.
    pub status: preflight::Status,
    /// Last step solved [-].
    pub last_step: u64,
}

/// Everything a run produces. Two outputs are equal when their records are: the wall times
/// ([`RunOutput::profile`]) differ between runs and are left out of the comparison.
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// Time step Δt [s].
    pub time_step: f64,
    /// Grid spacing Δx [m].
    pub grid_spacing: f64,
    /// Tip history, one record per step.
    pub tips: Vec<TipRecord>,
    /// Contact means every `output_interval`.
    pub contact: Vec<ContactMeanRecord>,
    /// Space-time fields every `field_output_interval` (empty if unset).
    pub fields: Vec<FieldRecord>,
    /// Cost figures.
    pub stats: RunStats,
    /// Wall time per phase of the steps this process computed (after its checkpoint, for a
    /// resumed run; profiling: printed by the binary, never written nor checkpointed).
    pub profile: Profile,
    /// Work of one step per phase, as the model counts it (bytes and flops; not measured).
    pub work: StepWork,
}

impl PartialEq for RunOutput {
    fn eq(&self, other: &RunOutput) -> bool {
        // every field named: a new one is a compile error here until it is compared or left out
        let RunOutput {
            time_step,
            grid_spacing,
            tips,
            contact,
            fields,
            stats,
            profile: _,
            work,
        } = self;
        *time_step == other.time_step
            && *grid_spacing == other.grid_spacing
            && *tips == other.tips
            && *contact == other.contact
            && *fields == other.fields
            && *stats == other.stats
            && *work == other.work
    }
}

fn write<T: Serialize>(path: PathBuf, records: &[T]) -> std::io::Result<PathBuf> {
    // whole or not at all, the error naming the file (docs/outputs.md)
    preflight::save::atomically(&path, |file| {
        let mut w = csv::Writer::from_writer(file);
        for r in records {
            w.serialize(r).map_err(std::io::Error::other)?;
        }
        w.flush()
    })?;
    Ok(path)
}

/// Every file [`write_csv`] may write (fields.csv only with field snapshots).
pub const CSV_FILES: [&str; 4] = ["tips.csv", "contact.csv", "fields.csv", "stats.csv"];

/// Removes from `dir` the files of an earlier run ([`CSV_FILES`]), so that a run without field
/// snapshots does not leave an older fields.csv beside its own files. Returns how many were
/// removed. Only for a folder claimed by this model (`preflight::paths::claim`).
pub fn clear_previous(dir: &Path) -> std::io::Result<usize> {
    preflight::paths::remove_files(CSV_FILES.iter().map(|name| dir.join(name)))
}

/// Writes tips.csv, contact.csv and (if any) fields.csv into `dir` (created if needed).
pub fn write_csv(out: &RunOutput, dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    let mut files = vec![
        write(dir.join("tips.csv"), &out.tips)?,
        write(dir.join("contact.csv"), &out.contact)?,
    ];
    if !out.fields.is_empty() {
        files.push(write(dir.join("fields.csv"), &out.fields)?);
    }
    files.push(write(dir.join("stats.csv"), &[out.stats])?);
    Ok(files)
}
