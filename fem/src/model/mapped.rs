//! Internal forces of a mapped structured mesh (paper Section 4): every element has vertical sides
//! and the same width h, only the y coordinates of its corners differ. Then x = x_a + (h/2)(1 + ξ),
//! the Jacobian is lower-triangular and B follows from four numbers per element, so f_int is
//! computed on the fly (about 170 flops per element) instead of streaming a 512-byte K_e per
//! element per step, which made the per-element path memory-bound (docs/fem-model.md §1, same 2×2 Gauss
//! rule and the same discrete operator as K_e u_e, checked to round-off by a test).
//!
//! The elements of a row are computed in blocks of W consecutive elements, one lane each: W = 8,
//! one AVX-512 register a quantity, where the CPU has AVX-512F, else W = 4, one AVX2 register
//! (with FMA), or the portable build (the AVX-512 and AVX2 builds written in intrinsics, `avx512`
//! and `avx2`, from one macro, `intrinsics`). The width is chosen once, when the stiffness is
//! built, and the shapes are stored in blocks of that width, so that either reads them
//! contiguously. Every lane takes the same IEEE operations in the same order, each fused
//! multiply-add rounded once whether an instruction or the library computes it
//! (`f64::mul_add`), so the bits do not depend on the lane, the width or the CPU. The one-pass
//! sweep of unsampled steps (`solver::sweep`) computes each element row once ([`row_forces`]) and
//! sums it into its two layers ([`layer_from_rows`]) in the order of the separate force pass
//! ([`internal_forces`]), so both give the same bits (docs/performance.md, "Mapped meshes").

#[cfg(target_arch = "x86_64")]
#[macro_use]
mod intrinsics;
#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;

use crate::mesh::structured::Grid;
use nalgebra::Vector2;
use rayon::prelude::*;

/// Shape of one vertical-sided element: left and right heights y_d − y_a, y_c − y_b and bottom
/// and top rises y_b − y_a, y_c − y_d [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Trapezoid {
    pub v_left: f64,
    pub v_right: f64,
    pub rise_bottom: f64,
    pub rise_top: f64,
}

impl Trapezoid {
    /// The shape of the element with these corners, if its sides are vertical and its width is
    /// `width` [m] (to 1e-9 relative), else `None`.
    pub fn of(c: &[Vector2<f64>; 4], width: f64) -> Option<Trapezoid> {
        let tol = 1e-9 * width;
        let vertical = (c[3].x - c[0].x).abs() <= tol && (c[2].x - c[1].x).abs() <= tol;
        let wide = ((c[1].x - c[0].x) - width).abs() <= tol && ((c[2].x - c[3].x) - width).abs() <= tol;
        (vertical && wide).then(|| Trapezoid {
            v_left: c[3].y - c[0].y,
            v_right: c[2].y - c[1].y,
            rise_bottom: c[1].y - c[0].y,
            rise_top: c[2].y - c[3].y,
        })
    }
}

/// The widest block: eight f64, one AVX-512 register. Element-row buffers ([`row_len`]) are
/// padded to whole blocks of this width, so they suit either width.
const MAX_LANES: usize = 8;

/// Elements of a row whose forces are computed from one stack copy of their displacements, a
/// whole number of blocks of either width.
const SEGMENT: usize = 128;

/// How many elements a block holds, and so which registers compute it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Width {
    /// Four lanes: AVX2, or the portable build.
    Four,
    /// Eight lanes: AVX-512F.
    Eight,
}

impl Width {
    /// The widest this CPU computes in one register: eight with AVX-512F, else four.
    fn of_cpu() -> Width {
        if Width::Eight.runs_here() {
            Width::Eight
        } else {
            Width::Four
        }
    }

    /// Whether the CPU has the instructions of this width's build: AVX-512F for eight lanes,
    /// AVX2 and FMA for four.
    fn runs_here(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        return match self {
            Width::Eight => std::arch::is_x86_feature_detected!("avx512f"),
            Width::Four => {
                std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
            }
        };
        #[cfg(not(target_arch = "x86_64"))]
        false
    }
}

/// The shapes of every element, row by row, each row in blocks of one width (the last block
/// padded with copies of the row's last element).
#[derive(Debug, Clone)]
enum Blocks {
    Four(Vec<Shapes<4>>),
    Eight(Vec<Shapes<8>>),
}

/// Mapped-mesh stiffness: element width h [m], the elasticity matrix D [Pa] and the shape of
/// every element, by blocks of consecutive elements of a row.
#[derive(Debug, Clone)]
pub(crate) struct MappedStiffness {
    /// x_ξ = h/2 [m].
    pub half_width: f64,
    /// 1/x_ξ [1/m].
    inv_half_width: f64,
    /// Plane-strain D [Pa], its entries that are not zero.
    elasticity: Elasticity,
    /// Elements per row.
    nx: usize,
    /// Gauss constants, by blocks.
    blocks: Blocks,
    /// Whether the CPU runs the instructions of the blocks' width: AVX2 and FMA for four lanes,
    /// AVX-512F for eight (checked once, at build); else the portable build runs them.
    simd: bool,
}

