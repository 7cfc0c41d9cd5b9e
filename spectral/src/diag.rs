//! Read-only observers of the state: crack and cohesive-zone tips (docs/spectral-model.md §6), contact
//! means, space-time field snapshots.

use crate::law::PointState;
use crate::output::{ContactMeanRecord, FieldRecord, TipRecord};
use crate::solver::{Model, State, far_field};

/// Farthest index reached walking from the centre in direction `dir` (+1/−1) while `pred` holds,
/// at most N/2 − 1 points; None if the centre point itself fails `pred`.
fn walk(model: &Model, st: &State, dir: isize, pred: impl Fn(PointState) -> bool) -> Option<usize> {
    let n = model.n as isize;
    let c = model.center_index as isize;
    if !pred(st.points[c as usize].strength.state) {
        return None;
    }
    let mut m = c;
    for _ in 0..(n / 2 - 1) {
        // (m + dir) mod n, without a division per point (this walk runs four times a step)
        let next = match m + dir {
            -1 => n - 1,
            k if k == n => 0,
            k => k,
        };
        if !pred(st.points[next as usize].strength.state) {
            break;
        }
        m = next;
    }
    Some(m as usize)
}

/// Tips at t: crack tip = last point of the contiguous broken set (state 2 or 3), cohesive-zone tip =
/// last point of the contiguous set with state ≥ 1; both equal center_x if the centre is intact.
pub(crate) fn tips(model: &Model, st: &State, t: f64) -> TipRecord {
    let c = model.scene.center_x;
    let x = |m: Option<usize>| m.map_or(c, |m| model.x[m]);
    let broken = |s: PointState| s.is_broken();
    let damaged = |s: PointState| s >= PointState::Cohesive;
    TipRecord {
        t,
        tip_right: x(walk(model, st, 1, broken)),
        tip_left: x(walk(model, st, -1, broken)),
        cz_tip_right: x(walk(model, st, 1, damaged)),
        cz_tip_left: x(walk(model, st, -1, damaged)),
    }
}

/// Contact means over the pre-crack and penetration over the interface at t (tractions of step n,
/// penetration of u^n, i.e. what remains after step n − 1).
pub(crate) fn contact_means(model: &Model, st: &State, t: f64) -> ContactMeanRecord {
    let (sxy, syy) = far_field(model, t);
    let (mut count, mut slipping, mut sum_n, mut sum_t) = (0u32, 0u32, 0.0, 0.0);
    let (mut max_t2, mut max_pen) = (f64::NEG_INFINITY, 0.0f64);
    for m in 0..model.n {
        max_pen = max_pen.max(st.u.bottom_y[m] - st.u.top_y[m]);
        let p = &st.points[m];
        if !p.in_contact {
            continue;
        }
        max_t2 = max_t2.max(p.traction[1]);
        if model.on_precrack[m] {
            count += 1;
            slipping += u32::from(p.slipping);
            sum_n += p.traction[1].abs();
            sum_t += p.traction[0].abs();
        }
    }
    let mean = |s: f64| if count > 0 { s / count as f64 } else { 0.0 };
    ContactMeanRecord {
        t,
        far_field_shear: sxy,
        far_field_normal: syy,
        contact_points: count,
        slipping_points: slipping,
        mean_normal_traction: mean(sum_n),
        mean_tangential_traction: mean(sum_t),
        max_contact_normal_traction: if max_t2.is_finite() { max_t2 } else { 0.0 },
        max_penetration: max_pen,
    }
}

/// Appends one snapshot of every grid point.
pub(crate) fn fields(model: &Model, st: &State, t: f64, out: &mut Vec<FieldRecord>) {
    let smax = model.law.cohesive.sigma_max;
    for m in 0..model.n {
        let p = &st.points[m];
        let s = p.strength;
        out.push(FieldRecord {
            t,
            x: model.x[m],
            slip: st.u.top_x[m] - st.u.bottom_x[m],
            opening: st.u.top_y[m] - st.u.bottom_y[m],
            damage: 1.0 - s.sigma / smax,
            state: s.state as u8,
            shear_traction: p.traction[0],
            normal_traction: p.traction[1],
            vx_top: p.v[0],
            vy_top: p.v[1],
            vx_bottom: p.v[2],
            vy_bottom: p.v[3],
        });
    }
}
