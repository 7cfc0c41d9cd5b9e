//! The internal forces of a structured mesh of identical Q4 elements as a stencil (docs/fem-model.md
//! §1): every node gathers f_a = −Σ_e K_e[a-rows] u_e from its ≤ 4 elements, and with one K_e for
//! all elements that is a fixed 2×2 block per neighbour node. One layer (node row) at a time, from
//! the displacement rows below, of and above it, as flat x, y pairs.
//!
//! Interior nodes run lane code at the CPU's widest vectors (8 lanes with AVX-512, 4 in portable
//! code; the AVX2 build writes its 4 lanes out in intrinsics), two edge nodes per layer scalar;
//! every node's force is the same sequence of IEEE operations whatever the vector width, the
//! grouping or the thread.

/// Element stiffness K_e [N/m per m] (8×8, DOF order x₀, y₀, x₁, y₁, …).
pub(crate) type Ke = [[f64; 8]; 8];

/// A 2×2 block of K multiplying the displacement of one neighbour, as the two lane patterns of
/// a pair of nodes: f_x, f_y, f_x, f_y += `xs` · (u_x, u_x, u_x', u_x') + `ys` · (u_y, u_y, u_y', u_y').
pub(crate) type Block = [[f64; 4]; 2];

/// Blocks per node row of the stencil and per column offset dc = −1, 0, 1 (index dc + 1).
type Rows<const R: usize> = [[Block; 3]; R];

/// Row-major 2×2 blocks per node row of one element row (lower, upper) and column offset.
type Half = [[[f64; 4]; 3]; 2];

/// The stencils of one kind of layer: interior nodes (both element columns), the left edge
/// (element column i only) and the right edge (element column i − 1 only).
#[derive(Debug, Clone)]
struct Kind<const R: usize> {
    interior: Rows<R>,
    left: Rows<R>,
    right: Rows<R>,
}

/// Stencils of a shared K_e for a layer with element rows on both sides (3 node rows, the middle
/// row's blocks summed over the two element rows), below only (2 rows), or above only (2 rows).
#[derive(Debug, Clone)]
pub(crate) struct Stencil {
    both: Kind<3>,
    below: Kind<2>,
    above: Kind<2>,
    /// The CPU has AVX2 / AVX-512F (checked once at build): the same lane code compiled for
    /// 4- and 8-wide vectors.
    avx2: bool,
    avx512: bool,
}

/// Which element columns a stencil gathers from.
#[derive(Clone, Copy, PartialEq)]
enum Columns {
    Both,
    Right,
    Left,
}

impl Stencil {
    /// The stencils of element stiffness `k` (DOF order x₀, y₀, x₁, y₁, … counter-clockwise from
    /// the bottom-left node).
    pub(crate) fn new(k: &Ke) -> Stencil {
        let lanes = |m: [f64; 4]| -> Block { [[m[0], m[2], m[0], m[2]], [m[1], m[3], m[1], m[3]]] };
        let kind2 = |half: Half| half.map(|r| r.map(lanes));
        let (below_i, above_i) = halves(k, Columns::Both);
        let (below_l, above_l) = halves(k, Columns::Left);
        let (below_r, above_r) = halves(k, Columns::Right);
        let merge = |below: Half, above: Half| {
            let mut mid = [[0.0; 4]; 3];
            for dc in 0..3 {
                for q in 0..4 {
                    mid[dc][q] = below[1][dc][q] + above[0][dc][q];
                }
            }
            [below[0], mid, above[1]].map(|r| r.map(lanes))
        };
        #[cfg(target_arch = "x86_64")]
        let (avx2, avx512) = (
            std::arch::is_x86_feature_detected!("avx2"),
            std::arch::is_x86_feature_detected!("avx512f"),
        );
        #[cfg(not(target_arch = "x86_64"))]
        let (avx2, avx512) = (false, false);
        Stencil {
            both: Kind {
                interior: merge(below_i, above_i),
                left: merge(below_l, above_l),
                right: merge(below_r, above_r),
            },
            below: Kind {
                interior: kind2(below_i),
                left: kind2(below_l),
                right: kind2(below_r),
            },
            above: Kind {
                interior: kind2(above_i),
                left: kind2(above_l),
                right: kind2(above_r),
            },
            avx2,
            avx512,
        }
    }