/// Per-element constants of the 2×2 Gauss rule: y_η at ξ = ∓g, 1/y_η there, and y_ξ at η = ∓g
/// (g = 1/√3), with x_ξ = h/2 shared by every element [m, 1/m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GaussShape {
    y_eta: [f64; 2],
    inv_y_eta: [f64; 2],
    y_xi: [f64; 2],
}

/// The [`GaussShape`]s of `W` elements, one lane each [m, 1/m].
#[derive(Debug, Clone, Copy, PartialEq)]
struct Shapes<const W: usize> {
    y_eta: [[f64; W]; 2],
    inv_y_eta: [[f64; W]; 2],
    y_xi: [[f64; W]; 2],
}

impl<const W: usize> Shapes<W> {
    /// The blocks of a grid of `nx` elements per row, `shapes` in element order.
    fn blocks(nx: usize, shapes: &[Trapezoid]) -> Vec<Shapes<W>> {
        let per_row = nx.div_ceil(W);
        let zero = [[0.0; W]; 2];
        let mut blocks = vec![
            Shapes {
                y_eta: zero,
                inv_y_eta: zero,
                y_xi: zero
            };
            per_row * shapes.len() / nx.max(1)
        ];
        for (row, (row_shapes, row_blocks)) in shapes.chunks(nx).zip(blocks.chunks_mut(per_row)).enumerate() {
            debug_assert_eq!(row_shapes.len(), nx, "row {row}");
            for (b, block) in row_blocks.iter_mut().enumerate() {
                for q in 0..W {
                    let s = GaussShape::of(&row_shapes[(b * W + q).min(nx - 1)]);
                    for k in 0..2 {
                        block.y_eta[k][q] = s.y_eta[k];
                        block.inv_y_eta[k][q] = s.inv_y_eta[k];
                        block.y_xi[k][q] = s.y_xi[k];
                    }
                }
            }
        }
        blocks
    }
}

impl GaussShape {
    /// The constants of a trapezoid.
    pub fn of(s: &Trapezoid) -> GaussShape {
        let g = 1.0 / 3f64.sqrt();
        let y_eta = [-g, g].map(|xi| 0.25 * (s.v_left * (1.0 - xi) + s.v_right * (1.0 + xi)));
        GaussShape {
            y_eta,
            inv_y_eta: y_eta.map(|v| 1.0 / v),
            y_xi: [-g, g].map(|eta| 0.25 * (s.rise_bottom * (1.0 - eta) + s.rise_top * (1.0 + eta))),
        }
    }
}

impl MappedStiffness {
    /// The stiffness of a mapped grid of `nx` elements per row, `shapes` in element order (row
    /// by row), width 2 `half_width` [m], elasticity `d` [Pa], in blocks of the widest width
    /// this CPU computes in one register; `None` if D couples shear and normal strains (an
    /// anisotropic material), which this kernel does not compute.
    pub(crate) fn new(
        half_width: f64,
        d: [[f64; 3]; 3],
        nx: usize,
        shapes: &[Trapezoid],
    ) -> Option<MappedStiffness> {
        Self::with_width(half_width, d, nx, shapes, Width::of_cpu())
    }

    /// [`MappedStiffness::new`] in blocks of `width` (eight lanes run the portable build on a
    /// CPU without AVX-512F).
    pub(crate) fn with_width(
        half_width: f64,
        d: [[f64; 3]; 3],
        nx: usize,
        shapes: &[Trapezoid],
        width: Width,
    ) -> Option<MappedStiffness> {
        let elasticity = Elasticity::of(&d)?;
        let blocks = match width {
            Width::Four => Blocks::Four(Shapes::blocks(nx, shapes)),
            Width::Eight => Blocks::Eight(Shapes::blocks(nx, shapes)),
        };
        Some(MappedStiffness {
            half_width,
            inv_half_width: 1.0 / half_width,
            elasticity,
            nx,
            blocks,
            simd: width.runs_here(),
        })
    }
}

