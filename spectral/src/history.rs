//! History of the displacement spectra: one contiguous ring-buffer array with per-mode offsets
//! (cRacklet layout, docs/spectral-model.md §4). Each entry holds the four fields of one mode at one
//! past step, so the fused convolution streams one array.

use std::borrow::Cow;

use rustfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::modes::Modes;

/// Spectra of one mode at one step: Û^+_1, Û^+_2, Û^-_1, Û^-_2 [m].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[repr(C)]
pub struct Entry {
    /// Û of the top face, x component [m].
    #[serde(with = "complex")]
    pub top_x: Complex64,
    /// Û of the top face, y component [m].
    #[serde(with = "complex")]
    pub top_y: Complex64,
    /// Û of the bottom face, x component [m].
    #[serde(with = "complex")]
    pub bottom_x: Complex64,
    /// Û of the bottom face, y component [m].
    #[serde(with = "complex")]
    pub bottom_y: Complex64,
}

/// A complex number in serde form as its (re, im) pair of floats (num-complex's own serde form,
/// without enabling its feature).
pub(crate) mod complex {
    use rustfft::num_complex::Complex64;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Writes z as (re, im).
    pub fn serialize<S: Serializer>(z: &Complex64, s: S) -> Result<S::Ok, S::Error> {
        (z.re, z.im).serialize(s)
    }

    /// Reads (re, im).
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Complex64, D::Error> {
        let (re, im) = <(f64, f64)>::deserialize(d)?;
        Ok(Complex64::new(re, im))
    }
}

/// Ring buffers of the last L_j spectra of every mode j ≥ 1.
///
/// The write position of each mode moves backwards, so lag l (l = 0 newest) sits at
/// `(pos_j + l) mod L_j`: the lags are two forward runs `[pos_j, L_j)` then `[0, …)`.
#[derive(Debug, Clone)]
pub struct History {
    entries: Vec<Entry>,
    pos: Vec<usize>,
    offset: Vec<usize>,
    window: Vec<usize>,
    stored: usize,
}

impl History {
    /// Zeroed buffers for the windows of `modes`.
    pub fn new(modes: &Modes) -> History {
        History {
            entries: vec![Entry::default(); modes.total],
            pos: vec![0; modes.window.len()],
            offset: modes.offset.clone(),
            window: modes.window.clone(),
            stored: 0,
        }
    }

    /// Pushes the spectra of the current step (index j = mode; mode 0 is ignored).
    pub fn push(&mut self, spectra: &[Entry]) {
        for (j, e) in spectra.iter().enumerate().skip(1) {
            let l = self.window[j];
            let p = if self.pos[j] == 0 { l - 1 } else { self.pos[j] - 1 };
            self.pos[j] = p;
            self.entries[self.offset[j] + p] = *e;
        }
        self.stored += 1;
    }

    /// Marks every window as full (benchmarks).
    pub fn assume_full(&mut self) {
        self.stored = self.window.iter().copied().max().unwrap_or(0);
    }

    /// Number of valid lags of mode j: min(steps stored, L_j).
    pub fn count(&self, j: usize) -> usize {
        self.stored.min(self.window[j])
    }

    /// The evolving part, for a checkpoint: the ring buffers, their write positions and the
    /// count of steps pushed (offsets and windows are the scene's).
    pub(crate) fn saved(&self) -> HistoryState<'_> {
        let History {
            entries,
            pos,
            offset: _,
            window: _,
            stored,
        } = self;
        HistoryState {
            entries: Cow::Borrowed(entries),
            pos: Cow::Borrowed(pos),
            stored: *stored,
        }
    }

    /// Restores what [`History::saved`] wrote into these buffers (built for the same scene).
    pub(crate) fn restore(&mut self, saved: &HistoryState<'_>) -> Result<(), String> {
        let History {
            entries,
            pos,
            offset: _,
            window,
            stored,
        } = self;
        let HistoryState {
            entries: e,
            pos: p,
            stored: s,
        } = saved;
        fill(entries, e, "history ring buffers")?;
        fill(pos, p, "history write positions")?;
        if pos.iter().zip(window.iter()).skip(1).any(|(&p, &l)| p >= l) {
            return Err("a history write position outside its window".into());
        }
        *stored = *s;
        Ok(())
    }

    /// Lags 0..count of mode j as two contiguous runs (newest first).
    pub fn lags(&self, j: usize) -> (&[Entry], &[Entry]) {
        let (off, l, p) = (self.offset[j], self.window[j], self.pos[j]);
        let c = self.count(j);
        let first_len = c.min(l - p);
        let first = &self.entries[off + p..off + p + first_len];
        let second = &self.entries[off..off + (c - first_len)];
        (first, second)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lags_come_newest_first_and_wrap() {
        let modes = Modes::new(
            4,
            1.0,
            0.5,
            3.0 * 2.0 * std::f64::consts::PI * 0.5 / 4.0 + 1e-9,
            10,
        );
        assert_eq!(modes.window[1], 2); // floor(3) − 1
        let mut h = History::new(&modes);
        for s in 1..=3 {
            let e = Entry {
                top_x: Complex64::new(s as f64, 0.0),
                ..Default::default()
            };
            h.push(&[Entry::default(), e, e]);
        }
        let (a, b) = h.lags(1);
        let v: Vec<f64> = a.iter().chain(b).map(|e| e.top_x.re).collect();
        assert_eq!(v, vec![3.0, 2.0]);
    }
}

/// The direct path's ring buffers (§4.1; `crate::history::History`).
#[derive(Debug, Serialize, Deserialize)]
pub(crate) struct HistoryState<'a> {
    /// Past spectra Û of every mode j ≥ 1, Σ_j L_j entries at the modes' offsets [m].
    pub entries: Cow<'a, [Entry]>,
    /// Write position of each mode in its window [-].
    pub pos: Cow<'a, [usize]>,
    /// Steps pushed so far [-].
    pub stored: usize,
}

/// Copies `from` into `into`, which must have its length (the buffers a resumed run built keep
/// their allocation); `what` names the buffer in the refusal.
pub(crate) fn fill<T: Copy>(into: &mut [T], from: &[T], what: &str) -> Result<(), String> {
    if into.len() != from.len() {
        return Err(format!(
            "its {what} hold {} values, this scene's model {}",
            from.len(),
            into.len()
        ));
    }
    into.copy_from_slice(from);
    Ok(())
}
