//! Numbers of the Section 4 comparison (standard against hybrid cohesive-contact model) computed
//! from one FE run's records: KKT violations, residual stress (eq. 17), quasi-static check
//! (App. B) and crack-tip progress. The `compare sinusoid` command and the validation test both
//! use these definitions.

use crate::quasi_static::max_ratio;
use crate::series::{Series, onset};
use fem::RunOutput;
use serde::Serialize;

/// Delay after the onset of propagation before the quasi-static check of Appendix B starts, in
/// units of T [-]: the 0.9a-long process zone of the weak branch fails at once at the onset (a
/// dynamic event by nature); 0.05 T later the crack runs along the weak branch under the slowly
/// growing shear.
pub const QUASI_STATIC_AFTER_ONSET_OVER_T: f64 = 0.05;

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
    /// Largest E_kin/E_strain from 0.05 T after the onset to T [-] (Appendix B in its
    /// quasi-static phase; NaN without onset).
    pub max_kinetic_over_internal_quasi_static: f64,
    /// Largest E_kin/E_strain of the whole run [-] (the paper's literal claim).
    pub max_kinetic_over_internal: f64,
    /// Right crack tip at t = T [m].
    pub final_tip_right: f64,
    /// Right cohesive-zone tip at t = T [m].
    pub final_cz_tip_right: f64,
    /// Time the right crack tip reaches 2.4a: the weak branch has cracked and the crack is
    /// arrested at the strong interface (2.5a) [s] (NaN: never). From the per-point failure
    /// times, so exact to the time step rather than to the output interval.
    pub t_weak_cracked: f64,
    /// Time the right crack tip passes 2.5a + 0.08a (l_p of the strong interface): the crack has
    /// entered the strong interface [s] (NaN: never). Exact to the time step, as above.
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

/// Time [s] the right crack tip (docs/fem-model.md §8.1: every interface point from the pre-crack tip on
/// fully broken) passes x > a: the latest full-failure time of the points with a < x_q ≤ x (NaN
/// if one of them never fails). Pre-crack centred at 0, as in the Section 4 scene.
pub fn tip_passes(out: &RunOutput, a: f64, x: f64) -> f64 {
    out.arrivals
        .iter()
        .filter(|r| r.x > a && r.x <= x)
        .map(|r| r.failure_time)
        .try_fold(f64::NEG_INFINITY, |m: f64, t: f64| {
            (!t.is_nan()).then_some(m.max(t))
        })
        .filter(|t| t.is_finite())
        .unwrap_or(f64::NAN)
}

/// Computes the summary; `a` is the pre-crack half-length [m] (centred at x = 0, as in the
/// Section 4 scene), `h` the element size [m], `duration` T [s].
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
    let right_tip = Series {
        t: out.tips.iter().map(|r| r.t).collect(),
        y: out.tips.iter().map(|r| r.tip_right).collect(),
    };
    let onset = onset(&right_tip, a).unwrap_or(f64::NAN);
    let from = onset + QUASI_STATIC_AFTER_ONSET_OVER_T * duration;
    let ratio = |t0: f64| max_ratio(out, t0, f64::INFINITY).map_or(f64::NAN, |m| m.0);
    let last_tip = out.tips.last();
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
        max_kinetic_over_internal_quasi_static: if from.is_finite() { ratio(from) } else { f64::NAN },
        max_kinetic_over_internal: ratio(0.0),
        final_tip_right: last_tip.map_or(f64::NAN, |r| r.tip_right),
        final_cz_tip_right: last_tip.map_or(f64::NAN, |r| r.cz_tip_right),
        t_weak_cracked: tip_passes(out, a, 2.4 * a),
        t_strong_entered: tip_passes(out, a, 2.58 * a),
    }
}

#[cfg(test)]
mod tests {
    use super::tip_passes;
    use fem::{ArrivalRecord, RunOutput};

    fn point(x: f64, failure_time: f64) -> ArrivalRecord {
        ArrivalRecord {
            x,
            insertion_time: f64::NAN,
            failure_time,
            work_density: 0.0,
            chain: None,
        }
    }

    #[test]
    fn the_tip_passes_x_when_every_point_from_the_pre_crack_tip_to_x_has_failed() {
        let a = 1.0;
        let out = RunOutput {
            arrivals: vec![
                point(-1.5, 9.0),     // left branch: ignored
                point(0.5, f64::NAN), // pre-crack: never inserted, ignored
                point(1.1, 2.0),
                point(1.2, 1.5), // failed before its left neighbour: the tip waits for 1.1
                point(1.3, 3.0),
                point(1.4, f64::NAN),
            ],
            ..RunOutput::default()
        };
        assert_eq!(tip_passes(&out, a, 1.2), 2.0);
        assert_eq!(tip_passes(&out, a, 1.3), 3.0);
        assert!(tip_passes(&out, a, 1.45).is_nan(), "1.4 never failed");
        assert!(tip_passes(&out, a, 1.05).is_nan(), "no point in (a, x]");
    }
}
