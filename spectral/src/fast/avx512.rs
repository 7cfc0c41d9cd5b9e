//! The fast path's split, recursion and assembly of one mode in AVX-512 registers, written in
//! intrinsics: the operations of `elastodynamics::split`, [`mode_kernel`](super::mode_kernel) and
//! `elastodynamics::forces` with the packing of F^± (`assemble_modes`), lane by lane and in the
//! same order, so the bits are those of the three separate passes (tests
//! `the_fused_pass_over_the_modes_gives_the_bits_of_the_separate_passes` and
//! `every_instruction_set_gives_the_bits_of_the_portable_build`). A mode's four spectra and its
//! eight sums each fill one register, so neither is stored: the pass reads the packed transforms
//! at j and N − j and writes F^± back to the same places. Left to the compiler, the same per-mode
//! code took two-lane registers for the whole recursion (docs/performance.md, "The spectral
//! model").
//!
//! Lanes hold complex numbers as (re, im) pairs, four pairs a register: the spectra as (top x,
//! bottom x, top y, bottom y), the sums H as (H11 top, H11 bottom, H22 top, H22 bottom) and K as
//! (K12 top x, K12 bottom x, K12 top y, K12 bottom y), the order of [`Lanes`](super::Lanes).

use std::arch::x86_64::{
    __m128d, __m512d, _mm_loadu_pd, _mm_storeu_pd, _mm256_castpd256_pd128, _mm256_extractf128_pd,
    _mm256_load_ps, _mm256_set_m128d, _mm256_set1_pd, _mm256_store_ps, _mm512_add_pd, _mm512_castpd_si512,
    _mm512_castpd256_pd512, _mm512_castpd512_pd256, _mm512_castsi512_pd, _mm512_cvtpd_ps, _mm512_cvtps_pd,
    _mm512_insertf64x4, _mm512_load_pd, _mm512_mask_blend_pd, _mm512_mul_pd, _mm512_permute_pd,
    _mm512_set1_pd, _mm512_setr_epi64, _mm512_setzero_pd, _mm512_shuffle_f64x2, _mm512_store_pd,
    _mm512_sub_pd, _mm512_xor_si512,
};

use rustfft::num_complex::Complex64;

use super::{Packed, Stored};

/// Sign bits of the real (even) lanes.
const EVEN: [i64; 8] = [i64::MIN, 0, i64::MIN, 0, i64::MIN, 0, i64::MIN, 0];
/// Sign bits of the imaginary (odd) lanes.
const ODD: [i64; 8] = [0, i64::MIN, 0, i64::MIN, 0, i64::MIN, 0, i64::MIN];
/// Sign bits of the pairs 0 and 2 (the top face's H): −μk there, μk on the bottom's.
const TOP_PAIRS: [i64; 8] = [i64::MIN, i64::MIN, 0, 0, i64::MIN, i64::MIN, 0, 0];

/// Every mode of one block: `r` poles a mode, the block's z, g and states, and its place in the
/// packed transforms.
#[target_feature(enable = "avx512f,avx2,fma")]
pub(super) fn modes<S: Stored>(r: usize, z: &[Complex64], g: &[[Complex64; 3]], s: &mut [S], p: Packed<'_>) {
    let Packed {
        aj,
        an,
        bj,
        bn,
        k,
        mu,
        c,
    } = p;
    let modes = aj.len();
    assert!(
        an.len() == modes && bj.len() == modes && bn.len() == modes && k.len() == modes,
        "a block's packed slices and wavenumbers, one a mode"
    );
    assert!(z.len() >= modes * r && g.len() >= modes * r && s.len() >= modes * r);
    let coefficients = z.chunks(r).zip(g.chunks(r));
    for (m, (s, (z, g))) in s.chunks_mut(r).zip(coefficients).take(modes).enumerate() {
        let back = modes - 1 - m;
        let muk = mu * k[m];
        let [a_j, a_n, b_j, b_n] = mode(z, g, s, [&aj[m], &an[back], &bj[m], &bn[back]], muk, c);
        // SAFETY: each pointer is to one Complex64 borrowed mutably here: two f64, `repr(C)`.
        unsafe {
            let put = |x: &mut Complex64, v: __m128d| _mm_storeu_pd(x as *mut Complex64 as *mut f64, v);
            put(&mut aj[m], a_j);
            put(&mut an[back], a_n);
            put(&mut bj[m], b_j);
            put(&mut bn[back], b_n);
        }
    }
}