/// `W` numbers operated on together, lane by lane; every operation is one IEEE operation per
/// lane, so the compiler may pack them in one register without changing a bit.
#[derive(Clone, Copy)]
struct Lanes<const W: usize>([f64; W]);

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const W: usize> std::ops::$tr for Lanes<W> {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $f(self, o: Lanes<W>) -> Lanes<W> {
                let mut r = self.0;
                for q in 0..W {
                    r[q] = self.0[q] $op o.0[q];
                }
                Lanes(r)
            }
        }
        impl<const W: usize> std::ops::$tr<Lanes<W>> for f64 {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $f(self, o: Lanes<W>) -> Lanes<W> {
                Lanes([self; W]) $op o
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);

impl<const W: usize> Lanes<W> {
    /// self·b + c, lane by lane, rounded once (fused multiply-add: the same bits on every CPU,
    /// whether an instruction or the library computes it).
    #[inline(always)]
    fn mul_add(self, b: Lanes<W>, c: Lanes<W>) -> Lanes<W> {
        Lanes(std::array::from_fn(|q| self.0[q].mul_add(b.0[q], c.0[q])))
    }

    /// c − self·b, lane by lane, rounded once.
    #[inline(always)]
    fn neg_mul_add(self, b: Lanes<W>, c: Lanes<W>) -> Lanes<W> {
        Lanes(std::array::from_fn(|q| (-self.0[q]).mul_add(b.0[q], c.0[q])))
    }
}

impl<const W: usize> std::ops::Neg for Lanes<W> {
    type Output = Lanes<W>;
    #[inline(always)]
    fn neg(self) -> Lanes<W> {
        Lanes(self.0.map(|v| -v))
    }
}

/// The entries of an isotropic plane-strain D that are not zero: D₀₀, D₀₁, D₁₀, D₁₁, D₂₂ [Pa].
#[derive(Debug, Clone, Copy)]
struct Elasticity {
    d00: f64,
    d01: f64,
    d10: f64,
    d11: f64,
    d22: f64,
}

impl Elasticity {
    /// The non-zero entries of `d`, if σ_xy and the normal stresses are uncoupled (D₀₂ = D₁₂ =
    /// D₂₀ = D₂₁ = 0, as for every isotropic material).
    fn of(d: &[[f64; 3]; 3]) -> Option<Elasticity> {
        (d[0][2] == 0.0 && d[1][2] == 0.0 && d[2][0] == 0.0 && d[2][1] == 0.0).then_some(Elasticity {
            d00: d[0][0],
            d01: d[0][1],
            d10: d[1][0],
            d11: d[1][1],
            d22: d[2][2],
        })
    }
}

/// f_e = K_e u_e of `W` vertical-sided elements [N/m], 2×2 Gauss, as `[corner][component]`
/// per lane, from their corner displacements `ue[corner][component]` [m]. With the edge
/// differences U_ξ(η) = ¼[(1−η)(u₁−u₀) + (1+η)(u₂−u₃)] and U_η(ξ) = ¼[(1−ξ)(u₃−u₀) + (1+ξ)(u₂−u₁)]:
/// ∂u/∂y = U_η / y_η (a function of ξ alone), ∂u/∂x = (U_ξ − y_ξ ∂u/∂y)/x_ξ, σ = D ε, and Bᵀσ
/// det J (det J = x_ξ y_η) is N_a,ξ P + N_a,η Q with P = y_η (σ_xx, σ_xy), Q = x_ξ (σ_xy, σ_yy) −
/// y_ξ (σ_xx, σ_xy); the sums over Gauss points are gathered per edge before the scatter. A
/// product added to a sum is one fused multiply-add (one rounding), so the kernel takes about 120
/// operations an element where separate products and sums took about 170 (docs/performance.md,
/// "The mapped kernel with fused multiply-adds").
#[inline(always)]
fn block_forces<const W: usize>(
    s: &Shapes<W>,
    x_xi: f64,
    inv_x_xi: f64,
    d: &Elasticity,
    ue: &[V<W>; 4],
) -> [V<W>; 4] {
    let g = 1.0 / 3f64.sqrt();
    let (w0, w1) = (0.25 * (1.0 + g), 0.25 * (1.0 - g)); // ¼(1 ∓ (∓g)): weight of the near / far edge
    let (db, dt) = (ue[1] - ue[0], ue[2] - ue[3]);
    let (dl, dr) = (ue[3] - ue[0], ue[2] - ue[1]);
    // w·a + w'·b: w'·b rounded, w·a added to it fused
    let weigh = |w: f64, a: V<W>, w2: f64, b: V<W>| a.mul_add(Lanes([w; W]), w2 * b);
    // index 0: η (or ξ) = −g, index 1: +g
    let u_xi = [weigh(w0, db, w1, dt), weigh(w1, db, w0, dt)];
    let u_eta = [weigh(w0, dl, w1, dr), weigh(w1, dl, w0, dr)];
    let du_dy = [u_eta[0] * Lanes(s.inv_y_eta[0]), u_eta[1] * Lanes(s.inv_y_eta[1])];
    let zero = Lanes([0.0; W]);
    let mut p_sum = [V { x: zero, y: zero }; 2];
    let mut q_sum = [V { x: zero, y: zero }; 2];
    for je in 0..2 {
        let y_xi = Lanes(s.y_xi[je]);
        for ix in 0..2 {
            let dy = du_dy[ix];
            let dx = dy.neg_mul_add(y_xi, u_xi[je]) * Lanes([inv_x_xi; W]);
            let (e0, e1, e2) = (dx.x, dy.y, dy.x + dx.y);
            let sxx = e0.mul_add(Lanes([d.d00; W]), d.d01 * e1);
            let syy = e0.mul_add(Lanes([d.d10; W]), d.d11 * e1);
            let sxy = d.d22 * e2;
            let y_eta = Lanes(s.y_eta[ix]);
            p_sum[je] = V { x: sxx, y: sxy }.mul_add(y_eta, p_sum[je]);
            // (Q + x_ξ (σ_xy, σ_yy)) − y_ξ (σ_xx, σ_xy), each product fused
            let q = V { x: sxy, y: syy }.mul_add(Lanes([x_xi; W]), q_sum[ix]);
            q_sum[ix] = V { x: sxx, y: sxy }.neg_mul_add(y_xi, q);
        }
    }
    // N_a,ξ = ¼ ξ_a (1 + η η_a), N_a,η = ¼ η_a (1 + ξ ξ_a)
    let pb = weigh(w0, p_sum[0], w1, p_sum[1]);
    let pt = weigh(w1, p_sum[0], w0, p_sum[1]);
    let ql = weigh(w0, q_sum[0], w1, q_sum[1]);
    let qr = weigh(w1, q_sum[0], w0, q_sum[1]);
    [-pb - ql, pb - qr, pt + qr, -pt + ql]
}

/// A vector quantity of `W` elements: x and y components.
#[derive(Clone, Copy)]
struct V<const W: usize> {
    x: Lanes<W>,
    y: Lanes<W>,
}

impl<const W: usize> std::ops::Add for V<W> {
    type Output = V<W>;
    #[inline(always)]
    fn add(self, o: V<W>) -> V<W> {
        V {
            x: self.x + o.x,
            y: self.y + o.y,
        }
    }
}

impl<const W: usize> std::ops::Sub for V<W> {
    type Output = V<W>;
    #[inline(always)]
    fn sub(self, o: V<W>) -> V<W> {
        V {
            x: self.x - o.x,
            y: self.y - o.y,
        }
    }
}

impl<const W: usize> std::ops::Neg for V<W> {
    type Output = V<W>;
    #[inline(always)]
    fn neg(self) -> V<W> {
        V {
            x: -self.x,
            y: -self.y,
        }
    }
}

impl<const W: usize> std::ops::Mul<Lanes<W>> for V<W> {
    type Output = V<W>;
    #[inline(always)]
    fn mul(self, a: Lanes<W>) -> V<W> {
        V {
            x: self.x * a,
            y: self.y * a,
        }
    }
}

impl<const W: usize> std::ops::Mul<V<W>> for f64 {
    type Output = V<W>;
    #[inline(always)]
    fn mul(self, v: V<W>) -> V<W> {
        V {
            x: self * v.x,
            y: self * v.y,
        }
    }
}

impl<const W: usize> V<W> {
    /// self·a + c, each component fused ([`Lanes::mul_add`]).
    #[inline(always)]
    fn mul_add(self, a: Lanes<W>, c: V<W>) -> V<W> {
        V {
            x: self.x.mul_add(a, c.x),
            y: self.y.mul_add(a, c.y),
        }
    }

    /// c − self·a, each component fused ([`Lanes::neg_mul_add`]).
    #[inline(always)]
    fn neg_mul_add(self, a: Lanes<W>, c: V<W>) -> V<W> {
        V {
            x: self.x.neg_mul_add(a, c.x),
            y: self.y.neg_mul_add(a, c.y),
        }
    }
}

/// Length of a buffer of one element row's forces ([`row_forces`]) for `nx` elements per row:
/// 8 arrays (corner a, component c) of the row's elements, padded to whole blocks of either width.
pub(crate) fn row_len(nx: usize) -> usize {
    8 * nx.div_ceil(MAX_LANES) * MAX_LANES
}

/// Element forces of one element row into `out` ([`row_len`] numbers: corner a, component c of
/// element e at `(2a + c)·E + e`, E = `out.len()` / 8) [N/m], from the displacement rows of its
/// lower and upper layers (x, y pairs) [m].
pub(crate) fn row_forces(k: &MappedStiffness, row: usize, lower: &[f64], upper: &[f64], out: &mut [f64]) {
    for first in (0..k.nx).step_by(SEGMENT) {
        let segment = Segment {
            row,
            first,
            lower,
            upper,
            e0: 0,
        };
        segment_forces(k, &segment, out);
    }
}

/// A segment of [`row_forces`]: elements `first..` of element row `row` (at most [`SEGMENT`] of
/// them, and at most the row's; `first` a multiple of [`MAX_LANES`]), from the displacement rows
/// of its lower and upper layers (x, y pairs) [m], into a buffer whose first element is element
/// `e0` of the row ([`row_forces`] layout, E = its length / 8).
struct Segment<'a> {
    row: usize,
    first: usize,
    lower: &'a [f64],
    upper: &'a [f64],
    e0: usize,
}

