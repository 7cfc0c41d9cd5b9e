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
    let a = f / m;
    *v += 0.5 * dt * a;
    track_vmax2(vmax2, v.norm_squared());
    predict(u, v, &a, dt);
}
