//! Far-field loading: uniform s_xy(t), s_yy(t) through the smooth ramp of paper eq. (B.1), plus an
//! optional time-independent cos² shear bump for nucleation. Pure.

use crate::scene::{Nucleation, Ramp};

/// Paper eq. (B.1): S(s) = s³ (10 − 15 s + 6 s²), clamped to s ∈ [0, 1].
pub fn smooth_step(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)
}

/// Value of a ramp at time t [s]: initial + (final − initial) S((t − start)/(end − start)) [Pa];
/// a zero-length ramp is a step at `ramp_start`.
pub fn ramp_value(r: &Ramp, t: f64) -> f64 {
    let s = if r.ramp_end > r.ramp_start {
        (t - r.ramp_start) / (r.ramp_end - r.ramp_start)
    } else if t >= r.ramp_start {
        1.0
    } else {
        0.0
    };
    r.initial + (r.r#final - r.initial) * smooth_step(s)
}

/// Nucleation bump at x [m]: shear · cos²(π (x − center)/(2 half_width)) inside the half-width [Pa].
pub fn nucleation_shear(n: &Nucleation, x: f64) -> f64 {
    let d = (x - n.center) / n.half_width;
    if d.abs() >= 1.0 {
        0.0
    } else {
        n.shear * (0.5 * std::f64::consts::PI * d).cos().powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_is_smooth_and_reaches_final() {
        let r = Ramp {
            initial: 0.0,
            r#final: -5.0,
            ramp_start: 0.0,
            ramp_end: 2.0,
        };
        assert_eq!(ramp_value(&r, 0.0), 0.0);
        assert_eq!(ramp_value(&r, 1.0), -2.5);
        assert_eq!(ramp_value(&r, 3.0), -5.0);
        let step = Ramp { ramp_end: 0.0, ..r };
        assert_eq!(ramp_value(&step, 0.0), -5.0);
    }

    #[test]
    fn nucleation_bump_peaks_at_center_and_vanishes_outside() {
        let n = Nucleation {
            shear: 2.0,
            center: 1.0,
            half_width: 0.5,
        };
        assert_eq!(nucleation_shear(&n, 1.0), 2.0);
        assert!((nucleation_shear(&n, 1.25) - 1.0).abs() < 1e-15);
        assert_eq!(nucleation_shear(&n, 1.5), 0.0);
        assert_eq!(nucleation_shear(&n, -3.0), 0.0);
    }
}