impl Segment<'_> {
    /// The blocks of this segment's elements, out of `blocks` (every block of a grid of `nx`
    /// elements a row, in blocks of `W`).
    #[inline(always)]
    fn blocks<'b, const W: usize>(&self, nx: usize, blocks: &'b [Shapes<W>]) -> &'b [Shapes<W>] {
        let per_row = nx.div_ceil(W);
        let blocks = &blocks[self.first_block::<W>(nx)..(self.row + 1) * per_row];
        &blocks[..blocks.len().min(SEGMENT / W)]
    }

    /// The index of this segment's first block among every block of a grid of `nx` elements a
    /// row, in blocks of `W`.
    #[inline(always)]
    fn first_block<const W: usize>(&self, nx: usize) -> usize {
        debug_assert!(self.first.is_multiple_of(W) && SEGMENT.is_multiple_of(MAX_LANES));
        self.row * nx.div_ceil(W) + self.first / W
    }
}

/// The forces of a [`Segment`] into `out`, by the stiffness's blocks on the widest registers the
/// CPU has for them.
fn segment_forces(k: &MappedStiffness, segment: &Segment<'_>, out: &mut [f64]) {
    match &k.blocks {
        Blocks::Eight(blocks) => {
            #[cfg(target_arch = "x86_64")]
            if k.simd {
                // SAFETY: `simd` is true for eight lanes only if the CPU reported AVX-512F at run
                // time (`MappedStiffness::with_width`).
                return unsafe { avx512::segment(k, blocks, segment, out) };
            }
            segment_portable(k, blocks, segment, out)
        }
        Blocks::Four(blocks) => {
            #[cfg(target_arch = "x86_64")]
            if k.simd {
                // SAFETY: `simd` is true for four lanes only if the CPU reported AVX2 and FMA at
                // run time (`MappedStiffness::with_width`).
                return unsafe { avx2::segment(k, blocks, segment, out) };
            }
            segment_portable(k, blocks, segment, out)
        }
    }
}