    /// f = −f_int of every node of one layer into `out` (its x, y pairs), from the displacement
    /// rows below (`lo`, if the layer has an element row below), of the layer (`mid`) and above
    /// (`hi`, if it has one above). At least 3 nodes per row.
    pub(crate) fn layer(&self, lo: Option<&[f64]>, mid: &[f64], hi: Option<&[f64]>, out: &mut [f64]) {
        match (lo, hi) {
            (Some(lo), Some(hi)) => self.run([lo, mid, hi], &self.both, out),
            (Some(lo), None) => self.run([lo, mid], &self.below, out),
            (None, Some(hi)) => self.run([mid, hi], &self.above, out),
            (None, None) => out.fill(0.0),
        }
    }

    #[inline]
    fn run<const R: usize>(&self, rows: [&[f64]; R], kind: &Kind<R>, out: &mut [f64]) {
        let nx = out.len() / 2 - 1;
        edge(rows, &kind.left, 0, 1..3, out);
        edge(rows, &kind.right, nx, 0..2, out);
        self.interior(rows, &kind.interior, out);
    }

    /// Forces of the interior nodes 1..nx−1 of one layer.
    #[inline]
    fn interior<const R: usize>(&self, rows: [&[f64]; R], blocks: &Rows<R>, out: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if self.avx512 {
            // SAFETY: `avx512` is true only if the CPU reported AVX-512F at run time (`Stencil::new`).
            return unsafe { interior_avx512(rows, blocks, out) };
        }
        #[cfg(target_arch = "x86_64")]
        if self.avx2 {
            // SAFETY: `avx2` is true only if the CPU reported AVX2 at run time (`Stencil::new`).
            return unsafe { interior_avx2(rows, blocks, out) };
        }
        interior::<R, 4>(rows, blocks, out)
    }
}

/// Per element row below and above a node (index 0: the lower node row of that element row),
/// the 2×2 blocks K[a-rows][b-columns] summed over the element columns `cols`, placed at the
/// neighbour's column offset.
fn halves(k: &Ke, cols: Columns) -> (Half, Half) {
    let block = |a: usize, b: usize| {
        [
            k[2 * a][2 * b],
            k[2 * a][2 * b + 1],
            k[2 * a + 1][2 * b],
            k[2 * a + 1][2 * b + 1],
        ]
    };
    // (element column: i − 1 → Right edge's only column, i → Left edge's; local index a of the
    // node; element nodes b = 0..3 at (node row offset, column offset + 1))
    let below_elems = [
        (Columns::Right, 2usize, [(0usize, 0usize), (0, 1), (1, 1), (1, 0)]),
        (Columns::Left, 3, [(0, 1), (0, 2), (1, 2), (1, 1)]),
    ];
    let above_elems = [
        (Columns::Right, 1usize, [(0usize, 0usize), (0, 1), (1, 1), (1, 0)]),
        (Columns::Left, 0, [(0, 1), (0, 2), (1, 2), (1, 1)]),
    ];
    let mut below: Half = [[[0.0; 4]; 3]; 2];
    let mut above: Half = [[[0.0; 4]; 3]; 2];
    for (target, elems) in [(&mut below, below_elems), (&mut above, above_elems)] {
        for (col, a, nodes) in elems {
            if cols != Columns::Both && cols != col {
                continue;
            }
            for (b, (lo, dc)) in nodes.iter().enumerate() {
                for (t, v) in target[*lo][*dc].iter_mut().zip(block(a, b)) {
                    *t += v;
                }
            }
        }
    }
    (below, above)
}

