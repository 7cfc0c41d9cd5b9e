//! `fem.interface_rough`: the interface row follows a self-affine rough profile, the outlook of
//! Pundir & Anciaux (2020), Section 5 (a crack along a rough interface whose faces interlock).
//!
//! The profile is made by spectral synthesis with random phases: on each branch
//! (from ≤ |x − x_c| ≤ to, length L = to − from, s = |x − x_c| − from),
//!
//! ```text
//! z(s) = Σ_k q_k^{-(1+2H)/2} cos(q_k s + φ_k),   q_k = 2πk/L,   λ_min ≤ L/k ≤ λ_max,
//! ```
//!
//! so that its power spectrum is C(q) ∝ q^{-(1+2H)} between the cut-offs (a self-affine profile
//! of Hurst exponent H; Persson et al. 2005, J. Phys.: Condens. Matter 17 R1, eq. 5, 1D form).
//! The amplitudes are the spectrum's, the phases φ_k uniform in [0, 2π) from ChaCha8 seeded with
//! `seed` (right branch first, then left: the two branches are independent). The profile is
//! multiplied by a Tukey window (sin² ramps of length `taper` at both ends, so it is zero where
//! it joins the flat row) and scaled so that the RMS slope of the sampled row, the finite
//! differences between node columns over both branches, is `rms_slope` exactly.
//!
//! Every operation is IEEE arithmetic, ChaCha's specified stream and `libm` (pure Rust): the row
//! is the same to the bit on every platform.

use super::checks::{check, inconsistent};
use super::raw::RawFem;
use crate::error::SceneError;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use std::f64::consts::{PI, TAU};

/// Fewest elements per shortest wavelength [-]: the row is piecewise linear between node
/// columns, and a sine sampled at n points per period keeps sin(π/n)/(π/n) of its RMS slope,
/// 90 % at n = 4 (a coarser sampling would be a different profile than the spectrum says).
pub(crate) const MIN_ELEMENTS_PER_WAVELENGTH: f64 = 4.0;

/// Default taper length over the longest wavelength [-]: a sin² ramp of length λ_max/4 adds
/// little slope where the long waves are tall, and leaves the middle of a branch untouched.
const DEFAULT_TAPER_OVER_WAVELENGTH_MAX: f64 = 0.25;

/// A validated `fem.interface_rough` (lengths [m]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rough {
    /// Hurst exponent H [-], in (0, 1).
    pub hurst: f64,
    /// RMS slope of the sampled row over both branches [-].
    pub rms_slope: f64,
    /// Seed of the phases.
    pub seed: u64,
    /// Inner end of each branch, distance from the crack centre [m].
    pub from: f64,
    /// Outer end of each branch [m].
    pub to: f64,
    /// Shortest wavelength [m].
    pub wavelength_min: f64,
    /// Longest wavelength [m].
    pub wavelength_max: f64,
    /// Length of each sin² ramp of the taper [m].
    pub taper: f64,
}

/// Key of a field, as written.
fn key(name: &str) -> String {
    format!("fem.interface_rough.{name}")
}

/// The mode numbers k with λ_min ≤ L/k ≤ λ_max (a relative 1e-12 of slack, so that a wavelength
/// given as L/k exactly is in).
fn mode_range(period: f64, wavelength_min: f64, wavelength_max: f64) -> std::ops::RangeInclusive<u64> {
    let lo = (period / wavelength_max * (1.0 - 1e-12)).ceil().max(1.0) as u64;
    let hi = (period / wavelength_min * (1.0 + 1e-12)).floor() as u64;
    lo..=hi
}

