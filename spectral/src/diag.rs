//! Read-only observers of the state: crack and cohesive-zone tips (docs/spectral-model.md §6), contact
//! means, space-time field snapshots.

use crate::law::PointState;
use crate::output::{ContactMeanRecord, FieldRecord, TipRecord};
use crate::solver::{Model, State, far_field};

/// Farthest indices reached walking from the centre in direction `dir` (+1/−1), at most N/2 − 1
/// points, while the points are broken (state ≥ 2) and while they are damaged (state ≥ 1); None
/// where the centre point itself is not. One walk serves both: a broken point is damaged, so the
/// broken run from the centre ends no later than the damaged one.
fn walk(model: &Model, st: &State, dir: isize) -> (Option<usize>, Option<usize>) {
    let n = model.n as isize;
    let c = model.center_index as isize;
    let state = |m: isize| st.points[m as usize].strength.state;
    if state(c) < PointState::Cohesive {
        return (None, None);
    }
    let (mut m, mut broken) = (c, state(c).is_broken().then_some(c));
    for _ in 0..(n / 2 - 1) {
        // (m + dir) mod n, without a division per point (this walk runs twice a step)
        let next = match m + dir {
            -1 => n - 1,
            k if k == n => 0,
            k => k,
        };
        let s = state(next);
        if s < PointState::Cohesive {
            break;
        }
        if broken == Some(m) && s.is_broken() {
            broken = Some(next);
        }
        m = next;
    }
    (broken.map(|b| b as usize), Some(m as usize))
}

/// Tips at t: crack tip = last point of the contiguous broken set (state 2 or 3), cohesive-zone tip =
/// last point of the contiguous set with state ≥ 1; both equal center_x if the centre is intact.
pub(crate) fn tips(model: &Model, st: &State, t: f64) -> TipRecord {
    let c = model.scene.center_x;
    let x = |m: Option<usize>| m.map_or(c, |m| model.x[m]);
    let (right, cz_right) = walk(model, st, 1);
    let (left, cz_left) = walk(model, st, -1);
    TipRecord {
        t,
        tip_right: x(right),
        tip_left: x(left),
        cz_tip_right: x(cz_right),
        cz_tip_left: x(cz_left),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;
    use crate::solver;

    /// The definition: the farthest point reached from the centre in direction `dir` while `pred`
    /// holds, one walk a predicate, modulo N, at most N/2 − 1 points.
    fn walk_one(model: &Model, st: &State, dir: isize, pred: impl Fn(PointState) -> bool) -> Option<usize> {
        let n = model.n as isize;
        let c = model.center_index as isize;
        if !pred(st.points[c as usize].strength.state) {
            return None;
        }
        let mut m = c;
        for _ in 0..(n / 2 - 1) {
            let next = (m + dir).rem_euclid(n);
            if !pred(st.points[next as usize].strength.state) {
                break;
            }
            m = next;
        }
        Some(m as usize)
    }

    /// One walk a direction finds both tips of the definition's two walks, on interfaces of runs
    /// of every state in random order and lengths, the centre's state among them, on runs that
    /// reach the walk's limit, and where broken points lie beyond a cohesive one.
    #[test]
    fn one_walk_finds_the_crack_and_cohesive_tips_of_two() {
        let scene = Scene::from_toml_str(include_str!("../../scenes/center-crack.toml")).unwrap();
        let (model, mut st, _) = solver::build(&scene).unwrap();
        let (n, c) = (model.n, model.center_index);
        let states = [
            PointState::Intact,
            PointState::Cohesive,
            PointState::Broken,
            PointState::Contact,
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = |k: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % k
        };
        let (mut broken_beyond_cohesive, mut to_the_limit) = (false, false);
        for case in 0..400 {
            // runs of one state each, up to a quarter of the grid long
            let mut m = 0;
            while m < n {
                let (state, run) = (states[next(4) as usize], 1 + next((n / 4) as u64) as usize);
                for p in &mut st.points[m..(m + run).min(n)] {
                    p.strength.state = state;
                }
                m += run;
            }
            if case % 10 == 0 {
                // every point damaged: both walks end at their limit
                for p in &mut st.points {
                    p.strength.state = states[2 + next(2) as usize];
                }
            }
            let broken = |s: PointState| s.is_broken();
            let damaged = |s: PointState| s >= PointState::Cohesive;
            for dir in [1, -1] {
                let expected = (
                    walk_one(&model, &st, dir, broken),
                    walk_one(&model, &st, dir, damaged),
                );
                assert_eq!(walk(&model, &st, dir), expected, "case {case}, direction {dir}");
                // the cohesive tip's point broken, the crack tip short of it
                if let (b, Some(d)) = expected {
                    broken_beyond_cohesive |= b != Some(d) && st.points[d].strength.state.is_broken();
                }
                to_the_limit |= expected.1.is_some_and(|d| d.abs_diff(c) == n / 2 - 1);
            }
        }
        assert!(broken_beyond_cohesive && to_the_limit, "the cases reach both");
    }
}
