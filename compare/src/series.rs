//! Crack-tip histories as time series, and the definitions every study and test shares: the
//! onset of propagation, the mean tip speed and the least-squares slope. Pure.
//!
//! Both models report the right and left crack tips of a centre crack loaded symmetrically
//! (the problem is invariant under a 180° rotation about the crack centre), so the harness
//! works with the crack half-length ℓ(t) = (x_right − x_left)/2 [m], the mean of the two tips'
//! distances to the centre. It halves the grid quantisation noise of either tip.

use serde::{Deserialize, Serialize};

/// One sample of a model's crack-tip history, exactly the columns of `fem_mu*.csv` and
/// `spectral_mu*.csv`: time [s] (unshifted), tip and cohesive-zone-tip x coordinates [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TipRow {
    /// Time [s], as the model reports it (no shift).
    pub t: f64,
    /// Right crack tip (fully broken) x [m].
    pub tip_right: f64,
    /// Left crack tip (fully broken) x [m].
    pub tip_left: f64,
    /// Right cohesive-zone tip x [m].
    pub cz_tip_right: f64,
    /// Left cohesive-zone tip x [m].
    pub cz_tip_left: f64,
}

/// One of the two tips of a centre crack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Tip {
    /// The tip at larger x (running in +x).
    Right,
    /// The tip at smaller x (running in −x).
    Left,
}

/// A sampled scalar history y(t); times strictly increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Times [s].
    pub t: Vec<f64>,
    /// Values (unit of the quantity).
    pub y: Vec<f64>,
}

impl Series {
    /// Crack half-length ℓ = (tip_right − tip_left)/2 [m] of a tip history.
    pub fn half_length(rows: &[TipRow]) -> Series {
        Series {
            t: rows.iter().map(|r| r.t).collect(),
            y: rows.iter().map(|r| 0.5 * (r.tip_right - r.tip_left)).collect(),
        }
    }

    /// Distance of one tip from the crack centre `center` [m]: x_right − center for the right tip,
    /// center − x_left for the left one. With two different half-spaces the tips run apart
    /// unlike each other, and each is compared on its own.
    pub fn tip_distance(rows: &[TipRow], center: f64, tip: Tip) -> Series {
        Series {
            t: rows.iter().map(|r| r.t).collect(),
            y: rows
                .iter()
                .map(|r| match tip {
                    Tip::Right => r.tip_right - center,
                    Tip::Left => center - r.tip_left,
                })
                .collect(),
        }
    }

    /// The same history with every time moved by `dt` [s] (t → t + dt).
    pub fn shifted(&self, dt: f64) -> Series {
        Series {
            t: self.t.iter().map(|t| t + dt).collect(),
            y: self.y.clone(),
        }
    }

    /// First time [s] at which y reaches `level` (y(t) ≥ level), linearly interpolated between
    /// the two samples that bracket it; `None` if it never does.
    pub fn first_crossing(&self, level: f64) -> Option<f64> {
        let i = self.y.iter().position(|&y| y >= level)?;
        if i == 0 {
            return Some(self.t[0]);
        }
        let (t0, t1, y0, y1) = (self.t[i - 1], self.t[i], self.y[i - 1], self.y[i]);
        Some(t0 + (t1 - t0) * (level - y0) / (y1 - y0))
    }

    /// Linear interpolation of y at time `t` [s]; `None` outside the sampled range.
    pub fn at(&self, t: f64) -> Option<f64> {
        let n = self.t.len();
        if n == 0 || t < self.t[0] || t > self.t[n - 1] {
            return None;
        }
        let j = self.t.partition_point(|&s| s <= t).clamp(1, n - 1);
        let (t0, t1) = (self.t[j - 1], self.t[j]);
        let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 0.0 };
        Some(self.y[j - 1] + w * (self.y[j] - self.y[j - 1]))
    }

    /// Local least-squares slope dy/dt over the samples within ±`half_width` [s] of each time.
    /// Crack tips move one facet or grid point at a time, so raw differences are useless; a
    /// window of a few h/c_R gives a usable speed (docs/fem-model.md §8.1). The window is in time, not
    /// in samples, so histories sampled at different rates get the same smoothing.
    pub fn slope(&self, half_width: f64) -> Series {
        let n = self.t.len();
        let y = (0..n)
            .map(|i| {
                let lo = self.t.partition_point(|&s| s < self.t[i] - half_width);
                let hi = self.t.partition_point(|&s| s <= self.t[i] + half_width);
                least_squares_slope(&self.t[lo..hi], &self.y[lo..hi])
            })
            .collect();
        Series { t: self.t.clone(), y }
    }
}

