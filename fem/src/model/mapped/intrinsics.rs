//! The mapped kernel once for every instruction set written in intrinsics: `kernel_in!` writes,
//! into the module that calls it, the segment loop and [`block_forces`](super::block_forces) on
//! one register type, from that set's intrinsics. The calling module gives the two operations
//! that differ between sets: `nodes` (a block's nodes split into x and y lanes) and `neg` (the
//! sign bit flipped). Every operation is the portable build's, on the same operands and in the
//! same order, so the bits are its bits (test `every_lane_gives_the_bits_of_its_element_alone`).

/// The kernel on `$w` lanes of `$reg` under target feature `$feature`, from the intrinsics
/// named; the shapes `$ahead` blocks ahead are asked of the cache.
macro_rules! kernel_in {
    (
        feature: $feature:literal,
        lanes: $w:literal,
        register: $reg:ty,
        ahead: $ahead:literal,
        set1: $set1:ident,
        zero: $zero:ident,
        load: $load:ident,
        store: $store:ident,
        add: $add:ident,
        sub: $sub:ident,
        mul: $mul:ident,
        fmadd: $fmadd:ident,
        fnmadd: $fnmadd:ident $(,)?
    ) => {
        /// A vector quantity of one lane an element: x and y lanes.
        #[derive(Clone, Copy)]
        struct P {
            x: $reg,
            y: $reg,
        }

        /// The scalars of [`block_forces`](super::block_forces), each in every lane: the Gauss
        /// weights of the near and far edge w₀, w₁, x_ξ and 1/x_ξ [m, 1/m], the entries of D [Pa].
        struct Constants {
            w0: $reg,
            w1: $reg,
            x_xi: $reg,
            inv_x_xi: $reg,
            d00: $reg,
            d01: $reg,
            d10: $reg,
            d11: $reg,
            d22: $reg,
        }

        /// Blocks ahead whose shapes [`segment`] asks the cache for.
        const AHEAD: usize = $ahead;

        /// [`segment_forces`](super::segment_forces) on blocks of this width: for each block,
        /// its corners read from the two displacement rows, its forces, and its lanes stored in
        /// place.
        #[inline]
        #[target_feature(enable = $feature)]
        pub(super) fn segment(
            k: &super::MappedStiffness,
            blocks: &[super::Shapes<$w>],
            segment: &super::Segment<'_>,
            out: &mut [f64],
        ) {
            let (nx, stride) = (k.nx, out.len() / 8);
            // the shapes of the blocks ahead are asked of the cache, past this segment's end too
            let (every, ahead) = (blocks, segment.first_block::<$w>(nx) + AHEAD);
            let blocks = segment.blocks(nx, blocks);
            let g = 1.0 / 3f64.sqrt();
            let d = &k.elasticity;
            let c = Constants {
                w0: $set1(0.25 * (1.0 + g)),
                w1: $set1(0.25 * (1.0 - g)),
                x_xi: $set1(k.half_width),
                inv_x_xi: $set1(k.inv_half_width),
                d00: $set1(d.d00),
                d01: $set1(d.d01),
                d10: $set1(d.d10),
                d11: $set1(d.d11),
                d22: $set1(d.d22),
            };
            let mut pads = [[0.0; 2 * (super::MAX_LANES + 1)]; 2];
            for (j, (b, shape)) in (segment.first / $w..).zip(blocks).enumerate() {
                crate::hint::prefetch(every, ahead + j);
                let e = b * $w - segment.e0;
                // every store below writes lanes e..e + W of one of the eight arrays of `stride`
                // numbers
                assert!(
                    e + $w <= stride,
                    "block {b} past the buffer of {stride} elements"
                );
                let [pad_l, pad_h] = &mut pads;
                let (l0, l1) = nodes(super::block_nodes::<$w>(segment.lower, b, nx, pad_l));
                let (h0, h1) = nodes(super::block_nodes::<$w>(segment.upper, b, nx, pad_h));
                let fe = block_forces(shape, &c, [l0, l1, h1, h0]);
                let base = out.as_mut_ptr();
                for (a, corner) in fe.iter().enumerate() {
                    // SAFETY: (2a + 1)·stride + e + W ≤ 8·stride = len ≤ out.len(), by the
                    // assert above.
                    unsafe {
                        $store(base.add(2 * a * stride + e), corner.x);
                        $store(base.add((2 * a + 1) * stride + e), corner.y);
                    }
                }
            }
        }

        /// [`block_forces`](super::block_forces) on this width: the same operations on the same
        /// operands in the same order (a product's operands may swap: IEEE multiplication and
        /// addition are commutative, and so is the product of a fused multiply-add), the fused
        /// ones fused, the sums over Gauss points started from +0 as there.
        #[inline]
        #[target_feature(enable = $feature)]
        fn block_forces(s: &super::Shapes<$w>, c: &Constants, ue: [P; 4]) -> [P; 4] {
            // SAFETY: each array of `s` holds W f64; the loads are unaligned.
            let load = |v: &[f64; $w]| unsafe { $load(v.as_ptr()) };
            let (add, sub, mul) = ($add, $sub, $mul);
            // a·b + c and c − a·b, rounded once
            let (fmadd, fnmadd) = ($fmadd, $fnmadd);
            let diff = |a: P, b: P| P {
                x: sub(a.x, b.x),
                y: sub(a.y, b.y),
            };
            // w·a + w'·b, per component: w'·b rounded, w·a added to it fused
            let weigh = |w: $reg, a: P, w2: $reg, b: P| P {
                x: fmadd(a.x, w, mul(w2, b.x)),
                y: fmadd(a.y, w, mul(w2, b.y)),
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
                x: $zero(),
                y: $zero(),
            };
            let mut p_sum = [zero; 2];
            let mut q_sum = [zero; 2];
            for je in 0..2 {
                let y_xi = load(&s.y_xi[je]);
                for ix in 0..2 {
                    let dy = du_dy[ix];
                    let dx = P {
                        x: mul(fnmadd(dy.x, y_xi, u_xi[je].x), c.inv_x_xi),
                        y: mul(fnmadd(dy.y, y_xi, u_xi[je].y), c.inv_x_xi),
                    };
                    let (e0, e1, e2) = (dx.x, dy.y, add(dy.x, dx.y));
                    let sxx = fmadd(e0, c.d00, mul(c.d01, e1));
                    let syy = fmadd(e0, c.d10, mul(c.d11, e1));
                    let sxy = mul(c.d22, e2);
                    let y_eta = load(&s.y_eta[ix]);
                    p_sum[je] = P {
                        x: fmadd(sxx, y_eta, p_sum[je].x),
                        y: fmadd(sxy, y_eta, p_sum[je].y),
                    };
                    q_sum[ix] = P {
                        x: fnmadd(sxx, y_xi, fmadd(sxy, c.x_xi, q_sum[ix].x)),
                        y: fnmadd(sxy, y_xi, fmadd(syy, c.x_xi, q_sum[ix].y)),
                    };
                }
            }
            let pb = weigh(c.w0, p_sum[0], c.w1, p_sum[1]);
            let pt = weigh(c.w1, p_sum[0], c.w0, p_sum[1]);
            let ql = weigh(c.w0, q_sum[0], c.w1, q_sum[1]);
            let qr = weigh(c.w1, q_sum[0], c.w0, q_sum[1]);
            let minus = |a: P| P {
                x: neg(a.x),
                y: neg(a.y),
            };
            let plus = |a: P, b: P| P {
                x: add(a.x, b.x),
                y: add(a.y, b.y),
            };
            [
                diff(minus(pb), ql),
                diff(pb, qr),
                plus(pt, qr),
                plus(minus(pt), ql),
            ]
        }
    };
}
