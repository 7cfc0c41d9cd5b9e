//! The mapped kernel's eight-lane build, written in AVX-512F intrinsics: the operations of
//! [`block_forces`](super::block_forces), lane by lane and in the same order, so the bits are the
//! portable build's (test `every_lane_gives_the_bits_of_its_element_alone`). It is the four-lane
//! build of [`avx2`](super::avx2) on registers twice as wide; the nodes of a block are split into
//! x and y lanes by one two-source permute each (docs/performance.md, "The mapped kernel on eight
//! lanes (AVX-512)").

use std::arch::x86_64::{
    __m512d, __m512i, _mm512_add_pd, _mm512_castpd_si512, _mm512_castsi512_pd, _mm512_loadu_pd,
    _mm512_mul_pd, _mm512_permutex2var_pd, _mm512_set1_epi64, _mm512_set1_pd, _mm512_setr_epi64,
    _mm512_setzero_pd, _mm512_storeu_pd, _mm512_sub_pd, _mm512_xor_si512,
};

use super::{MAX_LANES, MappedStiffness, Segment, Shapes, block_nodes};
use crate::hint::prefetch;

/// A vector quantity of eight elements: x and y lanes.
#[derive(Clone, Copy)]
struct P {
    x: __m512d,
    y: __m512d,
}

/// The scalars of [`block_forces`](super::block_forces), each in every lane: the Gauss weights of
/// the near and far edge w₀, w₁, x_ξ and 1/x_ξ [m, 1/m], the entries of D [Pa], the sign bit
/// for the negations, and the permutes that pick the x and the y of eight nodes out of their
/// sixteen values.
struct Constants {
    w0: __m512d,
    w1: __m512d,
    x_xi: __m512d,
    inv_x_xi: __m512d,
    d00: __m512d,
    d01: __m512d,
    d10: __m512d,
    d11: __m512d,
    d22: __m512d,
    sign: __m512i,
    even: __m512i,
    odd: __m512i,
}

/// [`segment_forces`](super::segment_forces) on blocks of eight elements: for each block, its
/// corners read from the two displacement rows, its forces, and the eight lanes stored in place.
#[inline]
#[target_feature(enable = "avx512f")]
pub(super) fn segment(k: &MappedStiffness, blocks: &[Shapes<8>], segment: &Segment<'_>, out: &mut [f64]) {
    let (nx, stride) = (k.nx, out.len() / 8);
    // the shapes two blocks ahead are asked of the cache, past this segment's end too
    let (every, ahead) = (blocks, segment.first_block::<8>(nx) + AHEAD);
    let blocks = segment.blocks(nx, blocks);
    let g = 1.0 / 3f64.sqrt();
    let d = &k.elasticity;
    let c = Constants {
        w0: _mm512_set1_pd(0.25 * (1.0 + g)),
        w1: _mm512_set1_pd(0.25 * (1.0 - g)),
        x_xi: _mm512_set1_pd(k.half_width),
        inv_x_xi: _mm512_set1_pd(k.inv_half_width),
        d00: _mm512_set1_pd(d.d00),
        d01: _mm512_set1_pd(d.d01),
        d10: _mm512_set1_pd(d.d10),
        d11: _mm512_set1_pd(d.d11),
        d22: _mm512_set1_pd(d.d22),
        sign: _mm512_set1_epi64(i64::MIN),
        even: _mm512_setr_epi64(0, 2, 4, 6, 8, 10, 12, 14),
        odd: _mm512_setr_epi64(1, 3, 5, 7, 9, 11, 13, 15),
    };
    let mut pads = [[0.0; 2 * (MAX_LANES + 1)]; 2];
    for (j, (b, shape)) in (segment.first / 8..).zip(blocks).enumerate() {
        prefetch(every, ahead + j);
        let e = b * 8 - segment.e0;
        // every store below writes lanes e..e + 8 of one of the eight arrays of `stride` numbers
        assert!(e + 8 <= stride, "block {b} past the buffer of {stride} elements");
        let [pad_l, pad_h] = &mut pads;
        let (l0, l1) = nodes(block_nodes::<8>(segment.lower, b, nx, pad_l), &c);
        let (h0, h1) = nodes(block_nodes::<8>(segment.upper, b, nx, pad_h), &c);
        let fe = block_forces(shape, &c, [l0, l1, h1, h0]);
        let base = out.as_mut_ptr();
        for (a, corner) in fe.iter().enumerate() {
            // SAFETY: (2a + 1)·stride + e + 8 ≤ 8·stride = len ≤ out.len(), by the assert above.
            unsafe {
                _mm512_storeu_pd(base.add(2 * a * stride + e), corner.x);
                _mm512_storeu_pd(base.add((2 * a + 1) * stride + e), corner.y);
            }
        }
    }
}

/// Blocks ahead whose shapes (six cache lines each) [`segment`] asks the cache for: sixteen
/// elements, as the four-lane build's four blocks.
const AHEAD: usize = 2;

