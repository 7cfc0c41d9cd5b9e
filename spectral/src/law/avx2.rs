//! [`point::step`](super::point::step) on four grid points at once, for AVX2, written in
//! intrinsics (docs/performance.md, "The interface law on four points at once (AVX2)").
//!
//! The scalar law branches at every point (strength update, the normal solve's stuck, open and
//! contact branches, the shear solve's stick and slip), and its divisions, one after the other,
//! bound its time. Here every branch is computed on four points with the operations of the
//! scalar law, on the same operands and in the same order (each product rounded on its own, no
//! fused multiply-add), and the scalar law's choice of branch is made lane by lane with masks.
//! So each point gets the bits of the scalar law (test
//! `the_law_on_four_lanes_gives_the_bits_of_the_scalar_law`), with four points' divisions in one
//! instruction. A branch that none of the four points takes is not computed: away from the
//! crack, where the faces stick and their jumps stay zero, that leaves three divisions for the
//! four points; on the crack, where all four are broken, the damage ratio is not computed.

use std::arch::x86_64::{
    __m256d, _CMP_EQ_OQ, _CMP_GE_OQ, _CMP_LE_OQ, _CMP_LT_OQ, _CMP_UNORD_Q, _mm256_add_pd, _mm256_and_pd,
    _mm256_andnot_pd, _mm256_blendv_pd, _mm256_cmp_pd, _mm256_div_pd, _mm256_loadu_pd, _mm256_min_pd,
    _mm256_movemask_pd, _mm256_mul_pd, _mm256_or_pd, _mm256_set_pd, _mm256_set1_pd, _mm256_setzero_pd,
    _mm256_sqrt_pd, _mm256_storeu_pd, _mm256_sub_pd,
};

use super::cohesive::Strength;
use super::point::{ContactFriction, Drives, Point, PointLaw};
use super::{Impedances, PointState};

/// The points of `points` solved four at a time, with their loads from `d` (index for index), as
/// [`point::step`](super::point::step) would solve each: returns how many points were solved (a
/// multiple of four; the caller solves the rest) and the first of them whose velocity is not
/// finite or exceeds `v_limit` [m/s], if any.
#[target_feature(enable = "avx2")]
pub(crate) fn solve(
    law: &PointLaw,
    v_limit: f64,
    d: &Drives<'_>,
    points: &mut [Point],
) -> (usize, Option<usize>) {
    // the caller checked that every slice of `d` is as long as `points`; the loads below are
    // bounds-checked all the same
    let n = points.len();
    let c = Constants::new(law, v_limit, d.load);
    let mut blown = None;
    let mut i = 0;
    while i + 4 <= n {
        let load = |x: &[f64]| {
            let x = &x[i..i + 4];
            // SAFETY: `x` holds four f64; the load has no alignment requirement.
            unsafe { _mm256_loadu_pd(x.as_ptr()) }
        };
        let drive = Lanes {
            nucleation: load(d.nucleation),
            f_top_x: load(d.f_top_x),
            f_bottom_x: load(d.f_bottom_x),
            f_top_y: load(d.f_top_y),
            f_bottom_y: load(d.f_bottom_y),
            u_top_x: load(d.u_top_x),
            u_bottom_x: load(d.u_bottom_x),
            u_top_y: load(d.u_top_y),
            u_bottom_y: load(d.u_bottom_y),
        };
        let group = &mut points[i..i + 4];
        let out_of_bounds = four(&c, law, &drive, group);
        if out_of_bounds != 0 && blown.is_none() {
            blown = Some(i + out_of_bounds.trailing_zeros() as usize);
        }
        i += 4;
    }
    (i, blown)
}

/// The loads of four points, as read from [`Drives`].
struct Lanes {
    nucleation: __m256d,
    f_top_x: __m256d,
    f_bottom_x: __m256d,
    f_top_y: __m256d,
    f_bottom_y: __m256d,
    u_top_x: __m256d,
    u_bottom_x: __m256d,
    u_top_y: __m256d,
    u_bottom_y: __m256d,
}

/// What the scalar law computes from the model alone at every point, computed once here with
/// the same operations.
struct Constants {
    sxy: f64,
    syy: f64,
    v_limit: f64,
    /// σ_max − σ_res and τ_max − τ_res [Pa].
    sigma_drop: f64,
    tau_drop: f64,
    /// (Z^-/ΣZ, Z^+/ΣZ, ΣZ) for the normal and the shear solve ([`Impedances::stick_weights`]).
    normal: (f64, f64, f64),
    shear: (f64, f64, f64),
}

