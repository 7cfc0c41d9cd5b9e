//! The shared problem of a scene as typed values: load ramps (paper eq. B.1), the pre-crack and
//! the far-field loading. Plain data; validated in `scene.rs`.

/// A ramp through the quintic smoothstep of paper eq. (B.1):
/// value(t) = initial + (final − initial) S((t − t₀)/(t₁ − t₀)), S(s) = s³(10 − 15s + 6s²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Value before the ramp (unit of the quantity: [Pa] or [m]).
    pub initial: f64,
    /// Value after the ramp (same unit).
    pub final_value: f64,
    /// Ramp start t₀ [s].
    pub ramp_start: f64,
    /// Ramp end t₁ [s] (t₁ = t₀ gives a step).
    pub ramp_end: f64,
}

impl Ramp {
    /// A constant zero.
    pub const ZERO: Ramp = Ramp {
        initial: 0.0,
        final_value: 0.0,
        ramp_start: 0.0,
        ramp_end: 0.0,
    };

    /// Value at time t [s].
    pub fn value(&self, t: f64) -> f64 {
        let s = if self.ramp_end > self.ramp_start {
            ((t - self.ramp_start) / (self.ramp_end - self.ramp_start)).clamp(0.0, 1.0)
        } else if t >= self.ramp_start {
            1.0
        } else {
            0.0
        };
        self.initial + (self.final_value - self.initial) * s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)
    }

    /// Rate d(value)/dt at time t [unit/s]: (final − initial) S'(s)/(t₁ − t₀) with
    /// S'(s) = 30 s²(1 − s)², 0 outside the ramp (and for a step).
    pub fn rate(&self, t: f64) -> f64 {
        let span = self.ramp_end - self.ramp_start;
        if span <= 0.0 || t <= self.ramp_start || t >= self.ramp_end {
            return 0.0;
        }
        let s = (t - self.ramp_start) / span;
        (self.final_value - self.initial) * 30.0 * s * s * (1.0 - s) * (1.0 - s) / span
    }

    /// Second derivative d²(value)/dt² at time t [unit/s²]: (final − initial) S''(s)/(t₁ − t₀)²
    /// with S''(s) = 60 s (1 − s)(1 − 2s), 0 outside the ramp (and for a step).
    pub fn acceleration(&self, t: f64) -> f64 {
        let span = self.ramp_end - self.ramp_start;
        if span <= 0.0 || t <= self.ramp_start || t >= self.ramp_end {
            return 0.0;
        }
        let s = (t - self.ramp_start) / span;
        (self.final_value - self.initial) * 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s) / (span * span)
    }
}

#[cfg(test)]
mod tests {
    use super::Ramp;

    #[test]
    fn rate_is_the_derivative_of_the_value() {
        let r = Ramp {
            initial: 1.0,
            final_value: 3.0,
            ramp_start: 1.0,
            ramp_end: 3.0,
        };
        for t in [1.2, 1.7, 2.0, 2.9] {
            let d = 1e-6;
            let fd = (r.value(t + d) - r.value(t - d)) / (2.0 * d);
            assert!((r.rate(t) - fd).abs() < 1e-8, "t = {t}: {} vs {fd}", r.rate(t));
        }
        assert_eq!(r.rate(0.5), 0.0);
        assert_eq!(r.rate(3.5), 0.0);
        // peak S'(½) = 15/8 over a span of 2 s and a rise of 2
        assert!((r.rate(2.0) - 15.0 / 8.0).abs() < 1e-12);
        for t in [1.2, 1.7, 2.0, 2.9] {
            let d = 1e-6;
            let fd = (r.rate(t + d) - r.rate(t - d)) / (2.0 * d);
            assert!(
                (r.acceleration(t) - fd).abs() < 1e-7,
                "t = {t}: {} vs {fd}",
                r.acceleration(t)
            );
        }
        assert_eq!(r.acceleration(0.5), 0.0);
        assert_eq!(r.acceleration(3.5), 0.0);
    }
}

/// Pre-crack on the row y = 0: |x − center_x| < half_length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crack {
    /// Half length a [m].
    pub half_length: f64,
    /// Centre x_c [m].
    pub center_x: f64,
}

/// Far-field loading: duration and the two stress histories (paper Section 3, docs/cases.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loading {
    /// Run duration T [s].
    pub duration: f64,
    /// Far-field normal stress σ_yy^∞(t) [Pa] (tension positive).
    pub normal: Ramp,
    /// Far-field shear stress σ_xy^∞(t) [Pa].
    pub shear: Ramp,
}
