//! Direct truncated history convolution (docs/spectral-model.md §4), fused over the four fields and
//! three kernels that read the same history, parallel over modes (rayon), no allocation.
//!
//! C^K_j(n) = Σ_{l=0}^{min(n+1, L_j)−1} W^K_{j,l} Û_j^{n−l},
//! W^K_{j,l} = ½ [K(l ΔT_j) + K((l+1) ΔT_j)] ΔT_j  (trapezoid; the k c_s dt' factor is inside W).

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::history::{Entry, History};
use crate::kernels::KernelTable;
use crate::modes::Modes;
use crate::profile::Work;

/// The eight convolutions of one mode (K ∗ Û) [m].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ModeSums {
    /// H11 ∗ Û^+_1.
    pub h11_top: Complex64,
    /// H11 ∗ Û^-_1.
    pub h11_bottom: Complex64,
    /// H22 ∗ Û^+_2.
    pub h22_top: Complex64,
    /// H22 ∗ Û^-_2.
    pub h22_bottom: Complex64,
    /// K12 ∗ Û^+_1.
    pub k12_top_x: Complex64,
    /// K12 ∗ Û^+_2.
    pub k12_top_y: Complex64,
    /// K12 ∗ Û^-_1.
    pub k12_bottom_x: Complex64,
    /// K12 ∗ Û^-_2.
    pub k12_bottom_y: Complex64,
}

/// Pre-integrated weights [W^H11, W^H22, W^K12] per (mode, lag), same offsets as the history.
#[derive(Debug, Clone)]
pub struct Weights {
    w: Vec<[f64; 3]>,
    offset: Vec<usize>,
}

impl Weights {
    /// Builds W^K_{j,l} from kernel samples at multiples of ΔT_1 (`table.dt` must equal `modes.dt1`).
    pub fn new(modes: &Modes, table: &KernelTable) -> Weights {
        let mut w = vec![[0.0; 3]; modes.total];
        for j in 1..modes.window.len() {
            let dtj = j as f64 * modes.dt1;
            let off = modes.offset[j];
            for l in 0..modes.window[j] {
                let (a, b) = (l * j, (l + 1) * j);
                w[off + l] = [
                    0.5 * (table.h11[a] + table.h11[b]) * dtj,
                    0.5 * (table.h22[a] + table.h22[b]) * dtj,
                    0.5 * (table.k12[a] + table.k12[b]) * dtj,
                ];
            }
        }
        Weights {
            w,
            offset: modes.offset.clone(),
        }
    }

    /// Bytes of weights read per step once every window is full [B].
    pub fn bytes(&self) -> usize {
        self.w.len() * std::mem::size_of::<[f64; 3]>()
    }

    /// Work of one direct step once every window is full (§4.1): per mode j ≥ 1, its Û read
    /// and pushed into the ring buffer, and its eight sums written; per (mode, lag), the entry
    /// and its three weights read and [`FLOPS_PER_LAG`] flops.
    pub fn work(&self) -> Work {
        let modes = self.offset.len().saturating_sub(1) as f64;
        let lags = self.w.len() as f64;
        let entry = std::mem::size_of::<Entry>() as f64;
        Work {
            flops: lags * FLOPS_PER_LAG,
            read: modes * entry + lags * (entry + std::mem::size_of::<[f64; 3]>() as f64),
            written: modes * (entry + std::mem::size_of::<ModeSums>() as f64),
        }
    }
}

/// Flops of one (mode, lag) of [`accumulate`]: eight sums of a complex entry times a real
/// weight (2 multiplies and 2 adds each).
const FLOPS_PER_LAG: f64 = 32.0;

#[inline(always)]
fn accumulate(s: &mut ModeSums, w: &[[f64; 3]], h: &[Entry]) {
    // Local accumulators keep the loop in registers; the compiler streams both slices.
    let mut acc = *s;
    for (w, e) in w.iter().zip(h) {
        acc.h11_top += e.top_x * w[0];
        acc.h11_bottom += e.bottom_x * w[0];
        acc.h22_top += e.top_y * w[1];
        acc.h22_bottom += e.bottom_y * w[1];
        acc.k12_top_x += e.top_x * w[2];
        acc.k12_top_y += e.top_y * w[2];
        acc.k12_bottom_x += e.bottom_x * w[2];
        acc.k12_bottom_y += e.bottom_y * w[2];
    }
    *s = acc;
}

/// Computes the convolutions of every mode j ≥ 1 into `out[j]` (out[0] is zeroed).
pub fn convolve(history: &History, weights: &Weights, out: &mut [ModeSums]) {
    out[0] = ModeSums::default();
    out[1..]
        .par_iter_mut()
        .with_min_len(8)
        .enumerate()
        .for_each(|(i, s)| {
            let j = i + 1;
            let (first, second) = history.lags(j);
            let off = weights.offset[j];
            *s = ModeSums::default();
            accumulate(s, &weights.w[off..off + first.len()], first);
            let off2 = off + first.len();
            accumulate(s, &weights.w[off2..off2 + second.len()], second);
        });
}