impl Constants {
    fn new(law: &PointLaw, v_limit: f64, (sxy, syy): (f64, f64)) -> Constants {
        let weights = |z: Impedances| {
            let (w_top, w_bottom) = z.stick_weights();
            (w_top, w_bottom, z.sum())
        };
        let p = &law.cohesive;
        Constants {
            sxy,
            syy,
            v_limit,
            sigma_drop: p.sigma_max - p.sigma_res,
            tau_drop: p.tau_max - p.tau_res,
            normal: weights(law.z_normal),
            shear: weights(law.z_shear),
        }
    }
}

/// `f64::min(a, b)`: `b` where `a` is NaN (as `_mm256_min_pd` gives), `a` where `b` is NaN.
#[inline]
#[target_feature(enable = "avx2")]
fn min(a: __m256d, b: __m256d) -> __m256d {
    _mm256_blendv_pd(_mm256_min_pd(a, b), a, _mm256_cmp_pd::<_CMP_UNORD_Q>(b, b))
}

/// |x|: the sign bit cleared, as `f64::abs`.
#[inline]
#[target_feature(enable = "avx2")]
fn abs(x: __m256d) -> __m256d {
    _mm256_andnot_pd(_mm256_set1_pd(-0.0), x)
}

/// `f64::signum`: ±1 with the sign of x (of ±0 too), NaN where x is NaN.
#[inline]
#[target_feature(enable = "avx2")]
fn signum(x: __m256d) -> __m256d {
    let one = _mm256_or_pd(_mm256_and_pd(x, _mm256_set1_pd(-0.0)), _mm256_set1_pd(1.0));
    _mm256_blendv_pd(one, _mm256_set1_pd(f64::NAN), _mm256_cmp_pd::<_CMP_UNORD_Q>(x, x))
}

/// `b` where `mask`, else `a`.
#[inline]
#[target_feature(enable = "avx2")]
fn select(mask: __m256d, b: __m256d, a: __m256d) -> __m256d {
    _mm256_blendv_pd(a, b, mask)
}

/// Whether the mask is set in every lane.
#[inline]
#[target_feature(enable = "avx2")]
fn all(mask: __m256d) -> bool {
    _mm256_movemask_pd(mask) == 0b1111
}

/// Whether the mask is set in no lane.
#[inline]
#[target_feature(enable = "avx2")]
fn none(mask: __m256d) -> bool {
    _mm256_movemask_pd(mask) == 0
}

/// The four lanes of x, in point order.
#[inline]
#[target_feature(enable = "avx2")]
fn lanes(x: __m256d) -> [f64; 4] {
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four f64; the store has no alignment requirement.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), x) };
    out
}

/// A point's state, carried as its discriminant in an f64 lane.
fn state_of(code: f64) -> PointState {
    if code >= 3.0 {
        PointState::Contact
    } else if code >= 2.0 {
        PointState::Broken
    } else if code >= 1.0 {
        PointState::Cohesive
    } else {
        PointState::Intact
    }
}

