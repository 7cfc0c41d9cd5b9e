//! The explicit update of one node, shared by the separate passes of the step and by its one-pass
//! sweep, so that both perform the same IEEE operations (docs/fem-model.md §9).

use nalgebra::Vector2;

/// The stability guard's running max of |v|² [m²/s²]: a non-finite |v|² counts as ∞. A new
/// maximum is rare once a few nodes are seen, so this is a well-predicted branch, not a chain of
/// dependent `max` instructions through every node of the step.
#[inline(always)]
pub(crate) fn track_vmax2(vmax2: &mut f64, v2: f64) {
    // true when v2 > vmax2 or v2 is NaN
    if v2.partial_cmp(vmax2) != Some(std::cmp::Ordering::Less) && v2 != *vmax2 {
        *vmax2 = if v2.is_finite() { v2 } else { f64::INFINITY };
    }
}

/// The predictor of one node, u += Δt v + ½Δt² a and v += ½Δt a: the same IEEE operations
/// wherever it runs.
#[inline(always)]
pub(crate) fn predict(u: &mut Vector2<f64>, v: &mut Vector2<f64>, a: &Vector2<f64>, dt: f64) {
    *u += dt * *v + 0.5 * dt * dt * *a;
    *v += 0.5 * dt * *a;
}

/// The corrector of one node, a = f/m and v += ½Δt a, then the next step's predictor with the
/// same a (the fused update of an unsampled step); |v_{n+1}|² goes to the stability guard.
#[inline(always)]
pub(crate) fn advance(
    u: &mut Vector2<f64>,
    v: &mut Vector2<f64>,
    f: Vector2<f64>,
    m: f64,
    dt: f64,
    vmax2: &mut f64,
) {
    let mut a = Vector2::zeros();
    correct(&mut a, v, f, m, dt, vmax2);
    predict(u, v, &a, dt);
}

/// The corrector of one node alone, a = f/m and v += ½Δt a, a stored (a sampled step, or a node
/// the fused update leaves); |v_{n+1}|² goes to the stability guard. The same IEEE operations as
/// the corrector within [`advance`].
#[inline(always)]
pub(crate) fn correct(
    a: &mut Vector2<f64>,
    v: &mut Vector2<f64>,
    f: Vector2<f64>,
    m: f64,
    dt: f64,
    vmax2: &mut f64,
) {
    *a = f / m;
    *v += 0.5 * dt * *a;
    track_vmax2(vmax2, v.norm_squared());
}

/// [`advance`] of consecutive nodes; their largest |v_{n+1}|² joins `vmax2` as [`track_vmax2`]
/// would take it. With AVX-512F four nodes go through one vector of eight lanes, with AVX2 two
/// through one of four, each lane through the IEEE operations of [`advance`]; the maximum is the
/// same whatever the order the nodes are seen in.
pub(crate) fn advance_all(nodes: Span<'_>, dt: f64, vmax2: &mut f64) {
    update_all::<true>(nodes, &mut [], dt, vmax2);
}

/// [`correct`] of consecutive nodes, their accelerations into `a` (`nodes.u` is left as it is);
/// the largest |v_{n+1}|² joins `vmax2`. Vectorised as [`advance_all`], each lane through the
/// IEEE operations of [`correct`].
pub(crate) fn correct_all(nodes: Span<'_>, a: &mut [Vector2<f64>], dt: f64, vmax2: &mut f64) {
    assert_eq!(a.len(), nodes.u.len());
    update_all::<false>(nodes, bytemuck::cast_slice_mut(a), dt, vmax2);
}

/// [`advance_all`] (`FUSED`) or [`correct_all`] (a into `a_out`, x, y pairs) on the widest
/// build the CPU runs.
fn update_all<const FUSED: bool>(nodes: Span<'_>, a_out: &mut [f64], dt: f64, vmax2: &mut f64) {
    let Span { u, v, f, m } = &nodes;
    assert!(v.len() == u.len() && m.len() == u.len() && f.len() == 2 * u.len());
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU reported AVX-512F at run time.
        return unsafe { update_avx512::<FUSED>(nodes, a_out, dt, vmax2) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU reported AVX2 at run time.
        return unsafe { update_avx2::<FUSED>(nodes, a_out, dt, vmax2) };
    }
    update_from::<FUSED>(nodes, a_out, dt, vmax2, 0);
}

