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
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// A 0.3 m × 0.1 m grid at h = 1 mm, centre crack a = 25 mm, rough stretches 25–175 mm
    /// from the centre (150 elements a branch), with `extra` added to the table.
    fn scene(extra: &str) -> String {
        let base = crate::test_scenes::scene_text("tiny-fem-center-crack");
        base.replace("x_range = [-0.02, 0.02]", "x_range = [-0.2, 0.2]")
            .replace("y_range = [-0.01, 0.01]", "y_range = [-0.05, 0.05]")
            .replace("half_length = 0.01 ", "half_length = 0.025 ")
            + &format!(
                "interface_rough = {{ hurst = 0.8, rms_slope = 0.1, seed = 1, from = 0.025, to = 0.175, \
                 wavelength_min = 0.006, wavelength_max = 0.075{extra} }}\n"
            )
    }

    fn row(text: &str) -> Vec<[f64; 2]> {
        let s = Scene::from_toml_str(text).unwrap_or_else(|e| panic!("{e}"));
        let [x0, x1] = s.fem.x_range;
        let h = s.fem.element_size;
        let n = ((x1 - x0) / h).round() as usize;
        (0..=n)
            .map(|i| {
                let x = x0 + i as f64 * h;
                [x, s.fem.interface_y(x)]
            })
            .collect()
    }

    fn bits(row: &[[f64; 2]]) -> Vec<u64> {
        row.iter().map(|p| p[1].to_bits()).collect()
    }

    #[test]
    fn the_same_seed_gives_the_same_bits_and_another_seed_another_row() {
        let a = row(&scene(""));
        assert_eq!(bits(&a), bits(&row(&scene(""))));
        let b = row(&scene("").replace("seed = 1", "seed = 2"));
        assert_ne!(bits(&a), bits(&b));
        // the two branches are independent draws, not mirror images: node j of the right branch
        // is column 225 + j (x = 25 mm + j h), of the left 175 - j
        assert!((1..150).any(|j| (a[225 + j][1] - a[175 - j][1]).abs() > 1e-6));
        // pinned: the first words of ChaCha8 for this key and the arithmetic after them; a
        // change of the crate's stream or of the synthesis shows here (the value this code gave
        // at the commit that introduced it)
        assert_eq!(
            a[300][1].to_bits(),
            PINNED_Y_AT_100MM,
            "y(0.1 m) = {:e}",
            a[300][1]
        );
    }

    /// y(x = 0.1 m) of `scene("")`, as bits (see the test above).
    const PINNED_Y_AT_100MM: u64 = 13778669967359682635; // -3.611643786071191e-4 m

    #[test]
    fn the_rms_slope_of_the_sampled_row_is_the_requested_one() {
        for (slope, hurst, seed) in [(0.1, 0.8, 1), (0.35, 0.3, 7), (0.02, 0.95, 123456789)] {
            let text = scene("")
                .replace("rms_slope = 0.1", &format!("rms_slope = {slope}"))
                .replace("hurst = 0.8", &format!("hurst = {hurst}"))
                .replace("seed = 1", &format!("seed = {seed}"));
            let r = row(&text);
            let y: Vec<f64> = r.iter().map(|p| p[1]).collect();
            // columns of x = 25 mm and x = -175 mm on the grid from -0.2 m
            let measured = rms_slope(&y, 1e-3, &[(225, 150), (25, 150)]);
            assert!(
                ((measured - slope) / slope).abs() <= 1e-12,
                "{measured} against {slope}"
            );
        }
    }

    #[test]
    fn the_row_is_zero_at_both_ends_of_each_branch_and_outside() {
        let r = row(&scene(""));
        for p in &r {
            let d = p[0].abs();
            if d <= 0.025 + 1e-9 || d >= 0.175 - 1e-9 {
                assert_eq!(p[1], 0.0, "x = {}", p[0]);
            }
        }
        // inside, away from the taper (default λ_max/4 = 18.75 mm), the row is rough
        assert!(
            r.iter()
                .filter(|p| p[0] > 0.05 && p[0] < 0.15)
                .any(|p| p[1].abs() > 1e-5)
        );
        // and the taper ramps in: within a millimetre of an end the row is small
        let near_end = r.iter().find(|p| (p[0] - 0.026).abs() < 1e-9).unwrap()[1];
        let scale = r.iter().map(|p| p[1].abs()).fold(0.0, f64::max);
        assert!(near_end.abs() < 0.05 * scale, "{near_end} against {scale}");
    }

    /// Power |Z_m|² of the discrete Fourier transform of z at mode m (O(n), one mode).
    fn power(z: &[f64], m: u64) -> f64 {
        let n = z.len() as f64;
        let (re, im) = z.iter().enumerate().fold((0.0, 0.0), |(re, im), (j, &v)| {
            let a = TAU * m as f64 * j as f64 / n;
            (re + v * a.cos(), im - v * a.sin())
        });
        re * re + im * im
    }

    #[test]
    fn the_periodogram_of_the_profile_falls_as_q_to_the_minus_1_plus_2h() {
        for hurst in [0.2, 0.5, 0.8] {
            let r = Rough {
                hurst,
                rms_slope: 0.1,
                seed: 42,
                from: 0.025,
                to: 0.175,
                wavelength_min: 0.006,
                wavelength_max: 0.075,
                taper: 0.01,
            };
            let n = 150u64;
            for m in branch_modes(&r) {
                let z: Vec<f64> = (0..n).map(|j| m.at(j, n)).collect();
                // least squares of log P against log k over the band (k = 2..=25)
                let pts: Vec<(f64, f64)> =
                    m.k.iter()
                        .map(|&k| ((k as f64).ln(), power(&z, k).ln()))
                        .collect();
                assert_eq!(pts.len(), 24);
                let mean = |f: &dyn Fn(&(f64, f64)) -> f64| pts.iter().map(f).sum::<f64>() / pts.len() as f64;
                let (mx, my) = (mean(&|p| p.0), mean(&|p| p.1));
                let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
                let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
                let slope = sxy / sxx;
                // the amplitudes are the spectrum's and the n samples cover one period, so the
                // transform returns each mode's amplitude to round-off (the phases cancel in
                // |Z|²): the fit is exact to ~1e-12. 1e-6 keeps far from round-off and still
                // catches any wrong exponent (H for 2H, or the spectrum for its root, is off by > 0.1)
                assert!(
                    (slope + 1.0 + 2.0 * hurst).abs() < 1e-6,
                    "H = {hurst}: slope {slope}"
                );
                // and nothing outside the band (k = 1 and 26..75): the profile has no other wave
                let total: f64 = m.k.iter().map(|&k| power(&z, k)).sum();
                for k in (1..2).chain(26..75) {
                    assert!(power(&z, k) < 1e-20 * total, "H = {hurst}: mode {k}");
                }
            }
        }
    }

    #[test]
    fn bad_values_are_refused_naming_the_key() {
        let cases = [
            ("hurst = 0.8", "hurst = 1.0", "fem.interface_rough.hurst"),
            ("hurst = 0.8", "hurst = 0.0", "fem.interface_rough.hurst"),
            (
                "rms_slope = 0.1",
                "rms_slope = 0.0",
                "fem.interface_rough.rms_slope",
            ),
            (
                "rms_slope = 0.1",
                "rms_slope = nan",
                "fem.interface_rough.rms_slope",
            ),
            ("seed = 1", "seed = -3", "fem.interface_rough.seed"),
            ("from = 0.025", "from = -0.01", "fem.interface_rough.from"),
            ("to = 0.175", "to = 0.02", "fem.interface_rough.to"),
            ("to = 0.175", "to = 0.25", "fem.interface_rough.to"),
            ("to = 0.175", "to = 0.1755", "fem.interface_rough.to"),
            ("from = 0.025", "from = 0.0255", "fem.interface_rough.from"),
            (
                "wavelength_min = 0.006",
                "wavelength_min = 0.003",
                "fem.interface_rough.wavelength_min",
            ),
            (
                "wavelength_min = 0.006",
                "wavelength_min = -1.0",
                "fem.interface_rough.wavelength_min",
            ),
            (
                "wavelength_max = 0.075",
                "wavelength_max = 0.2",
                "fem.interface_rough.wavelength_max",
            ),
            (
                "wavelength_max = 0.075",
                "wavelength_max = 0.005",
                "fem.interface_rough.wavelength_max",
            ),
            // one wavelength only: 150/25 = 6 mm, the next, 150/24, is above 6.2 mm
            (
                "wavelength_max = 0.075",
                "wavelength_max = 0.0062",
                "fem.interface_rough.wavelength_min",
            ),
        ];
        for (from, to, key) in cases {
            let text = scene("").replace(from, to);
            assert_ne!(text, scene(""), "{to}: the edit did not apply");
            let e = Scene::from_toml_str(&text).unwrap_err().to_string();
            assert!(e.contains(key), "{to}: {e}");
        }
        let e = Scene::from_toml_str(&scene(", taper = 0.0005"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("fem.interface_rough.taper"), "{e}");
        let e = Scene::from_toml_str(&scene(", taper = 0.08"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("fem.interface_rough.taper"), "{e}");
        let e = Scene::from_toml_str(&scene(", hurts = 0.5"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("fem.interface_rough.hurts"), "{e}");
        // every field problem at once
        let e = Scene::from_toml_str(
            &scene("")
                .replace("hurst = 0.8", "hurst = 2.0")
                .replace("seed = 1", "seed = -1"),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("fem.interface_rough.hurst") && e.contains("fem.interface_rough.seed"),
            "{e}"
        );
        // a height beyond half the block is refused, naming the slope that made it
        let e = Scene::from_toml_str(&scene("").replace("rms_slope = 0.1", "rms_slope = 5.0"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("fem.interface_rough.rms_slope"), "{e}");
    }

    #[test]
    fn the_rough_row_goes_with_no_other_path_and_no_mesh() {
        for other in [
            "interface_sine = { amplitude = 0.001, half_period = 0.01, from = 0.025, to = 0.1 }\n",
            "interface_polyline = [[0.0, 0.0], [0.1, 0.0]]\n",
        ] {
            let e = Scene::from_toml_str(&(scene("") + other))
                .unwrap_err()
                .to_string();
            assert!(e.contains("fem.interface_rough") && e.contains("not two"), "{e}");
        }
        // with [fem.mesh] the file is the geometry: refused before the file is looked for
        let text = scene("");
        let kept: Vec<&str> = text
            .lines()
            .filter(|l| {
                !(l.starts_with("x_range") || l.starts_with("y_range") || l.starts_with("element_size"))
            })
            .collect();
        let mesh = format!("{}\n[fem.mesh]\nfile = \"no-such.msh\"\n", kept.join("\n"));
        let e = Scene::from_toml_str(&mesh).unwrap_err().to_string();
        assert!(
            e.contains("fem.interface_rough") && e.contains("built-in grid"),
            "{e}"
        );
    }
}