/// One step of the law on the four points of `p` (docs/spectral-model.md §5.4); the bits set in
/// the result mark the points whose velocity is out of bounds (not finite, or above the limit).
#[inline]
#[target_feature(enable = "avx2")]
fn four(c: &Constants, law: &PointLaw, d: &Lanes, p: &mut [Point]) -> i32 {
    let set = _mm256_set1_pd;
    let cmp_eq = |a, b| _mm256_cmp_pd::<_CMP_EQ_OQ>(a, b);
    let cmp_lt = |a, b| _mm256_cmp_pd::<_CMP_LT_OQ>(a, b);
    let (zero, one) = (_mm256_setzero_pd(), set(1.0));
    let (p0, p1, p2, p3) = (&p[0], &p[1], &p[2], &p[3]);
    let sigma = _mm256_set_pd(
        p3.strength.sigma,
        p2.strength.sigma,
        p1.strength.sigma,
        p0.strength.sigma,
    );
    let tau = _mm256_set_pd(p3.strength.tau, p2.strength.tau, p1.strength.tau, p0.strength.tau);
    let code = |q: &Point| q.strength.state as u8 as f64;
    let state = _mm256_set_pd(code(p3), code(p2), code(p1), code(p0));
    let prev_reg = _mm256_set_pd(p3.reg_normal, p2.reg_normal, p1.reg_normal, p0.reg_normal);

    // the drive: S^± = T^0 + f^± and the jumps
    let t01 = _mm256_add_pd(set(c.sxy), d.nucleation);
    let (s_top, s_bottom) = (_mm256_add_pd(t01, d.f_top_x), _mm256_add_pd(t01, d.f_bottom_x));
    let syy = set(c.syy);
    let (n_top, n_bottom) = (_mm256_add_pd(syy, d.f_top_y), _mm256_add_pd(syy, d.f_bottom_y));
    let opening = _mm256_sub_pd(d.u_top_y, d.u_bottom_y);
    let slip = _mm256_sub_pd(d.u_top_x, d.u_bottom_x);

    // strengths (§5.1, `cohesive::update`); skipped where no lane changes them
    let q = &law.cohesive;
    let broken = _mm256_cmp_pd::<_CMP_GE_OQ>(state, set(PointState::Broken as u8 as f64));
    let untouched = _mm256_andnot_pd(broken, _mm256_and_pd(cmp_eq(opening, zero), cmp_eq(slip, zero)));
    let (sigma, tau, state) = if all(untouched) {
        (sigma, tau, state)
    } else {
        let at_residual = cmp_eq(sigma, set(q.sigma_res));
        let residual = _mm256_or_pd(at_residual, cmp_eq(tau, set(q.tau_res)));
        // the damage ratio decides only where a strength is above its residual (broken points
        // have both at it)
        let (fails, softened_sigma, softened_tau) = if all(residual) {
            (residual, zero, zero)
        } else {
            let (rn, rt) = (
                _mm256_div_pd(opening, set(q.delta_cn)),
                _mm256_div_pd(slip, set(q.delta_ct)),
            );
            let a = _mm256_sqrt_pd(_mm256_add_pd(_mm256_mul_pd(rn, rn), _mm256_mul_pd(rt, rt)));
            (
                _mm256_or_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(a, one), residual),
                min(
                    _mm256_sub_pd(set(q.sigma_max), _mm256_mul_pd(set(c.sigma_drop), a)),
                    sigma,
                ),
                min(
                    _mm256_sub_pd(set(q.tau_max), _mm256_mul_pd(set(c.tau_drop), a)),
                    tau,
                ),
            )
        };
        let kept = _mm256_and_pd(at_residual, cmp_lt(opening, set(-f64::EPSILON)));
        let unchanged = _mm256_or_pd(untouched, _mm256_and_pd(fails, kept));
        let to_residual = _mm256_andnot_pd(kept, fails);
        (
            select(
                unchanged,
                sigma,
                select(to_residual, set(q.sigma_res), softened_sigma),
            ),
            select(unchanged, tau, select(to_residual, set(q.tau_res), softened_tau)),
            select(
                unchanged,
                state,
                select(
                    to_residual,
                    set(PointState::Broken as u8 as f64),
                    set(PointState::Cohesive as u8 as f64),
                ),
            ),
        )
    };

    // the normal solve (§5.2 a–c, `contact::solve`); a branch no lane takes is not computed
    let (wb, wt, zsum) = c.normal;
    let z = law.z_normal;
    let t_star = _mm256_add_pd(_mm256_mul_pd(set(wb), n_top), _mm256_mul_pd(set(wt), n_bottom));
    let not_stuck = _mm256_or_pd(cmp_lt(sigma, t_star), cmp_eq(sigma, zero));
    let (v_top_open, v_bottom_open) = if none(not_stuck) {
        (zero, zero)
    } else {
        (
            _mm256_div_pd(_mm256_sub_pd(n_top, sigma), set(z.top)),
            _mm256_div_pd(_mm256_sub_pd(sigma, n_bottom), set(z.bottom)),
        )
    };
    let in_contact = if law.contact && !none(not_stuck) {
        let gap = _mm256_add_pd(
            opening,
            _mm256_mul_pd(set(law.dt), _mm256_sub_pd(v_top_open, v_bottom_open)),
        );
        _mm256_and_pd(not_stuck, cmp_lt(gap, set(-f64::EPSILON)))
    } else {
        zero
    };
    let (v_top_contact, v_bottom_contact, traction_contact) = if none(in_contact) {
        (zero, zero, zero)
    } else {
        let w = _mm256_div_pd(opening, set(law.dt));
        let v_top = _mm256_div_pd(
            _mm256_sub_pd(_mm256_sub_pd(n_top, n_bottom), _mm256_mul_pd(set(z.bottom), w)),
            set(zsum),
        );
        (
            v_top,
            _mm256_add_pd(v_top, w),
            _mm256_sub_pd(n_top, _mm256_mul_pd(set(z.top), v_top)),
        )
    };
    let v_stuck = if all(not_stuck) {
        zero
    } else {
        _mm256_div_pd(_mm256_sub_pd(n_top, n_bottom), set(zsum))
    };
    let normal_v_top = select(in_contact, v_top_contact, select(not_stuck, v_top_open, v_stuck));
    let normal_v_bottom = select(
        in_contact,
        v_bottom_contact,
        select(not_stuck, v_bottom_open, v_stuck),
    );
    let normal_traction = select(in_contact, traction_contact, select(not_stuck, sigma, t_star));

    // where friction acts, and σ̃ (eq. 14)
    let (closed, friction_on) = match law.rule {
        ContactFriction::FailedOnly => (in_contact, in_contact),
        ContactFriction::AllFaces => {
            let compressed = _mm256_andnot_pd(not_stuck, cmp_lt(normal_traction, zero));
            let closed = _mm256_or_pd(in_contact, compressed);
            let intact = cmp_eq(state, set(PointState::Intact as u8 as f64));
            (closed, _mm256_andnot_pd(intact, closed))
        }
    };
    let towards = _mm256_and_pd(closed, normal_traction);
    let reg_normal = match law.relax {
        None => towards,
        Some(r) => _mm256_div_pd(
            _mm256_add_pd(prev_reg, _mm256_mul_pd(set(r), towards)),
            set(1.0 + r),
        ),
    };
    let friction = _mm256_mul_pd(set(law.friction_coeff), abs(reg_normal));
    let state = select(in_contact, set(PointState::Contact as u8 as f64), state);
    let shear_strength = select(friction_on, _mm256_add_pd(tau, friction), tau);

    // the shear solve (§5.2 d, `friction::solve_shear`)
    let (wb, wt, zsum) = c.shear;
    let z = law.z_shear;
    let t_trial = _mm256_add_pd(_mm256_mul_pd(set(wb), s_top), _mm256_mul_pd(set(wt), s_bottom));
    let slipping = _mm256_or_pd(cmp_lt(shear_strength, abs(t_trial)), cmp_eq(shear_strength, zero));
    let (traction_slip, v_top_slip, v_bottom_slip) = if none(slipping) {
        (zero, zero, zero)
    } else {
        let t = _mm256_mul_pd(shear_strength, signum(t_trial));
        (
            t,
            _mm256_div_pd(_mm256_sub_pd(s_top, t), set(z.top)),
            _mm256_div_pd(_mm256_sub_pd(t, s_bottom), set(z.bottom)),
        )
    };
    let v_stick = if all(slipping) {
        zero
    } else {
        _mm256_div_pd(_mm256_sub_pd(s_top, s_bottom), set(zsum))
    };
    let shear_traction = select(slipping, traction_slip, t_trial);
    let shear_v_top = select(slipping, v_top_slip, v_stick);
    let shear_v_bottom = select(slipping, v_bottom_slip, v_stick);

    // the blow-up guard: |v| ≤ v_limit on all four velocities, NaN failing it
    let limit = set(c.v_limit);
    let within = |v| _mm256_cmp_pd::<_CMP_LE_OQ>(abs(v), limit);
    let ok = _mm256_and_pd(
        _mm256_and_pd(within(shear_v_top), within(normal_v_top)),
        _mm256_and_pd(within(shear_v_bottom), within(normal_v_bottom)),
    );
    let out_of_bounds = !_mm256_movemask_pd(ok) & 0b1111;

    let (sigma, tau, state, reg_normal) = (lanes(sigma), lanes(tau), lanes(state), lanes(reg_normal));
    let (shear_traction, normal_traction) = (lanes(shear_traction), lanes(normal_traction));
    let v = [shear_v_top, normal_v_top, shear_v_bottom, normal_v_bottom].map(|v| lanes(v));
    let flags = |m| _mm256_movemask_pd(m);
    let (in_contact, slipping, friction_on) = (flags(in_contact), flags(slipping), flags(friction_on));
    for (l, q) in p.iter_mut().enumerate().take(4) {
        q.strength = Strength {
            sigma: sigma[l],
            tau: tau[l],
            state: state_of(state[l]),
        };
        q.reg_normal = reg_normal[l];
        q.in_contact = in_contact >> l & 1 == 1;
        q.slipping = slipping >> l & 1 == 1;
        q.friction_on = friction_on >> l & 1 == 1;
        q.traction = [shear_traction[l], normal_traction[l]];
        q.v = [v[0][l], v[1][l], v[2][l], v[3][l]];
    }
    out_of_bounds
}