/// [`advance_from`] (`FUSED`) or [`correct_from`]: node by node from node `k` on.
#[inline(always)]
fn update_from<const FUSED: bool>(nodes: Span<'_>, a_out: &mut [f64], dt: f64, vmax2: &mut f64, k: usize) {
    if FUSED {
        advance_from(nodes, dt, vmax2, k);
    } else {
        correct_from(nodes, a_out, dt, vmax2, k);
    }
}

/// The predictor of consecutive nodes ([`predict`] on each), on the widest vectors the CPU has:
/// every node through the same IEEE operations, so the same bits on any CPU.
pub(crate) fn predict_all(u: &mut [Vector2<f64>], v: &mut [Vector2<f64>], a: &[Vector2<f64>], dt: f64) {
    assert!(v.len() == u.len() && a.len() == u.len());
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx512f") {
        // SAFETY: the CPU reported AVX-512F at run time.
        return unsafe { predict_avx512(u, v, a, dt) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU reported AVX2 at run time.
        return unsafe { predict_avx2(u, v, a, dt) };
    }
    predict_each(u, v, a, dt);
}

/// [`predict`] node by node; the builds below let the compiler vectorise it (the operations per
/// component are independent, and it contracts nothing into fused multiply-adds).
#[inline(always)]
fn predict_each(u: &mut [Vector2<f64>], v: &mut [Vector2<f64>], a: &[Vector2<f64>], dt: f64) {
    for ((u, v), a) in u.iter_mut().zip(v.iter_mut()).zip(a) {
        predict(u, v, a, dt);
    }
}

/// [`predict_each`] compiled for AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn predict_avx512(u: &mut [Vector2<f64>], v: &mut [Vector2<f64>], a: &[Vector2<f64>], dt: f64) {
    predict_each(u, v, a, dt);
}

/// [`predict_each`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn predict_avx2(u: &mut [Vector2<f64>], v: &mut [Vector2<f64>], a: &[Vector2<f64>], dt: f64) {
    predict_each(u, v, a, dt);
}

/// Consecutive nodes for [`advance_all`].
pub(crate) struct Span<'a> {
    /// Displacements [m].
    pub(crate) u: &'a mut [Vector2<f64>],
    /// Velocities [m/s].
    pub(crate) v: &'a mut [Vector2<f64>],
    /// Forces as x, y pairs [N/m].
    pub(crate) f: &'a [f64],
    /// Lumped masses [kg/m].
    pub(crate) m: &'a [f64],
}

/// [`correct`] node by node from node `k` on, the accelerations into `a` (x, y pairs).
#[inline(always)]
pub(crate) fn correct_from(nodes: Span<'_>, a: &mut [f64], dt: f64, vmax2: &mut f64, k: usize) {
    let Span { u: _, v, f, m } = nodes;
    for (((a, v), f), &m) in a
        .chunks_exact_mut(2)
        .zip(v.iter_mut())
        .zip(f.chunks_exact(2))
        .zip(m)
        .skip(k)
    {
        let mut acc = Vector2::zeros();
        correct(&mut acc, v, Vector2::new(f[0], f[1]), m, dt, vmax2);
        a.copy_from_slice(acc.as_slice());
    }
}

/// [`advance`] node by node from node `k` on.
#[inline(always)]
pub(crate) fn advance_from(nodes: Span<'_>, dt: f64, vmax2: &mut f64, k: usize) {
    let Span { u, v, f, m } = nodes;
    for (((u, v), f), &m) in u
        .iter_mut()
        .zip(v.iter_mut())
        .zip(f.chunks_exact(2))
        .zip(m)
        .skip(k)
    {
        advance(u, v, Vector2::new(f[0], f[1]), m, dt, vmax2);
    }
}