/// Nodes 0..8 and nodes 1..=8 of a block, from its nine nodes' x, y pairs (eighteen values) [m]:
/// sixteen values loaded as they lie, from the first node and from the second, and each sixteen
/// split into x and y lanes by one two-source permute.
#[inline]
#[target_feature(enable = "avx512f")]
fn nodes(r: &[f64], c: &Constants) -> (P, P) {
    let r = &r[..18];
    // SAFETY: `r` holds eighteen f64; the loads read r[0..8], r[8..16], r[2..10] and r[10..18],
    // unaligned.
    let load = |i: usize| unsafe { _mm512_loadu_pd(r.as_ptr().add(i)) };
    let split = |from: usize| {
        let (a, b) = (load(from), load(from + 8));
        P {
            x: _mm512_permutex2var_pd(a, c.even, b),
            y: _mm512_permutex2var_pd(a, c.odd, b),
        }
    };
    (split(0), split(2))
}

/// [`block_forces`](super::block_forces) on eight lanes: the same operations on the same operands
/// in the same order (a product's operands may swap: IEEE multiplication and addition are
/// commutative), the sums over Gauss points started from +0 as there.
#[inline]
#[target_feature(enable = "avx512f")]
fn block_forces(s: &Shapes<8>, c: &Constants, ue: [P; 4]) -> [P; 4] {
    // SAFETY: each array of `s` holds eight f64; the loads are unaligned.
    let load = |v: &[f64; 8]| unsafe { _mm512_loadu_pd(v.as_ptr()) };
    let (add, sub, mul) = (_mm512_add_pd, _mm512_sub_pd, _mm512_mul_pd);
    let diff = |a: P, b: P| P {
        x: sub(a.x, b.x),
        y: sub(a.y, b.y),
    };
    // w·a + w'·b, per component
    let weigh = |w: __m512d, a: P, w2: __m512d, b: P| P {
        x: add(mul(w, a.x), mul(w2, b.x)),
        y: add(mul(w, a.y), mul(w2, b.y)),
    };
    let (db, dt) = (diff(ue[1], ue[0]), diff(ue[2], ue[3]));
    let (dl, dr) = (diff(ue[3], ue[0]), diff(ue[2], ue[1]));
    let u_xi = [weigh(c.w0, db, c.w1, dt), weigh(c.w1, db, c.w0, dt)];
    let u_eta = [weigh(c.w0, dl, c.w1, dr), weigh(c.w1, dl, c.w0, dr)];
    let du_dy: [P; 2] = std::array::from_fn(|ix| {
        let inv = load(&s.inv_y_eta[ix]);
        P {
            x: mul(u_eta[ix].x, inv),
            y: mul(u_eta[ix].y, inv),
        }
    });
    let zero = P {
        x: _mm512_setzero_pd(),
        y: _mm512_setzero_pd(),
    };
    let mut p_sum = [zero; 2];
    let mut q_sum = [zero; 2];
    for je in 0..2 {
        let y_xi = load(&s.y_xi[je]);
        for ix in 0..2 {
            let dy = du_dy[ix];
            let dx = P {
                x: mul(sub(u_xi[je].x, mul(dy.x, y_xi)), c.inv_x_xi),
                y: mul(sub(u_xi[je].y, mul(dy.y, y_xi)), c.inv_x_xi),
            };
            let (e0, e1, e2) = (dx.x, dy.y, add(dy.x, dx.y));
            let sxx = add(mul(c.d00, e0), mul(c.d01, e1));
            let syy = add(mul(c.d10, e0), mul(c.d11, e1));
            let sxy = mul(c.d22, e2);
            let y_eta = load(&s.y_eta[ix]);
            p_sum[je] = P {
                x: add(p_sum[je].x, mul(sxx, y_eta)),
                y: add(p_sum[je].y, mul(sxy, y_eta)),
            };
            q_sum[ix] = P {
                x: add(q_sum[ix].x, sub(mul(c.x_xi, sxy), mul(y_xi, sxx))),
                y: add(q_sum[ix].y, sub(mul(c.x_xi, syy), mul(y_xi, sxy))),
            };
        }
    }
    let pb = weigh(c.w0, p_sum[0], c.w1, p_sum[1]);
    let pt = weigh(c.w1, p_sum[0], c.w0, p_sum[1]);
    let ql = weigh(c.w0, q_sum[0], c.w1, q_sum[1]);
    let qr = weigh(c.w1, q_sum[0], c.w0, q_sum[1]);
    // −a: the sign bit flipped (AVX-512F has no floating-point xor; AVX-512DQ's is not asked for)
    let flip = |a: __m512d| _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), c.sign));
    let neg = |a: P| P {
        x: flip(a.x),
        y: flip(a.y),
    };
    let plus = |a: P, b: P| P {
        x: add(a.x, b.x),
        y: add(a.y, b.y),
    };
    [diff(neg(pb), ql), diff(pb, qr), plus(pt, qr), plus(neg(pt), ql)]
}
