//! The mapped kernel's four-lane build, written in AVX2 intrinsics: the operations of
//! [`block_forces`](super::block_forces), lane by lane and in the same order, so the bits are the
//! portable build's (test `every_lane_gives_the_bits_of_its_element_alone`). Left to the compiler,
//! the lane code kept its sums in arrays that went through the stack, reloaded the output
//! buffer's eight pointers for every block and checked each store's bounds
//! (docs/performance.md, "The mapped kernel in intrinsics").

use std::arch::x86_64::{
    __m256d, _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute4x64_pd, _mm256_set1_pd,
    _mm256_setzero_pd, _mm256_storeu_pd, _mm256_sub_pd, _mm256_unpackhi_pd, _mm256_unpacklo_pd,
    _mm256_xor_pd,
};

use super::{MAX_LANES, MappedStiffness, Segment, Shapes, block_nodes};
use crate::hint::prefetch;

/// A vector quantity of four elements: x and y lanes.
#[derive(Clone, Copy)]
struct P {
    x: __m256d,
    y: __m256d,
}

/// The scalars of [`block_forces`](super::block_forces), each in every lane: the Gauss weights of
/// the near and far edge w₀, w₁, x_ξ and 1/x_ξ [m, 1/m], the entries of D [Pa], and −0 for the
/// negations.
struct Constants {
    w0: __m256d,
    w1: __m256d,
    x_xi: __m256d,
    inv_x_xi: __m256d,
    d00: __m256d,
    d01: __m256d,
    d10: __m256d,
    d11: __m256d,
    d22: __m256d,
    sign: __m256d,
}

/// [`segment_forces`](super::segment_forces) on blocks of four elements: for each block, its
/// corners read from the two displacement rows, its forces, and the eight lanes stored in place.
#[inline]
#[target_feature(enable = "avx2")]
pub(super) fn segment(k: &MappedStiffness, blocks: &[Shapes<4>], segment: &Segment<'_>, out: &mut [f64]) {
    let (nx, stride) = (k.nx, out.len() / 8);
    // the shapes four blocks ahead are asked of the cache, past this segment's end too
    let (every, ahead) = (blocks, segment.first_block::<4>(nx) + AHEAD);
    let blocks = segment.blocks(nx, blocks);
    let g = 1.0 / 3f64.sqrt();
    let d = &k.elasticity;
    let c = Constants {
        w0: _mm256_set1_pd(0.25 * (1.0 + g)),
        w1: _mm256_set1_pd(0.25 * (1.0 - g)),
        x_xi: _mm256_set1_pd(k.half_width),
        inv_x_xi: _mm256_set1_pd(k.inv_half_width),
        d00: _mm256_set1_pd(d.d00),
        d01: _mm256_set1_pd(d.d01),
        d10: _mm256_set1_pd(d.d10),
        d11: _mm256_set1_pd(d.d11),
        d22: _mm256_set1_pd(d.d22),
        sign: _mm256_set1_pd(-0.0),
    };
    let mut pads = [[0.0; 2 * (MAX_LANES + 1)]; 2];
    for (j, (b, shape)) in (segment.first / 4..).zip(blocks).enumerate() {
        prefetch(every, ahead + j);
        let e = b * 4 - segment.e0;
        // every store below writes lanes e..e + 4 of one of the eight arrays of `stride` numbers
        assert!(e + 4 <= stride, "block {b} past the buffer of {stride} elements");
        let [pad_l, pad_h] = &mut pads;
        let (l0, l1) = nodes(block_nodes::<4>(segment.lower, b, nx, pad_l));
        let (h0, h1) = nodes(block_nodes::<4>(segment.upper, b, nx, pad_h));
        let fe = block_forces(shape, &c, [l0, l1, h1, h0]);
        let base = out.as_mut_ptr();
        for (a, corner) in fe.iter().enumerate() {
            // SAFETY: (2a + 1)·stride + e + 4 ≤ 8·stride = len ≤ out.len(), by the assert above.
            unsafe {
                _mm256_storeu_pd(base.add(2 * a * stride + e), corner.x);
                _mm256_storeu_pd(base.add((2 * a + 1) * stride + e), corner.y);
            }
        }
    }
}

/// Blocks ahead whose shapes (three cache lines each) [`segment`] asks the cache for.
const AHEAD: usize = 4;

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

/// [`block_forces`](super::block_forces) on four lanes: the same operations on the same operands
/// in the same order (a product's operands may swap: IEEE multiplication and addition are
/// commutative), the sums over Gauss points started from +0 as there.
#[inline]
#[target_feature(enable = "avx2")]
fn block_forces(s: &Shapes<4>, c: &Constants, ue: [P; 4]) -> [P; 4] {
    // SAFETY: each array of `s` holds four f64; the loads are unaligned.
    let load = |v: &[f64; 4]| unsafe { _mm256_loadu_pd(v.as_ptr()) };
    let (add, sub, mul) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd);
    let diff = |a: P, b: P| P {
        x: sub(a.x, b.x),
        y: sub(a.y, b.y),
    };
    // w·a + w'·b, per component
    let weigh = |w: __m256d, a: P, w2: __m256d, b: P| P {
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
        x: _mm256_setzero_pd(),
        y: _mm256_setzero_pd(),
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
    let neg = |a: P| P {
        x: _mm256_xor_pd(a.x, c.sign),
        y: _mm256_xor_pd(a.y, c.sign),
    };
    let plus = |a: P, b: P| P {
        x: add(a.x, b.x),
        y: add(a.y, b.y),
    };
    [diff(neg(pb), ql), diff(pb, qr), plus(pt, qr), plus(neg(pt), ql)]
}