/// One vectorised build of the node update, `$n` nodes a vector of 2`$n` lanes (x, y, x', y', …),
/// each lane through the IEEE operations of the one-node functions: a = f/m, v += ½Δt a and
/// |v|² = v_x² + v_y² (each pair swapped in-lane and added, an exact reordering); then, `FUSED`
/// ([`advance`]), u += Δt v + (½Δt)Δt a and v += ½Δt a, else ([`correct`]) a stored in `a_out`.
/// The running maximum is kept per lane with `max(|v|², max)`, which passes over a NaN; a lane
/// that is not finite (NaN, or ∞: not below ∞) sets a flag that makes the result ∞, as
/// [`track_vmax2`] does. The last nodes (fewer than `$n`) take the one-node path. A build gives
/// the operations that differ between instruction sets: `masses` (each node's mass in its two
/// lanes), `swap` (the pairs swapped), `not_finite`, and the flags' `none`, `or` and `any`.
macro_rules! update_in {
    (
        $(#[$doc:meta])*
        $name:ident,
        feature: $feature:literal,
        nodes: $n:literal,
        set1: $set1:ident,
        zero: $zero:ident,
        load: $load:ident,
        store: $store:ident,
        add: $add:ident,
        mul: $mul:ident,
        div: $div:ident,
        max: $max:ident,
        masses: |$mk:ident| $masses:expr,
        swap: |$sw:ident| $swap:expr,
        not_finite: |$x:ident, $inf:ident| $not_finite:expr,
        flags: $none:expr, |$fa:ident, $fb:ident| $or:expr, |$fl:ident| $any:expr $(,)?
    ) => {
        $(#[$doc])*
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $feature)]
        pub(crate) fn $name<const FUSED: bool>(nodes: Span<'_>, a_out: &mut [f64], dt: f64, vmax2: &mut f64) {
            #[allow(clippy::wildcard_imports)]
            use std::arch::x86_64::*;
            let Span { u, v, f, m } = nodes;
            assert!(FUSED || a_out.len() == 2 * u.len());
            let groups = u.len() / $n;
            let (hdt, h2) = (0.5 * dt, 0.5 * dt * dt);
            let (dtv, hdtv, h2v, inf) = ($set1(dt), $set1(hdt), $set1(h2), $set1(f64::INFINITY));
            let (mut top, mut bad) = ($zero(), $none);
            {
                let uf: &mut [f64] = bytemuck::cast_slice_mut(u);
                let vf: &mut [f64] = bytemuck::cast_slice_mut(v);
                for k in 0..groups {
                    let lanes = 2 * $n * k..2 * $n * (k + 1);
                    let (vk, fk) = (&mut vf[lanes.clone()], &f[lanes.clone()]);
                    let $mk = &m[$n * k..$n * (k + 1)];
                    // SAFETY: every slice read or written here holds the 2n (or n) f64 it touches.
                    unsafe {
                        let mass = $masses;
                        let a = $div($load(fk.as_ptr()), mass);
                        let half = $mul(hdtv, a);
                        let vn = $add($load(vk.as_ptr()), half);
                        let sq = $mul(vn, vn);
                        let v2 = $add(sq, {
                            let $sw = sq;
                            $swap
                        });
                        top = $max(v2, top);
                        bad = {
                            let ($fa, $fb) = (bad, {
                                let ($x, $inf) = (v2, inf);
                                $not_finite
                            });
                            $or
                        };
                        if FUSED {
                            let uk = &mut uf[lanes];
                            let du = $add($mul(dtv, vn), $mul(h2v, a));
                            $store(uk.as_mut_ptr(), $add($load(uk.as_ptr()), du));
                            $store(vk.as_mut_ptr(), $add(vn, half));
                        } else {
                            $store(a_out[lanes].as_mut_ptr(), a);
                            $store(vk.as_mut_ptr(), vn);
                        }
                    }
                }
            }
            let mut lanes = [0.0f64; 2 * $n];
            // SAFETY: `lanes` holds the 2n f64 stored.
            unsafe { $store(lanes.as_mut_ptr(), top) };
            if {
                let $fl = bad;
                $any
            } {
                *vmax2 = f64::INFINITY;
            }
            for l in lanes {
                track_vmax2(vmax2, l);
            }
            update_from::<FUSED>(Span { u, v, f, m }, a_out, dt, vmax2, $n * groups);
        }
    };
}