/// Nodes 0..W and nodes 1..=W of a block, from the `W + 1` nodes of a displacement row (x, y
/// pairs, at least 2(W + 1) values) [m], as lanes of x and of y.
#[inline(always)]
fn block_corners<const W: usize>(r: &[f64]) -> (V<W>, V<W>) {
    let node = |shift: usize| V {
        x: Lanes(std::array::from_fn(|q| r[2 * (q + shift)])),
        y: Lanes(std::array::from_fn(|q| r[2 * (q + shift) + 1])),
    };
    (node(0), node(1))
}

/// [`segment_forces`] on blocks of `W` elements (`blocks`: every block of the stiffness), in
/// any build.
#[inline(always)]
fn segment_portable<const W: usize>(
    k: &MappedStiffness,
    blocks: &[Shapes<W>],
    segment: &Segment<'_>,
    out: &mut [f64],
) {
    let (nx, stride) = (k.nx, out.len() / 8);
    let blocks = segment.blocks(nx, blocks);
    // the last block's nodes, padded ([`block_nodes`])
    let mut pads = [[0.0; 2 * (MAX_LANES + 1)]; 2];
    for (b, shape) in (segment.first / W..).zip(blocks) {
        let [pad_l, pad_h] = &mut pads;
        let (l, h) = (
            block_nodes::<W>(segment.lower, b, nx, pad_l),
            block_nodes::<W>(segment.upper, b, nx, pad_h),
        );
        let ((l0, l1), (h0, h1)) = (block_corners::<W>(l), block_corners::<W>(h));
        let ue = [l0, l1, h1, h0];
        let fe = block_forces(shape, k.half_width, k.inv_half_width, &k.elasticity, &ue);
        let e = b * W - segment.e0;
        for (a, corner) in fe.iter().enumerate() {
            out[2 * a * stride + e..2 * a * stride + e + W].copy_from_slice(&corner.x.0);
            out[(2 * a + 1) * stride + e..(2 * a + 1) * stride + e + W].copy_from_slice(&corner.y.0);
        }
    }
}

/// The `W + 1` nodes of block `b` of a displacement row `r` (x, y pairs) [m], read in place;
/// past the row's last node (node `nx`, in its last block) the last node again, copied into
/// `pad`: those lanes' forces are never read. (Copied into an array for every block, by a
/// function the AVX2 build did not inline, the nodes went through the stack and back.)
#[inline(always)]
fn block_nodes<'a, const W: usize>(
    r: &'a [f64],
    b: usize,
    nx: usize,
    pad: &'a mut [f64; 2 * (MAX_LANES + 1)],
) -> &'a [f64] {
    let (n0, len) = (2 * b * W, 2 * (W + 1));
    match r.get(n0..n0 + len) {
        Some(r) => r,
        None => {
            for (i, v) in pad[..len].iter_mut().enumerate() {
                *v = r[2 * (b * W + i / 2).min(nx) + i % 2];
            }
            &pad[..len]
        }
    }
}

/// Force of corner `a`, component `c`, of element `e` in a [`row_forces`] buffer [N/m].
#[inline(always)]
fn at(r: &[f64], e: usize, a: usize, c: usize) -> f64 {
    r[(2 * a + c) * (r.len() / 8) + e]
}

/// −f_int of the nodes of one layer into `out` (x, y pairs) [N/m] from the element forces of the
/// row below it (`below`, its corners 2 and 3 act on this layer) and of the row above (`above`,
/// corners 0 and 1), [`row_forces`] layout. The terms are subtracted in the order
/// [`internal_forces`] subtracts them: the row whose lower layer is even first, and within a row
/// element i − 1 before element i, so the sum is the same to the bit.
pub(crate) fn layer_from_rows(layer: usize, below: Option<&[f64]>, above: Option<&[f64]>, out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU reported AVX-512F at run time.
        return unsafe { layer_from_rows_avx512(layer, below, above, out) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU reported AVX2 at run time.
        return unsafe { layer_from_rows_avx2(layer, below, above, out) };
    }
    layer_sum(layer, below, above, out)
}

