//! Fast history convolution (issue 6): with the kernels fitted as K(T) ≈ Σ_p c^K_p e^{λ_p T}
//! ([`SoeFit`]), the §4 quadrature of mode j becomes, exactly,
//!
//! W^K_{j,l} = ½[K(lΔT_j) + K((l+1)ΔT_j)]ΔT_j = Σ_p g^K_{j,p} z_{j,p}^l,
//! z_{j,p} = e^{λ_p ΔT_j},  g^K_{j,p} = c^K_p ΔT_j (1 + z_{j,p})/2,
//! C^K_j(n) = Σ_l W^K_{j,l} Û^{n−l} = Σ_p g^K_{j,p} s_{j,p}(n),  s_{j,p}(n) = Û^n + z_{j,p} s_{j,p}(n−1),
//!
//! so work and memory per step are O(N r), independent of the history length.
//!
//! # Deviation
//! The direct path truncates every kernel at T = tcut (cRacklet rule, §3.4); the recursion cannot,
//! so the fitted kernel continues beyond tcut with its own exponential decay (the exact kernel
//! decays like T^{−3/2} there, |K| ≤ 9e−3 at T = 100). Both paths use the same kernels on [0, tcut]
//! to the fit tolerance.

use rayon::prelude::*;
use rustfft::num_complex::Complex64;

use crate::convolution::ModeSums;
use crate::history::Entry;
use crate::modes::Modes;
pub use crate::soe::SoeFit;

/// Per-mode recursion coefficients and states, one contiguous block per mode.
///
/// A kernel is real, so a conjugate pair (z, z̄) with amplitudes (c, c̄) acting on Û = A + iB (A, B
/// real sequences) gives C = 2Re(c s_z[A]) + i 2Re(c s_z[B]), s_z[A] = Σ_l z^l A^{n−l}: one state per
/// pair and real part, and the outputs need only real parts.
pub struct FastConvolution {
    r: usize,
    /// z_{j,p} at [j r + p].
    z: Vec<Complex64>,
    /// w_p (g^H11, g^H22, g^K12)_{j,p} at [j r + p].
    g: Vec<[Complex64; 3]>,
    /// States s_z[Re Û], s_z[Im Û] for the four fields (top x, top y, bottom x, bottom y) at [j r + p].
    s: Vec<[Complex64; 8]>,
}

#[inline(always)]
fn re_mul(a: Complex64, b: Complex64) -> f64 {
    a.re * b.re - a.im * b.im
}

impl FastConvolution {
    /// Coefficients for every mode j ≥ 1 (mode 0 has no history term).
    pub fn new(modes: &Modes, fit: &SoeFit) -> FastConvolution {
        let r = fit.poles.len();
        let nm = modes.k.len();
        let mut z = vec![Complex64::default(); nm * r];
        let mut g = vec![[Complex64::default(); 3]; nm * r];
        for j in 1..nm {
            let dtj = j as f64 * modes.dt1;
            for p in 0..r {
                let zz = (fit.poles[p] * dtj).exp();
                let f = 0.5 * dtj * (1.0 + zz) * fit.weight[p];
                z[j * r + p] = zz;
                g[j * r + p] = [fit.amps[0][p] * f, fit.amps[1][p] * f, fit.amps[2][p] * f];
            }
        }
        FastConvolution {
            r,
            z,
            g,
            s: vec![[Complex64::default(); 8]; nm * r],
        }
    }

    /// Bytes of coefficients and states touched per step [B].
    pub fn bytes(&self) -> usize {
        self.z.len() * 16 + self.g.len() * 48 + self.s.len() * 128
    }

    /// Pushes Û^n of every mode and writes the eight convolutions per mode into `out`.
    pub fn step(&mut self, spectra: &[Entry], out: &mut [ModeSums]) {
        let r = self.r;
        out[0] = ModeSums::default();
        out[1..]
            .par_iter_mut()
            .zip(self.s[r..].par_chunks_mut(r))
            .zip(self.z[r..].par_chunks(r).zip(self.g[r..].par_chunks(r)))
            .zip(spectra[1..].par_iter())
            .with_min_len(16)
            .for_each(|(((o, s), (z, g)), e)| {
                let u = [
                    e.top_x.re,
                    e.top_x.im,
                    e.top_y.re,
                    e.top_y.im,
                    e.bottom_x.re,
                    e.bottom_x.im,
                    e.bottom_y.re,
                    e.bottom_y.im,
                ];
                // acc[field][part] for H (H11 on x fields, H22 on y fields) and K12.
                let mut h = [0.0f64; 8];
                let mut k = [0.0f64; 8];
                for p in 0..r {
                    let (zp, gp, sp) = (z[p], g[p], &mut s[p]);
                    for q in 0..8 {
                        sp[q] = zp * sp[q] + u[q];
                    }
                    for q in 0..8 {
                        // fields: 0,1 top x; 2,3 top y; 4,5 bottom x; 6,7 bottom y
                        let gh = if (q / 2) % 2 == 0 { gp[0] } else { gp[1] };
                        h[q] += re_mul(gh, sp[q]);
                        k[q] += re_mul(gp[2], sp[q]);
                    }
                }
                let c = |a: &[f64; 8], f: usize| Complex64::new(a[2 * f], a[2 * f + 1]);
                *o = ModeSums {
                    h11_top: c(&h, 0),
                    h22_top: c(&h, 1),
                    h11_bottom: c(&h, 2),
                    h22_bottom: c(&h, 3),
                    k12_top_x: c(&k, 0),
                    k12_top_y: c(&k, 1),
                    k12_bottom_x: c(&k, 2),
                    k12_bottom_y: c(&k, 3),
                };
            });
    }
}