update_in!(
    /// The node update two nodes at a time in four AVX2 lanes; a lane that is not finite sets the
    /// bits of a flag register.
    update_avx2,
    feature: "avx2",
    nodes: 2,
    set1: _mm256_set1_pd,
    zero: _mm256_setzero_pd,
    load: _mm256_loadu_pd,
    store: _mm256_storeu_pd,
    add: _mm256_add_pd,
    mul: _mm256_mul_pd,
    div: _mm256_div_pd,
    max: _mm256_max_pd,
    masses: |mk| _mm256_set_m128d(_mm_loaddup_pd(&mk[1]), _mm_loaddup_pd(&mk[0])),
    swap: |x| _mm256_permute_pd::<0b0101>(x),
    not_finite: |x, inf| _mm256_cmp_pd::<_CMP_NLT_UQ>(x, inf),
    flags: _mm256_setzero_pd(),
    |a, b| _mm256_or_pd(a, b),
    |flag| _mm256_testz_si256(_mm256_castpd_si256(flag), _mm256_castpd_si256(flag)) == 0,
);

update_in!(
    /// The node update four nodes at a time in eight AVX-512F lanes: each node's mass goes to its
    /// two lanes by one permute, and a lane that is not finite sets a bit of a mask.
    update_avx512,
    feature: "avx512f",
    nodes: 4,
    set1: _mm512_set1_pd,
    zero: _mm512_setzero_pd,
    load: _mm512_loadu_pd,
    store: _mm512_storeu_pd,
    add: _mm512_add_pd,
    mul: _mm512_mul_pd,
    div: _mm512_div_pd,
    max: _mm512_max_pd,
    // lane l takes the mass of node l / 2
    masses: |mk| _mm512_permutexvar_pd(
        _mm512_set_epi64(3, 3, 2, 2, 1, 1, 0, 0),
        _mm512_castpd256_pd512(_mm256_loadu_pd(mk.as_ptr())),
    ),
    swap: |x| _mm512_permute_pd::<0b0101_0101>(x),
    not_finite: |x, inf| _mm512_cmp_pd_mask::<_CMP_NLT_UQ>(x, inf),
    flags: 0u8,
    |a, b| a | b,
    |flag| flag != 0,
);

#[cfg(test)]
mod tests {
    use super::*;