/// [`layer_from_rows`] compiled for AVX-512F: the same operations, on wider registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn layer_from_rows_avx512(layer: usize, below: Option<&[f64]>, above: Option<&[f64]>, out: &mut [f64]) {
    layer_sum(layer, below, above, out)
}

/// [`layer_from_rows`] compiled for AVX2: the same operations, on wider registers.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn layer_from_rows_avx2(layer: usize, below: Option<&[f64]>, above: Option<&[f64]>, out: &mut [f64]) {
    layer_sum(layer, below, above, out)
}

/// The corner forces of one element row that act on a layer, each a slice over the row's
/// elements e [N/m]: x and y of e's corner at its right end (the one node e + 1 takes from its
/// element i − 1), then x and y of e's corner at its left end (the one node e takes from its
/// element i).
type RowCorners<'a> = [&'a [f64]; 4];

/// The sum of [`layer_from_rows`], in any build: each node's terms from +0, one row's after the
/// other in the order given, in one pass over the layer.
#[inline(always)]
fn layer_sum(layer: usize, below: Option<&[f64]>, above: Option<&[f64]>, out: &mut [f64]) {
    let nx = out.len() / 2 - 1;
    // a row, the corner it takes from element i − 1 and the one from element i
    fn corners(r: &[f64], left: usize, right: usize, nx: usize) -> RowCorners<'_> {
        let stride = r.len() / 8;
        let part = |a: usize, c: usize| &r[(2 * a + c) * stride..(2 * a + c) * stride + nx];
        [part(left, 0), part(left, 1), part(right, 0), part(right, 1)]
    }
    let below = below.map(|r| corners(r, 2, 3, nx));
    let above = above.map(|r| corners(r, 1, 0, nx));
    // the row above has this layer as its lower layer; the row below, the layer under it
    let order = if layer.is_multiple_of(2) {
        (above, below)
    } else {
        (below, above)
    };
    match order {
        (Some(first), Some(second)) => rows_into_layer([first, second], out),
        (Some(one), None) | (None, Some(one)) => rows_into_layer([one], out),
        (None, None) => out.fill(0.0),
    }
}

/// Node i of the layer: +0, minus each row's corner from element i − 1 then its corner from
/// element i, row after row (the end nodes have one element a row).
#[inline(always)]
fn rows_into_layer<const N: usize>(rows: [RowCorners<'_>; N], out: &mut [f64]) {
    let nx = out.len() / 2 - 1;
    let (mut first, mut last) = ([0.0; 2], [0.0; 2]);
    for [lx, ly, rx, ry] in rows {
        first = [first[0] - rx[0], first[1] - ry[0]];
        last = [last[0] - lx[nx - 1], last[1] - ly[nx - 1]];
    }
    out[..2].copy_from_slice(&first);
    out[2 * nx..].copy_from_slice(&last);
    for (i, o) in out[2..2 * nx].chunks_exact_mut(2).enumerate() {
        let mut sum = [0.0; 2];
        for [lx, ly, rx, ry] in rows {
            sum = [sum[0] - lx[i] - rx[i + 1], sum[1] - ly[i] - ry[i + 1]];
        }
        o.copy_from_slice(&sum);
    }
}

/// The displacement rows (x, y pairs) [m] of element row `r`'s lower and upper node layers, out
/// of every node's displacements `flat`.
pub(crate) fn row_layers<'a>(grid: &Grid, flat: &'a [f64], r: usize) -> (&'a [f64], &'a [f64]) {
    let (w, layer) = (grid.nx + 1, grid.upper_layer[r]);
    (
        &flat[2 * layer * w..2 * (layer + 1) * w],
        &flat[2 * (layer + 1) * w..2 * (layer + 2) * w],
    )
}