/// Crack advance that defines the onset of propagation, in units of a: the first time the
/// history exceeds its initial value by 0.05 a (6.25 mm at paper scale, about 6 elements).
/// Past onset the crack runs at ~c_R and covers this in ~0.002 T, so the choice moves the onset
/// by far less than any tolerance on it, while a smaller advance would count the quasi-static
/// creep of the tip.
pub const ONSET_ADVANCE_OVER_A: f64 = 0.05;

/// Onset time [s] of a crack-length history (the half-length ℓ, or one tip's distance from the
/// crack centre): the first time it exceeds its initial value by 0.05 a; `None`: never.
pub fn onset(length: &Series, a: f64) -> Option<f64> {
    let l0 = *length.y.first()?;
    length.first_crossing(l0 + ONSET_ADVANCE_OVER_A * a)
}

/// Mean tip speed [m/s] between half-lengths 1.2a and 1.9a; `None` if ℓ never reaches 1.9a.
pub fn mean_speed(half_length: &Series, a: f64) -> Option<f64> {
    let t1 = half_length.first_crossing(1.2 * a)?;
    let t2 = half_length.first_crossing(1.9 * a)?;
    (t2 > t1).then(|| 0.7 * a / (t2 - t1))
}

/// Slope dy/dx of the least-squares line through the points (x, y); 0 for fewer than two
/// distinct x.
pub fn least_squares_slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let xm = x.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (&xi, &yi) in x.iter().zip(y) {
        sxy += (xi - xm) * (yi - ym);
        sxx += (xi - xm) * (xi - xm);
    }
    if sxx > 0.0 { sxy / sxx } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> Series {
        // y = 0 until t = 1, then y = 2 (t − 1).
        let t: Vec<f64> = (0..=30).map(|i| i as f64 * 0.1).collect();
        let y = t.iter().map(|&t| (2.0 * (t - 1.0)).max(0.0)).collect();
        Series { t, y }
    }

    #[test]
    fn crossing_is_interpolated_between_samples() {
        let s = ramp();
        let tc = s.first_crossing(0.45).unwrap();
        assert!((tc - 1.225).abs() < 1e-12, "{tc}");
        assert_eq!(s.first_crossing(100.0), None);
    }

    #[test]
    fn shift_moves_crossings_by_the_shift() {
        let s = ramp();
        let a = s.first_crossing(1.0).unwrap();
        let b = s.shifted(0.25).first_crossing(1.0).unwrap();
        assert!((b - a - 0.25).abs() < 1e-12);
    }

    #[test]
    fn interpolation_is_exact_on_linear_data_and_none_outside() {
        let s = ramp();
        assert!((s.at(2.05).unwrap() - 2.1).abs() < 1e-12);
        assert_eq!(s.at(-0.1), None);
        assert_eq!(s.at(3.5), None);
    }

    #[test]
    fn slope_recovers_a_constant_speed() {
        let s = ramp();
        let v = s.slope(0.3);
        assert!((v.y[25] - 2.0).abs() < 1e-9);
        assert!(v.y[2].abs() < 1e-12);
    }

    #[test]
    fn half_length_is_the_mean_distance_of_the_tips() {
        let r = TipRow {
            t: 0.0,
            tip_right: 0.3,
            tip_left: -0.1,
            cz_tip_right: 0.3,
            cz_tip_left: -0.1,
        };
        assert!((Series::half_length(&[r]).y[0] - 0.2).abs() < 1e-15);
    }

    #[test]
    fn onset_is_an_advance_of_five_hundredths_of_a() {
        // ℓ = 1 until t = 1, then 1 + 2 (t − 1): ℓ = 1.05 at t = 1.025
        let s = Series {
            t: ramp().t,
            y: ramp().y.iter().map(|y| 1.0 + y).collect(),
        };
        assert!((onset(&s, 1.0).unwrap() - 1.025).abs() < 1e-12);
        assert_eq!(onset(&s, 100.0), None);
        // 1.2a → 1.9a in 0.35: 0.7a / 0.35 = 2
        assert!((mean_speed(&s, 1.0).unwrap() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn least_squares_slope_of_a_line_and_of_a_point() {
        assert!((least_squares_slope(&[0.0, 1.0, 2.0], &[1.0, 3.0, 5.0]) - 2.0).abs() < 1e-15);
        assert_eq!(least_squares_slope(&[1.0], &[4.0]), 0.0);
    }
}