    /// A build of the node update under test: the span, the accelerations out (x, y pairs; the
    /// fused update leaves them), Δt, the running max |v|².
    type Build = fn(Span<'_>, &mut [f64], f64, &mut f64);

    /// A smooth vector field over node numbers, its frequency s.
    fn start(k: usize, s: f64) -> Vector2<f64> {
        Vector2::new((k as f64 * s).sin(), (k as f64 * s * 1.3).cos())
    }

    /// The bits of every component, node by node.
    fn bits(x: &[Vector2<f64>]) -> Vec<u64> {
        x.iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect()
    }

    /// Every build of the fused update (`advance_all`) and of the corrector alone (`correct_all`)
    /// this CPU runs (AVX-512F, AVX2, node by node) against `advance` or `correct` node by node:
    /// the same bits in u, v and a, and the same maximum. Eleven nodes leave a tail for each width
    /// (two quads and three nodes, five pairs and one); masses differ node to node, so a lane
    /// given a neighbour's mass is seen. The largest |v|² lies in an odd lane, and a NaN and an
    /// infinite force are put in turn in a vector's lane and in the tail.
    #[test]
    fn every_build_gives_the_bits_of_the_one_node_update() {
        let mut builds: Vec<(&str, bool, Build)> = vec![
            ("advance node by node", true, |s, _, dt, x| {
                advance_from(s, dt, x, 0)
            }),
            ("advance_all", true, |s, _, dt, x| advance_all(s, dt, x)),
            ("correct node by node", false, |s, a, dt, x| {
                correct_from(s, a, dt, x, 0)
            }),
        ];
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY (all four): the CPU reported AVX2 at run time.
                builds.push(("avx2 fused", true, |s, _, dt, x| unsafe {
                    update_avx2::<true>(s, &mut [], dt, x)
                }));
                builds.push(("avx2 corrector", false, |s, a, dt, x| unsafe {
                    update_avx2::<false>(s, a, dt, x)
                }));
            }
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY (both): the CPU reported AVX-512F at run time.
                builds.push(("avx512 fused", true, |s, _, dt, x| unsafe {
                    update_avx512::<true>(s, &mut [], dt, x)
                }));
                builds.push(("avx512 corrector", false, |s, a, dt, x| unsafe {
                    update_avx512::<false>(s, a, dt, x)
                }));
            }
        }
        let n = 11;
        let dt = 3.7e-7;
        let bad_forces = [
            None,
            Some((8, f64::NAN)),
            Some((8, f64::INFINITY)),
            Some((19, f64::NAN)),
        ];
        for (name, fused, build) in builds {
            for bad in bad_forces {
                let mut f: Vec<f64> = (0..2 * n).map(|k| (k as f64 * 0.917).sin() * 1e4).collect();
                f[5] = 7e5; // node 2, y: the largest velocity
                if let Some((at, b)) = bad {
                    f[at] = b;
                }
                let m: Vec<f64> = (0..n).map(|k| 0.3 + 0.1 * k as f64).collect();
                let (mut u1, mut v1): (Vec<_>, Vec<_>) =
                    (0..n).map(|k| (start(k, 0.3), start(k, 0.7))).unzip();
                let mut a1 = vec![Vector2::new(-1.0, -1.0); n];
                let (mut u2, mut v2, mut a2) = (u1.clone(), v1.clone(), a1.clone());
                let mut max1 = 0.5;
                for k in 0..n {
                    let force = Vector2::new(f[2 * k], f[2 * k + 1]);
                    if fused {
                        advance(&mut u1[k], &mut v1[k], force, m[k], dt, &mut max1);
                    } else {
                        correct(&mut a1[k], &mut v1[k], force, m[k], dt, &mut max1);
                    }
                }
                let mut max2 = 0.5;
                let nodes = Span {
                    u: &mut u2,
                    v: &mut v2,
                    f: &f,
                    m: &m,
                };
                build(nodes, bytemuck::cast_slice_mut(&mut a2), dt, &mut max2);
                assert_eq!(bits(&u1), bits(&u2), "{name}: u, bad force {bad:?}");
                assert_eq!(bits(&v1), bits(&v2), "{name}: v, bad force {bad:?}");
                assert_eq!(bits(&a1), bits(&a2), "{name}: a, bad force {bad:?}");
                assert_eq!(
                    max1.to_bits(),
                    max2.to_bits(),
                    "{name}: max |v|², bad force {bad:?}"
                );
                assert_eq!(max1 == f64::INFINITY, bad.is_some(), "{name}");
            }
        }
    }

    /// `predict_all` against `predict` node by node: the same bits in u and v on an odd count.
    #[test]
    fn predict_all_equals_node_by_node() {
        let n = 11;
        let dt = 3.7e-7;
        let a: Vec<_> = (0..n).map(|k| start(k, 1.9) * 3e5).collect();
        let (mut u1, mut v1): (Vec<_>, Vec<_>) = (0..n).map(|k| (start(k, 0.3), start(k, 0.7))).unzip();
        let (mut u2, mut v2) = (u1.clone(), v1.clone());
        for k in 0..n {
            predict(&mut u1[k], &mut v1[k], &a[k], dt);
        }
        predict_all(&mut u2, &mut v2, &a, dt);
        assert_eq!(bits(&u1), bits(&u2), "u");
        assert_eq!(bits(&v1), bits(&v2), "v");
    }
}