/// Checks every field of `fem.interface_rough` that needs no other key, adding each problem to
/// `errors`. `Some(None)`: no rough interface; `None`: there was a problem.
pub(crate) fn rough(f: &RawFem, errors: &mut Vec<SceneError>) -> Option<Option<Rough>> {
    let Some(r) = &f.interface_rough else {
        return Some(None);
    };
    let before = errors.len();
    let length = r.to - r.from;
    let taper = r
        .taper
        .unwrap_or(DEFAULT_TAPER_OVER_WAVELENGTH_MAX * r.wavelength_max);
    let exclusive = (f.interface_sine.is_some() || f.interface_polyline.is_some()).then(|| {
        inconsistent(
            "fem.interface_rough",
            "give one of fem.interface_polyline, fem.interface_sine and fem.interface_rough, not two",
        )
    });
    let seed = (r.seed < 0).then(|| {
        inconsistent(
            key("seed"),
            format!("{} is negative; give a whole number >= 0", r.seed),
        )
    });
    let found = [
        exclusive,
        check(
            key("hurst"),
            r.hurst,
            r.hurst > 0.0 && r.hurst < 1.0,
            "(0, 1) (Hurst exponent H; the spectrum is C(q) ∝ q^-(1+2H))",
        )
        .err(),
        check(
            key("rms_slope"),
            r.rms_slope,
            r.rms_slope > 0.0,
            "> 0 (RMS of dy/dx over the rough stretches)",
        )
        .err(),
        seed,
        check(key("from"), r.from, r.from >= 0.0, ">= 0 m").err(),
        check(key("to"), r.to, r.to > r.from, "> from [m]").err(),
        check(
            key("wavelength_min"),
            r.wavelength_min,
            r.wavelength_min > 0.0,
            "> 0 m",
        )
        .err(),
        check(
            key("wavelength_max"),
            r.wavelength_max,
            r.wavelength_max > r.wavelength_min && r.wavelength_max <= length,
            "> wavelength_min and <= to - from [m] (the branch is one period of the synthesis)",
        )
        .err(),
        check(
            key("taper"),
            taper,
            taper > 0.0 && taper <= 0.5 * length,
            "(0, (to - from)/2] m",
        )
        .err(),
    ];
    errors.extend(found.into_iter().flatten());
    if errors.len() > before {
        return None;
    }
    let modes = mode_range(length, r.wavelength_min, r.wavelength_max);
    if modes.end() <= modes.start() {
        errors.push(inconsistent(
            key("wavelength_min"),
            format!(
                "fewer than two wavelengths (to - from)/k, k = 1, 2, ..., lie in [wavelength_min, wavelength_max] = \
                 [{}, {}] m with to - from = {length} m: widen the band",
                r.wavelength_min, r.wavelength_max
            ),
        ));
        return None;
    }
    Some(Some(Rough {
        hurst: r.hurst,
        rms_slope: r.rms_slope,
        seed: r.seed as u64,
        from: r.from,
        to: r.to,
        wavelength_min: r.wavelength_min,
        wavelength_max: r.wavelength_max,
        taper,
    }))
}

/// The Fourier modes of one branch, sampled at n points over its period L = n h.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Modes {
    /// Mode numbers k (wavelength L/k).
    pub k: Vec<u64>,
    /// Amplitudes q_k^{-(1+2H)/2}, q_k = 2πk/L [rad/m].
    pub amplitude: Vec<f64>,
    /// Phases φ_k [rad].
    pub phase: Vec<f64>,
}

/// A uniform number in [0, 1) from the top 53 bits of the next word (every double of that form
/// is exact).
fn unit(rng: &mut ChaCha8Rng) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The generator of `seed`: ChaCha8 keyed with the seed's little-endian bytes (rest zero).
fn generator(seed: u64) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    ChaCha8Rng::from_seed(key)
}

impl Modes {
    /// Draws the phases of one branch of period `length` [m] from `rng`.
    fn draw(r: &Rough, length: f64, rng: &mut ChaCha8Rng) -> Modes {
        let k: Vec<u64> = mode_range(length, r.wavelength_min, r.wavelength_max).collect();
        let amplitude = k
            .iter()
            .map(|&k| libm::pow(TAU * k as f64 / length, -0.5 * (1.0 + 2.0 * r.hurst)))
            .collect();
        let phase = k.iter().map(|_| TAU * unit(rng)).collect();
        Modes { k, amplitude, phase }
    }

    /// z at sample j of n per period (s = j L/n), untapered and unscaled. The argument is
    /// reduced in whole numbers, so the samples are exactly periodic.
    pub fn at(&self, j: u64, n: u64) -> f64 {
        self.k
            .iter()
            .zip(&self.amplitude)
            .zip(&self.phase)
            .map(|((&k, &a), &phi)| a * libm::cos(TAU * ((k * j) % n) as f64 / n as f64 + phi))
            .sum()
    }
}

/// The modes of the right and the left branch for `r` at n samples per branch of length
/// `to - from` (phases: right branch first, then left).
pub(crate) fn branch_modes(r: &Rough) -> [Modes; 2] {
    let mut rng = generator(r.seed);
    let length = r.to - r.from;
    let right = Modes::draw(r, length, &mut rng);
    let left = Modes::draw(r, length, &mut rng);
    [right, left]
}

