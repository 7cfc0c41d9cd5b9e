//! The mapped kernel's four-lane build, written in AVX2 and FMA intrinsics (`kernel_in!`, module
//! `intrinsics`): the operations of [`block_forces`](super::block_forces), lane by lane and in the
//! same order, so the bits are the portable build's (test
//! `every_lane_gives_the_bits_of_its_element_alone`). Left to the compiler, the lane code kept its
//! sums in arrays that went through the stack, reloaded the output buffer's eight pointers for
//! every block and checked each store's bounds (docs/performance.md, "The mapped kernel in
//! intrinsics").

use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_fmadd_pd, _mm256_fnmadd_pd, _mm256_loadu_pd, _mm256_mul_pd,
    _mm256_permute4x64_pd, _mm256_set1_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd,
    _mm256_unpackhi_pd, _mm256_unpacklo_pd, _mm256_xor_pd,
};

kernel_in! {
    feature: "avx2,fma",
    lanes: 4,
    register: __m256d,
    // four blocks of four elements: three cache lines of shapes each
    ahead: 4,
    set1: _mm256_set1_pd,
    zero: _mm256_setzero_pd,
    load: _mm256_loadu_pd,
    store: _mm256_storeu_pd,
    add: _mm256_add_pd,
    sub: _mm256_sub_pd,
    mul: _mm256_mul_pd,
    fmadd: _mm256_fmadd_pd,
    fnmadd: _mm256_fnmadd_pd,
}

/// Nodes 0..4 and nodes 1..=4 of a block, from its five nodes' x, y pairs (ten values) [m]: the
/// pairs loaded as they lie, then split into x and y lanes by one in-lane unpack and one permute
/// each.
#[inline]
#[target_feature(enable = "avx2")]
fn nodes(r: &[f64]) -> (P, P) {
    let r = &r[..10];
    // SAFETY: `r` holds ten f64; the loads read r[0..4], r[2..6], r[4..8] and r[6..10], unaligned.
    let load = |i: usize| unsafe { _mm256_loadu_pd(r.as_ptr().add(i)) };
    // (a₀, b₀, a₂, b₂) = (x₀, x₂, x₁, x₃) → (x₀, x₁, x₂, x₃)
    let split = |a: __m256d, b: __m256d| P {
        x: _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpacklo_pd(a, b)),
        y: _mm256_permute4x64_pd::<0b11_01_10_00>(_mm256_unpackhi_pd(a, b)),
    };
    (split(load(0), load(4)), split(load(2), load(6)))
}

/// −a: the sign bit of every lane flipped.
#[inline]
#[target_feature(enable = "avx2")]
fn neg(a: __m256d) -> __m256d {
    _mm256_xor_pd(a, _mm256_set1_pd(-0.0))
}