/// One mode: its transforms at j and N − j (`a_j`, `a_n`, `b_j`, `b_n`) in, its packed F^± at
/// the same places out, μk and 2 − η given.
#[inline]
#[target_feature(enable = "avx512f,avx2,fma")]
fn mode<S: Stored>(
    z: &[Complex64],
    g: &[[Complex64; 3]],
    s: &mut [S],
    [a_j, a_n, b_j, b_n]: [&Complex64; 4],
    muk: f64,
    c: f64,
) -> [__m128d; 4] {
    let n = z.len().min(g.len()).min(s.len());
    let (z, g, s) = (&z[..n], &g[..n], &mut s[..n]);
    // SAFETY: every pointer below points into a value borrowed for the whole call; each read or
    // write stays inside it (a Complex64 is two f64, `repr(C)`), and a state is `repr(C)` and
    // aligned to 64 bytes: eight f64 real parts then eight imaginary ones (each half aligned to
    // 64), or as many f32 if `S::SINGLE` (each half aligned to 32).
    unsafe {
        // a state's eight real (`half` 0) or imaginary (1) lanes, widened to f64 if stored as f32
        let load = |sp: &S, half: usize| {
            if S::SINGLE {
                _mm512_cvtps_pd(_mm256_load_ps((sp as *const S as *const f32).add(8 * half)))
            } else {
                _mm512_load_pd((sp as *const S as *const f64).add(8 * half))
            }
        };
        // ... stored back, rounded to f32 (to nearest, the default mode) if stored as f32
        let store = |sp: &mut S, half: usize, v: __m512d| {
            if S::SINGLE {
                _mm256_store_ps((sp as *mut S as *mut f32).add(8 * half), _mm512_cvtpd_ps(v))
            } else {
                _mm512_store_pd((sp as *mut S as *mut f64).add(8 * half), v)
            }
        };
        let mask = |m: [i64; 8]| _mm512_setr_epi64(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7]);
        let flip =
            |v: __m512d, m: [i64; 8]| _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(v), mask(m)));
        let load_c = |x: &Complex64| _mm_loadu_pd(x as *const Complex64 as *const f64);
        // each (re, im) pair swapped to (im, re)
        let swap = |v: __m512d| _mm512_permute_pd::<0b0101_0101>(v);
        // the two halves of four lanes exchanged
        let halves = |v: __m512d| _mm512_shuffle_f64x2::<0b0100_1110>(v, v);
        let twice = |lo: __m128d, hi: __m128d| {
            let v = _mm256_set_m128d(hi, lo);
            _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(v), v)
        };

        // the split (`elastodynamics::split`): with Ā = conj(a_n), x = ½(a_j + Ā), y = (−i/2)(a_j − Ā)
        let a = twice(load_c(a_j), load_c(b_j));
        let conj_n = flip(twice(load_c(a_n), load_c(b_n)), ODD);
        let x = _mm512_mul_pd(_mm512_set1_pd(0.5), _mm512_add_pd(a, conj_n));
        // (0 − 0.5 i)(d.re + i d.im) = (0 d.re − (−0.5) d.im) + i(0 d.im + (−0.5) d.re)
        let d = _mm512_sub_pd(a, conj_n);
        let zero_d = _mm512_mul_pd(_mm512_setzero_pd(), d);
        let half_d = _mm512_mul_pd(_mm512_set1_pd(-0.5), swap(d));
        let y = _mm512_mask_blend_pd(
            0b1010_1010,
            _mm512_sub_pd(zero_d, half_d),
            _mm512_add_pd(zero_d, half_d),
        );
        // u: lanes 0–3 the x spectra (top, bottom), 4–7 the y spectra
        let u = _mm512_mask_blend_pd(0b1111_0000, x, y);

        // the recursion ([`mode_kernel`](super::mode_kernel)), the sums started from +0 and
        // taking the new state before it is stored
        let (mut h, mut k) = (_mm512_setzero_pd(), _mm512_setzero_pd());
        for ((zp, gp), sp) in z.iter().zip(g).zip(s.iter_mut()) {
            let (zr, zi) = (_mm512_set1_pd(zp.re), _mm512_set1_pd(zp.im));
            let (re, im) = (load(sp, 0), load(sp, 1));
            // re ← zr re − zi im + u; im ← zr im + zi re
            let re2 = _mm512_add_pd(_mm512_sub_pd(_mm512_mul_pd(zr, re), _mm512_mul_pd(zi, im)), u);
            let im2 = _mm512_add_pd(_mm512_mul_pd(zr, im), _mm512_mul_pd(zi, re));
            store(sp, 0, re2);
            store(sp, 1, im2);
            // sum += Re(g s) = g.re s.re − g.im s.im: g_H11 on the x lanes, g_H22 on the y lanes
            let gh_re = _mm512_insertf64x4::<1>(_mm512_set1_pd(gp[0].re), _mm256_set1_pd(gp[1].re));
            let gh_im = _mm512_insertf64x4::<1>(_mm512_set1_pd(gp[0].im), _mm256_set1_pd(gp[1].im));
            let (gk_re, gk_im) = (_mm512_set1_pd(gp[2].re), _mm512_set1_pd(gp[2].im));
            h = _mm512_add_pd(
                h,
                _mm512_sub_pd(_mm512_mul_pd(gh_re, re2), _mm512_mul_pd(gh_im, im2)),
            );
            k = _mm512_add_pd(
                k,
                _mm512_sub_pd(_mm512_mul_pd(gk_re, re2), _mm512_mul_pd(gk_im, im2)),
            );
        }

        // F^± (`elastodynamics::forces` with the coupling μk): F = ∓μk H ± i μk (c Û + K), the
        // H11 pairs taking the y spectra and K12 of y, the H22 pairs those of x
        let coupled = halves(_mm512_mul_pd(
            _mm512_set1_pd(muk),
            _mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(c), u), k),
        ));
        let i_coupled = flip(swap(coupled), EVEN); // i w = (−w.im, w.re)
        let direct = _mm512_mul_pd(flip(_mm512_set1_pd(muk), TOP_PAIRS), h);
        // (F^+_1, F^-_1, F^+_2, F^-_2): + i(..) for the first two, − i(..) for the last two
        let f = _mm512_mask_blend_pd(
            0b1111_0000,
            _mm512_add_pd(direct, i_coupled),
            _mm512_sub_pd(direct, i_coupled),
        );
        // packed: F_1 + i F_2 at j, conj(F_1) + i conj(F_2) at N − j, where i conj(w) = (w.im, w.re)
        let f2 = swap(halves(f));
        let at_j = _mm512_castpd512_pd256(_mm512_add_pd(f, flip(f2, EVEN)));
        let at_n = _mm512_castpd512_pd256(_mm512_add_pd(flip(f, ODD), f2));
        [
            _mm256_castpd256_pd128(at_j),
            _mm256_castpd256_pd128(at_n),
            _mm256_extractf128_pd::<1>(at_j),
            _mm256_extractf128_pd::<1>(at_n),
        ]
    }
}