/// The taper at j of n segments with h [m] per segment: sin²(π d/(2τ)) within τ of an end
/// (d the distance to the nearer end), 1 elsewhere; exactly 0 at both ends.
fn taper(j: u64, n: u64, h: f64, tau: f64) -> f64 {
    let d = j.min(n - j) as f64 * h;
    if d < tau {
        let s = libm::sin(0.5 * PI * d / tau);
        s * s
    } else {
        1.0
    }
}

/// Column index of x [m] on the grid x₀ + i h, if x is on a column (to 1e-6 h).
fn column(x: f64, x0: f64, h: f64) -> Option<usize> {
    let i = (x - x0) / h;
    ((i - i.round()).abs() < 1e-6 && i.round() >= 0.0).then_some(i.round() as usize)
}

/// The interface row at every node column x₀ + i h: the rough profile on both branches, 0
/// elsewhere. Checks what needs the grid: both branches on node columns and inside
/// `fem.x_range`, the shortest wavelength resolved and the taper at least one element long.
pub(crate) fn rough_polyline(f: &RawFem, r: &Rough, center_x: f64) -> Result<Vec<[f64; 2]>, SceneError> {
    let h = f.element_size;
    let [x0, x1] = f.x_range;
    let n_row = ((x1 - x0) / h).round() as usize;
    check(
        key("wavelength_min"),
        r.wavelength_min,
        r.wavelength_min >= MIN_ELEMENTS_PER_WAVELENGTH * h * (1.0 - 1e-12),
        &format!(
            ">= {MIN_ELEMENTS_PER_WAVELENGTH} fem.element_size = {} m (the shortest wave drawn by \
             {MIN_ELEMENTS_PER_WAVELENGTH} elements)",
            MIN_ELEMENTS_PER_WAVELENGTH * h
        ),
    )?;
    check(
        key("taper"),
        r.taper,
        r.taper >= h * (1.0 - 1e-12),
        &format!(">= fem.element_size = {h} m (a shorter ramp is a step of the row)"),
    )?;
    if center_x - r.to < x0 - 1e-9 * h || center_x + r.to > x1 + 1e-9 * h {
        return Err(inconsistent(
            key("to"),
            format!(
                "the rough stretches reach x = {} and {} m, outside fem.x_range = [{x0}, {x1}] m",
                center_x - r.to,
                center_x + r.to
            ),
        ));
    }
    let mut columns = [0usize; 4];
    for (c, (name, x)) in columns.iter_mut().zip([
        ("from", center_x + r.from),
        ("from", center_x - r.from),
        ("to", center_x + r.to),
        ("to", center_x - r.to),
    ]) {
        *c = column(x, x0, h).ok_or_else(|| {
            inconsistent(
                key(name),
                format!(
                    "x = {x} m (crack.center_x ± {name}) is not on a node column: the branches must span \
                     whole elements of fem.element_size = {h} m"
                ),
            )
        })?;
    }
    let [right_from, left_from, right_to, _] = columns;
    let n = (right_to - right_from) as u64;
    let modes = branch_modes(r);
    let mut y = vec![0.0; n_row + 1];
    // each branch's nodes from its inner end outward: (column of j, the modes)
    let branches: [(&dyn Fn(u64) -> usize, &Modes); 2] = [
        (&|j| right_from + j as usize, &modes[0]),
        (&|j| left_from - j as usize, &modes[1]),
    ];
    for (col, m) in branches {
        for j in 0..=n {
            y[col(j)] = taper(j, n, h, r.taper) * m.at(j % n, n);
        }
    }
    let rms = rms_slope(
        &y,
        h,
        &[(right_from, n as usize), (left_from - n as usize, n as usize)],
    );
    if !(rms > 0.0 && rms.is_finite()) {
        return Err(inconsistent(
            key("rms_slope"),
            "the tapered profile is flat at the node columns; widen the band or lengthen the branches",
        ));
    }
    let scale = r.rms_slope / rms;
    Ok(y.iter()
        .enumerate()
        .map(|(i, &yi)| [x0 + i as f64 * h, scale * yi])
        .collect())
}

/// RMS of (y_{i+1} − y_i)/h over the segments of the stretches (first column, segments).
pub(crate) fn rms_slope(y: &[f64], h: f64, stretches: &[(usize, usize)]) -> f64 {
    let (sum, count) = stretches
        .iter()
        .flat_map(|&(i0, n)| (i0..i0 + n).map(|i| (y[i + 1] - y[i]) / h))
        .fold((0.0, 0usize), |(s, c), d| (s + d * d, c + 1));
    (sum / count as f64).sqrt()
}

#[cfg(test)]
mod tests;