/// The force of edge node i (0 or nx) from the column offsets `dcs` that exist there, with the
/// operations of [`interior`]'s one-node tail.
#[inline]
fn edge<const R: usize>(
    rows: [&[f64]; R],
    blocks: &Rows<R>,
    i: usize,
    dcs: std::ops::Range<usize>,
    out: &mut [f64],
) {
    let mut acc = [0.0f64; 2];
    for (row, blk) in rows.iter().zip(blocks) {
        for dc in dcs.clone() {
            let [xs, ys] = &blk[dc];
            let j = 2 * (i + dc - 1);
            for l in 0..2 {
                acc[l] += xs[l] * row[j] + ys[l] * row[j + 1];
            }
        }
    }
    out[2 * i] = -acc[0];
    out[2 * i + 1] = -acc[1];
}

/// Node pairs per iteration of [`interior_avx2`].
#[cfg(target_arch = "x86_64")]
const PAIRS: usize = 2;

/// The AVX2 build: two node pairs per iteration, each pair's four lanes (f_x, f_y, f_x', f_y') in
/// one register. Per neighbour the displacement window (u_x, u_y, u_x', u_y') is loaded as it lies
/// and with its pairs swapped in-lane, so that f_x += k_xx u_x + k_xy u_y and f_y += k_yy u_y +
/// k_yx u_x: the products of [`interior`]'s lanes, the f_y pair added in the other order (exact),
/// without the cross-lane shuffles the compiler builds from that code's broadcast pattern. The
/// two pairs are independent sums, so one pair's adds do not wait on the other's. The nodes left
/// over go through [`interior`] from the first one not done.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn interior_avx2<const R: usize>(rows: [&[f64]; R], blocks: &Rows<R>, out: &mut [f64]) {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_blend_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_permute_pd,
        _mm256_set1_pd, _mm256_setzero_pd, _mm256_storeu_pd, _mm256_xor_pd,
    };
    let nx = out.len() / 2 - 1;
    // per node row and column offset: (k_xx, k_yy, k_xx, k_yy) and (k_xy, k_yx, k_xy, k_yx), from
    // the blocks' (k_xx, k_yx, …) and (k_xy, k_yy, …)
    let load = |v: &[f64; 4]| {
        // SAFETY: `v` holds four f64; the load is unaligned.
        unsafe { _mm256_loadu_pd(v.as_ptr()) }
    };
    let coefficients: [[[__m256d; 2]; 3]; R] = std::array::from_fn(|r| {
        std::array::from_fn(|dc| {
            let [xs, ys] = &blocks[r][dc];
            let (xs, ys) = (load(xs), load(ys));
            [
                _mm256_blend_pd::<0b1010>(xs, ys),
                _mm256_blend_pd::<0b0101>(xs, ys),
            ]
        })
    });
    let sign = _mm256_set1_pd(-0.0);
    let negate = |a: __m256d| _mm256_xor_pd(a, sign);
    let mut i = 1;
    while i + 2 * PAIRS <= nx {
        let mut acc = [_mm256_setzero_pd(); PAIRS];
        for (row, ks) in rows.iter().zip(&coefficients) {
            // nodes i − 1 ..= i + 2·PAIRS, x, y pairs
            let u = &row[2 * (i - 1)..2 * (i - 1) + 4 * PAIRS + 4];
            for (dc, [k1, k2]) in ks.iter().enumerate() {
                for (g, a) in acc.iter_mut().enumerate() {
                    let w = load(
                        u[4 * g + 2 * dc..4 * g + 2 * dc + 4]
                            .try_into()
                            .expect("four values"),
                    );
                    let t = _mm256_add_pd(
                        _mm256_mul_pd(*k1, w),
                        _mm256_mul_pd(*k2, _mm256_permute_pd::<0b0101>(w)),
                    );
                    *a = _mm256_add_pd(*a, t);
                }
            }
        }
        let o = &mut out[2 * i..2 * i + 4 * PAIRS];
        for (g, a) in acc.iter().enumerate() {
            // SAFETY: `o` holds 4·PAIRS f64; the store is unaligned. The sign bit is flipped, as
            // the scalar negation does (0 − a would give +0 where −a gives −0).
            unsafe { _mm256_storeu_pd(o.as_mut_ptr().add(4 * g), negate(*a)) };
        }
        i += 2 * PAIRS;
    }
    interior_from::<R, 4>(rows, blocks, out, i)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn interior_avx512<const R: usize>(rows: [&[f64]; R], blocks: &Rows<R>, out: &mut [f64]) {
    interior::<R, 8>(rows, blocks, out)
}

