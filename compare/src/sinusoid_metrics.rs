//! Numbers of the Section 4 comparison (standard against hybrid cohesive-contact model) computed
//! from one FE run's records: KKT violations, residual stress (eq. 17), quasi-static check
//! (App. B) and crack-tip progress. The `compare -- sinusoid` command and the validation test
//! both use these definitions.

use fem::RunOutput;
use serde::Serialize;

/// Summary of one model's run on the sinusoidal-interface scene.
#[derive(Debug, Clone, Serialize)]
pub struct SinusoidSummary {
    /// "standard" or "hybrid".
    pub model: String,
    /// Largest share of crack-face nodes violating the KKT conditions, whole run [-].
    pub max_kkt_share: f64,
    /// First time the largest twin-pair slip exceeds 2h [s] (NaN: never).
    pub t_slip_2h: f64,
    /// Smallest KKT-violation share over the samples after `t_slip_2h` [-] (NaN: none).
    pub min_kkt_share_after_slip: f64,
    /// Largest compressive traction on a violating node, whole run [Pa].
    pub max_violating_traction: f64,
    /// Largest share of crack-face nodes where the contact zone (true distance < 0) and the
    /// traction zone (compressive traction > 0) differ, whole run [-].
    pub max_zone_mismatch_share: f64,
    /// Mean residual stress of eq. (17) over t ≥ T/2 [Pa].
    pub mean_residual_stress_second_half: f64,
    /// Residual stress at t = T [Pa].
    pub final_residual_stress: f64,
    /// Onset of propagation: first time the right crack tip passes a + 0.05a [s] (NaN: never).
    pub onset: f64,
    /// Largest E_kin/E_strain from the onset to T [-] (NaN without onset).
    pub max_kinetic_over_internal_after_onset: f64,
    /// Right crack tip at t = T [m].
    pub final_tip_right: f64,
    /// Right cohesive-zone tip at t = T [m].
    pub final_cz_tip_right: f64,
    /// First time the right crack tip reaches 2.4a: the weak branch has cracked and the crack is
    /// arrested at the strong interface (2.5a) [s] (NaN: never).
    pub t_weak_cracked: f64,
    /// First time the right crack tip passes 2.5a + 0.08a (l_p of the strong interface): the
    /// crack has entered the strong interface [s] (NaN: never).
    pub t_strong_entered: f64,
}

/// Mean residual stress of eq. (17) over samples with t0 ≤ t ≤ t1 [Pa] (NaN if none).
pub fn mean_residual_stress(out: &RunOutput, t0: f64, t1: f64) -> f64 {
    let v: Vec<f64> = out
        .residual_stress
        .iter()
        .filter(|r| r.t >= t0 && r.t <= t1)
        .map(|r| r.residual_stress)
        .collect();
    if v.is_empty() {
        f64::NAN
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Computes the summary; `a` is the pre-crack half-length [m], `h` the element size [m], `duration` T [s].
pub fn summarise(model: &str, out: &RunOutput, a: f64, h: f64, duration: f64) -> SinusoidSummary {
    let fmax = |it: &mut dyn Iterator<Item = f64>| it.fold(0.0, f64::max);
    let t_slip_2h = out
        .kkt
        .iter()
        .find(|r| r.max_slip > 2.0 * h)
        .map_or(f64::NAN, |r| r.t);
    let after: Vec<f64> = out
        .kkt
        .iter()
        .filter(|r| r.t >= t_slip_2h)
        .map(|r| r.violating_share)
        .collect();
    let min_after = after.iter().copied().fold(f64::NAN, f64::min);
    let second_half: Vec<f64> = out
        .residual_stress
        .iter()
        .filter(|r| r.t >= 0.5 * duration)
        .map(|r| r.residual_stress)
        .collect();
    let onset = out
        .tips
        .iter()
        .find(|r| r.tip_right > 1.05 * a)
        .map_or(f64::NAN, |r| r.t);
    let ratio = out
        .energy
        .iter()
        .filter(|e| e.t >= onset && e.strain > 0.0)
        .map(|e| e.kinetic / e.strain)
        .fold(f64::NAN, f64::max);
    let last_tip = out.tips.last();
    let first_tip_past = |x: f64| {
        out.tips
            .iter()
            .find(|r| r.tip_right >= x)
            .map_or(f64::NAN, |r| r.t)
    };
    SinusoidSummary {
        model: model.to_string(),
        max_kkt_share: fmax(&mut out.kkt.iter().map(|r| r.violating_share)),
        t_slip_2h,
        min_kkt_share_after_slip: min_after,
        max_violating_traction: fmax(&mut out.kkt.iter().map(|r| r.max_violating_traction)),
        max_zone_mismatch_share: fmax(
            &mut out
                .kkt
                .iter()
                .filter(|r| r.crack_face_nodes > 0)
                .map(|r| r.mismatch_nodes as f64 / r.crack_face_nodes as f64),
        ),
        mean_residual_stress_second_half: second_half.iter().sum::<f64>() / second_half.len().max(1) as f64,
        final_residual_stress: out.residual_stress.last().map_or(f64::NAN, |r| r.residual_stress),
        onset,
        max_kinetic_over_internal_after_onset: ratio,
        final_tip_right: last_tip.map_or(f64::NAN, |r| r.tip_right),
        final_cz_tip_right: last_tip.map_or(f64::NAN, |r| r.cz_tip_right),
        t_weak_cracked: first_tip_past(2.4 * a),
        t_strong_entered: first_tip_past(2.58 * a),
    }
}
