//! The mapped kernel's eight-lane build, written in AVX-512F intrinsics (`kernel_in!`, module
//! `intrinsics`): the operations of [`block_forces`](super::block_forces), lane by lane and in the
//! same order, so the bits are the portable build's (test
//! `every_lane_gives_the_bits_of_its_element_alone`). It is the four-lane AVX2 build on registers
//! twice as wide; the nodes of a block are split into x and y lanes by one two-source permute each
//! (docs/performance.md, "Every mesh kind side by side", its fifth machine).

use std::arch::x86_64::{
    __m512d, _mm512_add_pd, _mm512_castpd_si512, _mm512_castsi512_pd, _mm512_fmadd_pd, _mm512_fnmadd_pd,
    _mm512_loadu_pd, _mm512_mul_pd, _mm512_permutex2var_pd, _mm512_set1_epi64, _mm512_set1_pd,
    _mm512_setr_epi64, _mm512_setzero_pd, _mm512_storeu_pd, _mm512_sub_pd, _mm512_xor_si512,
};

kernel_in! {
    feature: "avx512f",
    lanes: 8,
    register: __m512d,
    // twelve blocks of eight elements, six cache lines of shapes each: the whole runs' bulk-force
    // phase took 7 % less than with two blocks (as the four-lane build's sixteen elements), where
    // a benchmark whose shapes stay in the cache had shown no difference (docs/performance.md,
    // "The shapes asked of the cache twelve blocks ahead")
    ahead: 12,
    set1: _mm512_set1_pd,
    zero: _mm512_setzero_pd,
    load: _mm512_loadu_pd,
    store: _mm512_storeu_pd,
    add: _mm512_add_pd,
    sub: _mm512_sub_pd,
    mul: _mm512_mul_pd,
    fmadd: _mm512_fmadd_pd,
    fnmadd: _mm512_fnmadd_pd,
}

/// Nodes 0..8 and nodes 1..=8 of a block, from its nine nodes' x, y pairs (eighteen values) [m]:
/// sixteen values loaded as they lie, from the first node and from the second, and each sixteen
/// split into x and y lanes by one two-source permute.
#[inline]
#[target_feature(enable = "avx512f")]
fn nodes(r: &[f64]) -> (P, P) {
    let r = &r[..18];
    // SAFETY: `r` holds eighteen f64; the loads read r[0..8], r[8..16], r[2..10] and r[10..18],
    // unaligned.
    let load = |i: usize| unsafe { _mm512_loadu_pd(r.as_ptr().add(i)) };
    let (even, odd) = (
        _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14),
        _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15),
    );
    let split = |from: usize| {
        let (a, b) = (load(from), load(from + 8));
        P {
            x: _mm512_permutex2var_pd(a, even, b),
            y: _mm512_permutex2var_pd(a, odd, b),
        }
    };
    (split(0), split(2))
}

/// −a: the sign bit of every lane flipped, by an integer xor (AVX-512F has no floating-point one;
/// AVX-512DQ's is not asked for).
#[inline]
#[target_feature(enable = "avx512f")]
fn neg(a: __m512d) -> __m512d {
    _mm512_castsi512_pd(_mm512_xor_si512(
        _mm512_castpd_si512(a),
        _mm512_set1_epi64(i64::MIN),
    ))
}
