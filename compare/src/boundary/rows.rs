//! The records of the boundary study: which box and field a run used and how it agreed.

use serde::Serialize;

/// The boundary field of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Field {
    /// The case's field, paper eqs. (C.8)–(C.9) with the lateral contraction.
    Case,
    /// The exact elastic field: the case's plus the mode-II part of u_y that (C.9) drops.
    Exact,
}

/// One run of the study (a row of `boundary.csv`).
#[derive(Debug, Clone, Serialize)]
pub struct BoundaryRow {
    /// Box factor k: the FE box is 4ka × 2ka [-].
    pub box_factor: u32,
    /// Boundary field.
    pub field: Field,
    /// Friction coefficient μ [-].
    pub mu: f64,
    /// (t_on,FE − (t_on,SBI + a/c_d)) / T, signed: > 0 when the FE crack starts later [-].
    pub onset_lag_over_t: f64,
    /// RMS tip-position difference from a common origin, / a [-].
    pub tip_position_rms_over_a: f64,
    /// (v_FE − v_SBI)/v_SBI, mean speed between 1.2a and 1.9a, signed [-].
    pub mean_speed_difference: f64,
    /// Wall time of the FE run [s].
    pub wall_s: f64,
}
