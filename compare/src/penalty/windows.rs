//! The time windows over which the centre crack's mean contact tractions are compared with the
//! far field (paper Figure 6c): one definition, read by the validation test and by the penalty
//! study (`compare penalty`, paper Appendix D).

/// Start of the normal-traction window, t/T [-]: the end of the compression's ramp, after which it
/// is held (its rate S' vanishes there, eq. B.1, so the faces follow without a jolt).
pub const NORMAL_WINDOW_START_OVER_T: f64 = 0.2;

/// Delay after the stick → slip transition before the tangential window starts, /T [-].
pub const SLIP_SETTLE_OVER_T: f64 = 0.05;

/// Time [s] of the first cohesive insertion anywhere on the interface (the onset of damage);
/// +∞ when nothing is inserted.
pub fn first_insertion(out: &fem::RunOutput) -> f64 {
    out.arrivals
        .iter()
        .map(|a| a.insertion_time)
        .filter(|t| t.is_finite())
        .fold(f64::INFINITY, f64::min)
}

/// First sample time [s] at which at least half of the contacting pre-crack face nodes
/// (|x − x_c| < a, p_N > 0) slip (|T| = μ p_N); +∞ when that never happens.
pub fn slip_time(scene: &fem::Scene, out: &fem::RunOutput) -> f64 {
    let (a, xc, mu) = (scene.half_length(), scene.center_x(), scene.friction_coeff);
    let mut times: Vec<f64> = out.faces.iter().map(|f| f.t).collect();
    times.dedup();
    for t in times {
        let rows = out
            .faces
            .iter()
            .filter(|f| f.t == t && (f.x - xc).abs() < a && f.normal_traction > 0.0);
        let (mut n, mut slipping) = (0, 0);
        for f in rows {
            n += 1;
            if f.tangential_traction >= (1.0 - 1e-9) * mu * f.normal_traction {
                slipping += 1;
            }
        }
        if n > 0 && 2 * slipping >= n {
            return t;
        }
    }
    f64::INFINITY
}

/// Mean of `value` over the contact records with t0 ≤ t ≤ t1; `None` for an empty window.
pub fn window_mean(
    out: &fem::RunOutput,
    t0: f64,
    t1: f64,
    value: impl Fn(&fem::ContactMeanRecord) -> f64,
) -> Option<f64> {
    let v: Vec<f64> = out
        .contact
        .iter()
        .filter(|c| c.t >= t0 && c.t <= t1)
        .map(value)
        .collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// The claim-3.6 windows of one run and the mean tractions over them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeanTractions {
    /// Onset of insertion (end of both windows) [s].
    pub onset: f64,
    /// Stick → slip time [s].
    pub slip: f64,
    /// Mean normal traction from NORMAL_WINDOW_START_OVER_T · T until onset [Pa]; `None` if empty.
    pub normal: Option<f64>,
    /// Mean tangential traction from slip + SLIP_SETTLE_OVER_T · T until onset [Pa]; `None` if
    /// empty (no slip before onset).
    pub tangential: Option<f64>,
}

/// Mean normal traction before onset and mean tangential traction while slipping (paper §3.3, Fig. 6c:
/// they should tend to |s_yy| and μ|s_yy|).
pub fn mean_tractions(scene: &fem::Scene, out: &fem::RunOutput) -> MeanTractions {
    let big_t = scene.duration();
    let onset = first_insertion(out);
    let slip = slip_time(scene, out);
    MeanTractions {
        onset,
        slip,
        normal: window_mean(out, NORMAL_WINDOW_START_OVER_T * big_t, onset, |c| {
            c.mean_normal_traction
        }),
        tangential: window_mean(out, slip + SLIP_SETTLE_OVER_T * big_t, onset, |c| {
            c.mean_tangential_traction
        }),
    }
}