/// L/2 nodes per iteration in L lanes (f_x, f_y of node i, then of node i + 1, …); the nodes left
/// over take one at a time the first two lanes of the same arithmetic.
#[inline(always)]
fn interior<const R: usize, const L: usize>(rows: [&[f64]; R], blocks: &Rows<R>, out: &mut [f64]) {
    interior_from::<R, L>(rows, blocks, out, 1)
}

/// [`interior`] from node `i` on.
#[inline(always)]
fn interior_from<const R: usize, const L: usize>(
    rows: [&[f64]; R],
    blocks: &Rows<R>,
    out: &mut [f64],
    mut i: usize,
) {
    let nx = out.len() / 2 - 1;
    let p = L / 2;
    while i + p <= nx {
        let mut acc = [0.0f64; L];
        for (row, blk) in rows.iter().zip(blocks) {
            let u = &row[2 * (i - 1)..2 * (i - 1) + L + 4];
            for (dc, [xs, ys]) in blk.iter().enumerate() {
                let w = &u[2 * dc..2 * dc + L];
                for l in 0..L {
                    let pair = l & !1;
                    acc[l] += xs[l % 4] * w[pair] + ys[l % 4] * w[pair + 1];
                }
            }
        }
        for (o, a) in out[2 * i..2 * i + L].iter_mut().zip(acc) {
            *o = -a;
        }
        i += p;
    }
    while i < nx {
        let mut acc = [0.0f64; 2];
        for (row, blk) in rows.iter().zip(blocks) {
            for (dc, [xs, ys]) in blk.iter().enumerate() {
                let j = 2 * (i + dc - 1);
                for l in 0..2 {
                    acc[l] += xs[l] * row[j] + ys[l] * row[j + 1];
                }
            }
        }
        out[2 * i] = -acc[0];
        out[2 * i + 1] = -acc[1];
        i += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every vector width gives the same bits as the portable code (the run's output must not
    /// depend on the CPU it runs on). Any 8×8 matrix will do for that: one with distinct entries.
    #[test]
    fn widths_agree_bit_for_bit() {
        let mut k: Ke = [[0.0; 8]; 8];
        for (i, row) in k.iter_mut().enumerate() {
            for (j, kij) in row.iter_mut().enumerate() {
                *kij = ((i * 8 + j) as f64 * 0.377).sin() * 1e7;
            }
        }
        let st = Stencil::new(&k);
        let w = 23;
        let rows: Vec<Vec<f64>> = (0..3)
            .map(|r| (0..2 * w).map(|k| ((k + 7 * r) as f64 * 0.731).sin()).collect())
            .collect();
        let rows = [rows[0].as_slice(), rows[1].as_slice(), rows[2].as_slice()];
        let mut reference = vec![0.0; 2 * w];
        interior::<3, 2>(rows, &st.both.interior, &mut reference);
        let mut four = vec![0.0; 2 * w];
        interior::<3, 4>(rows, &st.both.interior, &mut four);
        let mut eight = vec![0.0; 2 * w];
        interior::<3, 8>(rows, &st.both.interior, &mut eight);
        let mut dispatched = vec![0.0; 2 * w];
        st.interior(rows, &st.both.interior, &mut dispatched);
        assert_eq!(reference, four);
        assert_eq!(reference, eight);
        assert_eq!(reference, dispatched);
    }
}
