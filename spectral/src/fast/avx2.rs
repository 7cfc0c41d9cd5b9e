//! The recursion's kernel for AVX2, written in intrinsics: the operations of
//! [`mode_kernel`](super::mode_kernel), lane by lane and in the same order, so the bits are the
//! portable build's (test `every_instruction_set_gives_the_bits_of_the_portable_build`). A pole's
//! eight lanes take two registers here, lanes 0–3 (the x sequences) and 4–7 (the y sequences).
//! Left to the compiler, the lane code kept the K12 sums in the order of [`ModeSums`] and paid
//! four lane-crossing shuffles a pole for it; here they stay in lane order and are put in the
//! order of [`ModeSums`] once a mode (docs/performance.md, "The recursion in intrinsics (AVX2)").

use std::arch::x86_64::{
    __m256d, _mm_load_ps, _mm_store_ps, _mm_storeu_pd, _mm256_add_pd, _mm256_broadcast_sd,
    _mm256_castpd256_pd128, _mm256_cvtpd_ps, _mm256_cvtps_pd, _mm256_extractf128_pd, _mm256_load_pd,
    _mm256_loadu2_m128d, _mm256_mul_pd, _mm256_setzero_pd, _mm256_store_pd, _mm256_sub_pd,
};

use rustfft::num_complex::Complex64;

use super::{Stored, Task};
use crate::convolution::ModeSums;
use crate::history::Entry;

/// [`modes_kernel`](super::modes_kernel) for AVX2: every mode of one task.
#[target_feature(enable = "avx2,fma")]
pub(super) fn modes<S: Stored>((r, z, g, s, spectra, out): Task<'_, S>) {
    let coefficients = z.chunks(r).zip(g.chunks(r));
    for (((o, e), s), (z, g)) in out.iter_mut().zip(spectra).zip(s.chunks_mut(r)).zip(coefficients) {
        mode(z, g, s, e, o);
    }
}

/// One mode: s ← z s + u for every pole, then the sums H (g_H11 on lanes 0–3, g_H22 on 4–7) and
/// K (g_K12 on all eight), as in [`mode_kernel`](super::mode_kernel): each product rounded on
/// its own (no fused multiply-add), the sums started from +0.
#[inline]
#[target_feature(enable = "avx2,fma")]
fn mode<S: Stored>(z: &[Complex64], g: &[[Complex64; 3]], s: &mut [S], e: &Entry, o: &mut ModeSums) {
    let n = z.len().min(g.len()).min(s.len());
    let (z, g, s) = (&z[..n], &g[..n], &mut s[..n]);
    // SAFETY: every pointer below points into a value borrowed for the whole call, each read or
    // write stays inside it (an Entry and a ModeSums are Complex64 fields, each two f64 with
    // `repr(C)`), and a state is `repr(C)` and aligned to 64 bytes: eight f64 real parts then
    // eight imaginary ones, so its four quarters of four lanes are aligned to 32, or as many f32
    // if `S::SINGLE`, its quarters then aligned to 16.
    unsafe {
        // four lanes from `at` (in lanes) of a state, widened to f64 if stored as f32
        let load = |sp: &S, at: usize| {
            if S::SINGLE {
                _mm256_cvtps_pd(_mm_load_ps((sp as *const S as *const f32).add(at)))
            } else {
                _mm256_load_pd((sp as *const S as *const f64).add(at))
            }
        };
        // ... stored back, rounded to f32 (to nearest, the default mode) if stored as f32
        let store = |sp: &mut S, at: usize, v: __m256d| {
            if S::SINGLE {
                _mm_store_ps((sp as *mut S as *mut f32).add(at), _mm256_cvtpd_ps(v))
            } else {
                _mm256_store_pd((sp as *mut S as *mut f64).add(at), v)
            }
        };
        // u lanes 0–3: top x (re, im), bottom x (re, im); lanes 4–7: the same for y
        let f = |c: &Complex64| c as *const Complex64 as *const f64;
        let u_x = _mm256_loadu2_m128d(f(&e.bottom_x), f(&e.top_x));
        let u_y = _mm256_loadu2_m128d(f(&e.bottom_y), f(&e.top_y));
        let (mut h_x, mut h_y, mut k_x, mut k_y) = (
            _mm256_setzero_pd(),
            _mm256_setzero_pd(),
            _mm256_setzero_pd(),
            _mm256_setzero_pd(),
        );
        for ((zp, gp), sp) in z.iter().zip(g).zip(s.iter_mut()) {
            let (zr, zi) = (_mm256_broadcast_sd(&zp.re), _mm256_broadcast_sd(&zp.im));
            // real parts at lanes 0–7 of the state, imaginary parts at 8–15
            let (re_x, re_y) = (load(sp, 0), load(sp, 4));
            let (im_x, im_y) = (load(sp, 8), load(sp, 12));
            // re ← zr re − zi im + u; im ← zr im + zi re
            let re_x2 = _mm256_add_pd(
                _mm256_sub_pd(_mm256_mul_pd(zr, re_x), _mm256_mul_pd(zi, im_x)),
                u_x,
            );
            let re_y2 = _mm256_add_pd(
                _mm256_sub_pd(_mm256_mul_pd(zr, re_y), _mm256_mul_pd(zi, im_y)),
                u_y,
            );
            let im_x2 = _mm256_add_pd(_mm256_mul_pd(zr, im_x), _mm256_mul_pd(zi, re_x));
            let im_y2 = _mm256_add_pd(_mm256_mul_pd(zr, im_y), _mm256_mul_pd(zi, re_y));
            store(sp, 0, re_x2);
            store(sp, 4, re_y2);
            store(sp, 8, im_x2);
            store(sp, 12, im_y2);
            // sum += Re(g s) = g.re s.re − g.im s.im, with the new state before it is stored
            let term = |c: &Complex64, s_re: __m256d, s_im: __m256d| {
                let (c_re, c_im) = (_mm256_broadcast_sd(&c.re), _mm256_broadcast_sd(&c.im));
                _mm256_sub_pd(_mm256_mul_pd(c_re, s_re), _mm256_mul_pd(c_im, s_im))
            };
            h_x = _mm256_add_pd(h_x, term(&gp[0], re_x2, im_x2));
            h_y = _mm256_add_pd(h_y, term(&gp[1], re_y2, im_y2));
            k_x = _mm256_add_pd(k_x, term(&gp[2], re_x2, im_x2));
            k_y = _mm256_add_pd(k_y, term(&gp[2], re_y2, im_y2));
        }
        let put = |c: &mut Complex64, v| _mm_storeu_pd(c as *mut Complex64 as *mut f64, v);
        put(&mut o.h11_top, _mm256_castpd256_pd128(h_x));
        put(&mut o.h11_bottom, _mm256_extractf128_pd::<1>(h_x));
        put(&mut o.h22_top, _mm256_castpd256_pd128(h_y));
        put(&mut o.h22_bottom, _mm256_extractf128_pd::<1>(h_y));
        put(&mut o.k12_top_x, _mm256_castpd256_pd128(k_x));
        put(&mut o.k12_bottom_x, _mm256_extractf128_pd::<1>(k_x));
        put(&mut o.k12_top_y, _mm256_castpd256_pd128(k_y));
        put(&mut o.k12_bottom_y, _mm256_extractf128_pd::<1>(k_y));
    }
}