/// f = −f_int(u) (overwrites `f`). Element rows are processed in two passes, those whose lower
/// node layer is even, then odd: within a pass the rows write disjoint layer pairs, so the
/// parallel scatter has no race and needs no atomics. Each row's element forces go through
/// [`row_forces`]'s segments and are scattered in element order.
pub(crate) fn internal_forces(grid: &Grid, k: &MappedStiffness, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
    let nx = grid.nx;
    let w = nx + 1;
    let flat: &[f64] = bytemuck::cast_slice(u);
    f.par_iter_mut().for_each(|v| *v = Vector2::zeros());
    for parity in [0usize, 1] {
        let (_, tail) = f.split_at_mut(parity * w);
        tail.par_chunks_mut(2 * w).enumerate().for_each(|(k2, pair)| {
            let lower = parity + 2 * k2;
            if pair.len() < 2 * w {
                return;
            }
            let Some(r) = grid.layer_element_rows(lower).1 else {
                return;
            };
            let (lo, hi) = pair.split_at_mut(w);
            let (ul, uh) = row_layers(grid, flat, r);
            let mut segment = [0.0; 8 * SEGMENT];
            for first in (0..nx).step_by(SEGMENT) {
                // a segment at a time: a row's forces would need a buffer per task
                let part = Segment {
                    row: r,
                    first,
                    lower: ul,
                    upper: uh,
                    e0: first,
                };
                segment_forces(k, &part, &mut segment);
                for c in first..(first + SEGMENT).min(nx) {
                    let e = c - first;
                    let fe = |a: usize| Vector2::new(at(&segment, e, a, 0), at(&segment, e, a, 1));
                    lo[c] -= fe(0);
                    lo[c + 1] -= fe(1);
                    hi[c + 1] -= fe(2);
                    hi[c] -= fe(3);
                }
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::bulk;

    /// f_e of one element through [`row_forces`] (a row of one element).
    fn forces_of(
        corners: &[Vector2<f64>; 4],
        h: f64,
        d: &[[f64; 3]; 3],
        ue: &[Vector2<f64>; 4],
    ) -> [Vector2<f64>; 4] {
        let k = MappedStiffness::new(
            0.5 * h,
            *d,
            1,
            &[Trapezoid::of(corners, h).expect("vertical sides")],
        )
        .unwrap();
        let lower = [ue[0].x, ue[0].y, ue[1].x, ue[1].y];
        let upper = [ue[3].x, ue[3].y, ue[2].x, ue[2].y];
        let mut out = vec![0.0; row_len(1)];
        row_forces(&k, 0, &lower, &upper, &mut out);
        [0, 1, 2, 3].map(|a| Vector2::new(at(&out, 0, a, 0), at(&out, 0, a, 1)))
    }

    #[test]
    fn matches_k_e_times_u_on_distorted_elements() {
        let d = crate::law::elastic::PlaneStrain::new(7e6, 0.35, 1230.0).d_matrix();
        let h = 1e-3;
        // a square, a sheared parallelogram (slope π/2, the sinusoid's steepest) and a trapezoid
        let shapes = [
            [(0.0, 0.0), (h, 0.0), (h, h), (0.0, h)],
            [(0.0, 0.0), (h, 1.571 * h), (h, 2.571 * h), (0.0, h)],
            [(0.0, 0.1 * h), (h, -0.4 * h), (h, 0.35 * h), (0.0, 0.8 * h)],
        ];
        let ue = [(1.0, -2.0), (0.5, 0.25), (-1.5, 3.0), (2.0, 0.75)].map(|(x, y)| Vector2::new(x, y) * 1e-4);
        for corners in shapes {
            let c = corners.map(|(x, y)| Vector2::new(x + 0.3, y - 0.2));
            let ke = bulk::stiffness(&c, &d).unwrap();
            let f = forces_of(&c, h, &d, &ue);
            let scale: f64 = (0..8).map(|i| ke[i][i]).fold(0.0, f64::max) * 1e-4;
            for a in 0..4 {
                for comp in 0..2 {
                    let expect: f64 = (0..4)
                        .map(|b| ke[2 * a + comp][2 * b] * ue[b].x + ke[2 * a + comp][2 * b + 1] * ue[b].y)
                        .sum();
                    let got = if comp == 0 { f[a].x } else { f[a].y };
                    assert!((got - expect).abs() <= 1e-12 * scale, "{got} vs {expect}");
                }
            }
        }
        assert!(
            Trapezoid::of(
                &[(0.0, 0.0), (h, 0.0), (1.2 * h, h), (0.0, h)].map(|(x, y)| Vector2::new(x, y)),
                h
            )
            .is_none()
        );
    }

    /// Every build of the layer sum gives the bits of the portable one and of the terms
    /// subtracted one at a time from +0 in the order the separate force pass subtracts them, on
    /// a layer of 21 nodes (whole blocks of both widths and a tail), with a row below, a row above
    /// or both, for an even and an odd layer.
    #[test]
    fn every_build_of_the_layer_sum_gives_the_bits_of_the_terms_in_order() {
        let nx = 20;
        let row = |seed: f64| -> Vec<f64> {
            (0..row_len(nx))
                .map(|i| ((i as f64 + seed) * 0.731).sin() * 10f64.powi(i as i32 % 7 - 3))
                .collect()
        };
        let (below, above) = (row(0.5), row(7.25));
        type Build = fn(usize, Option<&[f64]>, Option<&[f64]>, &mut [f64]);
        let mut builds: Vec<(&str, Build)> = vec![("dispatched", layer_from_rows), ("portable", layer_sum)];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY (of the call below): the CPU reported AVX2.
                builds.push(("avx2", |l, b, a, o| unsafe { layer_from_rows_avx2(l, b, a, o) }));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY (of the call below): the CPU reported AVX-512F.
                builds.push(("avx512", |l, b, a, o| unsafe {
                    layer_from_rows_avx512(l, b, a, o)
                }));
            }
        }
        for layer in [4, 5] {
            for (b, a) in [(true, true), (true, false), (false, true)] {
                let (b, a) = (b.then_some(&below[..]), a.then_some(&above[..]));
                // node i takes corner 2 of element i − 1 and corner 3 of element i in the row
                // below, corners 1 and 0 in the row above; the row whose lower layer is even first
                let mut want = vec![0.0; 2 * (nx + 1)];
                let terms = [(b, 2, 3), (a, 1, 0)];
                let order = if layer % 2 == 0 {
                    [terms[1], terms[0]]
                } else {
                    terms
                };
                for (r, left, right) in order {
                    let Some(r) = r else { continue };
                    for i in 0..=nx {
                        for c in 0..2 {
                            if i > 0 {
                                want[2 * i + c] -= at(r, i - 1, left, c);
                            }
                            if i < nx {
                                want[2 * i + c] -= at(r, i, right, c);
                            }
                        }
                    }
                }
                let want: Vec<u64> = want.iter().map(|x| x.to_bits()).collect();
                for (name, build) in &builds {
                    let mut out = vec![f64::NAN; 2 * (nx + 1)];
                    build(layer, b, a, &mut out);
                    let got: Vec<u64> = out.iter().map(|x| x.to_bits()).collect();
                    assert_eq!(
                        got,
                        want,
                        "{name}, layer {layer}, below {}, above {}",
                        b.is_some(),
                        a.is_some()
                    );
                }
            }
        }
    }

    /// A row of two segments, the second of 11 elements (a padded block of either width), each
    /// element of its own shape, in blocks of four and of eight: the build for the CPU's
    /// registers gives the bits of the portable one, a segment starting at element 8 the bits of
    /// the whole row, every element the bits it has alone in a row, whatever its lane and the
    /// width, and the padding changes nothing.
    #[test]
    fn every_lane_gives_the_bits_of_its_element_alone() {
        let d = crate::law::elastic::PlaneStrain::new(7e6, 0.35, 1230.0).d_matrix();
        let (h, nx) = (1e-3, SEGMENT + 11);
        let y = |i: usize, j: usize| j as f64 * h * (1.0 + 0.3 * (i as f64 * 0.9).sin());
        let corners = |e: usize| {
            let x = |i: usize| i as f64 * h;
            [(e, 0), (e + 1, 0), (e + 1, 1), (e, 1)]
                .map(|(i, j)| Vector2::new(x(i), y(i, j) + 0.1 * h * (i as f64).cos()))
        };
        let shapes: Vec<Trapezoid> = (0..nx).map(|e| Trapezoid::of(&corners(e), h).unwrap()).collect();
        let u = |i: usize, j: usize| {
            Vector2::new(
                (i as f64 * 0.37 + j as f64).sin(),
                (i as f64 * 0.11 - j as f64).cos(),
            ) * 1e-5
        };
        let row = |j: usize| -> Vec<f64> { (0..=nx).flat_map(|i| [u(i, j).x, u(i, j).y]).collect() };
        let (lower, upper) = (row(0), row(1));
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        // every element's forces alone, in a row of one
        let mut alone = vec![0u64; 0];
        for e in 0..nx {
            let ue = [u(e, 0), u(e + 1, 0), u(e + 1, 1), u(e, 1)];
            alone.extend(
                forces_of(&corners(e), h, &d, &ue)
                    .iter()
                    .flat_map(|f| [f.x.to_bits(), f.y.to_bits()]),
            );
        }
        let of_each = |v: &[f64]| -> Vec<u64> {
            (0..nx)
                .flat_map(|e| (0..4).flat_map(move |a| [at(v, e, a, 0).to_bits(), at(v, e, a, 1).to_bits()]))
                .collect()
        };
        for width in [Width::Four, Width::Eight] {
            let k = MappedStiffness::with_width(0.5 * h, d, nx, &shapes, width).unwrap();
            let of = |first: usize| Segment {
                row: 0,
                first,
                lower: &lower,
                upper: &upper,
                e0: 0,
            };
            let mut portable = vec![f64::NAN; row_len(nx)];
            for first in (0..nx).step_by(SEGMENT) {
                match &k.blocks {
                    Blocks::Four(b) => segment_portable(&k, b, &of(first), &mut portable),
                    Blocks::Eight(b) => segment_portable(&k, b, &of(first), &mut portable),
                }
            }
            let mut dispatched = vec![f64::NAN; row_len(nx)];
            row_forces(&k, 0, &lower, &upper, &mut dispatched);
            assert!(
                bits(&portable) == bits(&dispatched),
                "{width:?}: the CPU's build against portable"
            );
            // a segment from element 8 on
            let mut part = vec![f64::NAN; row_len(nx)];
            segment_forces(&k, &of(8), &mut part);
            let from_8 = |v: &[f64]| {
                let stride = v.len() / 8;
                (0..8)
                    .flat_map(|a| bits(&v[a * stride + 8..a * stride + (8 + SEGMENT).min(nx)]))
                    .collect::<Vec<_>>()
            };
            assert!(
                from_8(&portable) == from_8(&part),
                "{width:?}: a segment from element 8 against a row"
            );
            let mismatch = (0..alone.len()).find(|&i| of_each(&portable)[i] != alone[i]);
            assert_eq!(
                mismatch.map(|i| i / 8),
                None,
                "{width:?}: the first element unlike its forces alone"
            );
        }
    }
}
