//! Section 4 diagnostics (paper Figures 10-12): the residual stress of eq. (17), the contact (KKT)
//! conditions on the crack faces of the contact surface, and stress snapshots. Read-only; called
//! at sample times only, and only for what the scene declares.

use crate::law::cohesive::ClosingTreatment;
use crate::mesh::interfaces::{FacetKind, InterfaceRow, NO_FACET};
use crate::model::cohesive::{facet_gauss, midline_normal};
use crate::model::state::{Model, State};
use crate::model::stress::{self, Side};
use crate::records::{FieldRecord, KktRecord, ProfileRecord};
use nalgebra::Vector2;

/// Columns searched on each side of a node for the closest opposing segment (slips up to this
/// many elements are measured exactly).
const SEARCH_COLUMNS: usize = 100;

fn pos(model: &Model, state: &State, n: u32) -> Vector2<f64> {
    model.bulk.x0[n as usize] + state.u[n as usize]
}

/// Distances within this fraction of the element size count as touching, neither open nor in
/// contact: node coordinates carry round-off of ~1e-16 m, penalty penetrations are 1e-7 to 1e-4 m.
const TOUCH_TOLERANCE_OVER_H: f64 = 1e-9;

/// Whether facet c is one the KKT metric watches (the interface zones when declared, else every
/// facet) and a free crack face (pre-crack or inserted).
fn free_face(model: &Model, state: &State, row: &InterfaceRow, c: usize) -> bool {
    watched(model, c) && (row.kind[c] == FacetKind::PreCrack || state.facets.inserted[c])
}

/// The facets of the interface zones when the scene declares zones (the interface the Section 4
/// comparison is about), else every facet.
fn watched(model: &Model, c: usize) -> bool {
    model.interface.laws.len() <= 1 || model.interface.facet_law[c] > 0
}

/// Facets adjacent to column i.
fn adjacent(row: &InterfaceRow, i: usize) -> impl Iterator<Item = usize> + '_ {
    row.column_facets(i)
}

/// Signed distance [m] of point p to the polyline through the `face` copies of the row's
/// columns (current positions), searched over the facets of columns i0 ± SEARCH_COLUMNS (of
/// i0's chain only: the facets join the columns in `row.ends`); positive on the side the
/// polyline's left normal points to (upwards for a left-to-right row). At a vertex the two
/// segments' normals are averaged.
fn signed_distance(
    model: &Model,
    state: &State,
    row: &InterfaceRow,
    face: &[u32],
    i0: usize,
    p: Vector2<f64>,
) -> f64 {
    let lo = i0.saturating_sub(SEARCH_COLUMNS);
    let hi = (i0 + SEARCH_COLUMNS).min(row.num_facets());
    let normal = |k: usize| {
        let [a, b] = row.facet_columns(k);
        let t = pos(model, state, face[b]) - pos(model, state, face[a]);
        Vector2::new(-t.y, t.x).normalize()
    };
    let mut best = (f64::INFINITY, 0.0);
    for k in (lo..hi).filter(|&k| row.chain[row.facet_columns(k)[0]] == row.chain[i0]) {
        let [ka, kb] = row.facet_columns(k);
        let a = pos(model, state, face[ka]);
        let t = pos(model, state, face[kb]) - a;
        let s = ((p - a).dot(&t) / t.norm_squared()).clamp(0.0, 1.0);
        let q = a + s * t;
        let d = (p - q).norm();
        if d < best.0 {
            let [before, after] = [row.col_facets[ka][0], row.col_facets[kb][1]];
            let n = match s {
                s if s <= 0.0 && before != NO_FACET => normal(before as usize) + normal(k),
                s if s >= 1.0 && after != NO_FACET => normal(k) + normal(after as usize),
                _ => normal(k),
            };
            best = (d, if (p - q).dot(&n) >= 0.0 { d } else { -d });
        }
    }
    best.1
}

/// True gaps [m] of the + and − copies of column i (> 0 open).
pub(crate) fn gaps(model: &Model, state: &State, row: &InterfaceRow, i: usize) -> (f64, f64) {
    let gp = signed_distance(model, state, row, &row.minus, i, pos(model, state, row.plus[i]));
    let gm = -signed_distance(model, state, row, &row.plus, i, pos(model, state, row.minus[i]));
    (gp, gm)
}

/// Compressive tractions [Pa] carried by the + and − copies of column i: the slave contact
/// pressure (hybrid) or ε_n ⟨−δ_n⟩₊ of the frozen twin pair (standard, eq. 4).
pub(crate) fn compressive(model: &Model, state: &State, row: &InterfaceRow, i: usize) -> (f64, f64) {
    match (model.interface.closing, &state.contact) {
        (ClosingTreatment::Standard { eps_n }, _) => {
            let mut n = Vector2::zeros();
            for c in adjacent(row, i).filter(|&c| state.facets.inserted[c]) {
                n += midline_normal(row, &model.bulk.x0, &state.u, c, state.facets.sign[c]);
            }
            if n == Vector2::zeros() {
                return (0.0, 0.0);
            }
            let delta_n =
                (pos(model, state, row.plus[i]) - pos(model, state, row.minus[i])).dot(&n.normalize());
            let p = eps_n * (-delta_n).max(0.0);
            (p, p)
        }
        (ClosingTreatment::Hybrid, Some(cp)) => {
            let cs = &cp.state;
            let p = |n: u32| {
                let c = cs.at(n as usize);
                if c.in_contact { c.normal_pressure } else { 0.0 }
            };
            (p(row.plus[i]), p(row.minus[i]))
        }
        (ClosingTreatment::Hybrid, None) => (0.0, 0.0),
    }
}

/// The KKT record of the current state.
pub(crate) fn kkt(model: &Model, state: &State) -> KktRecord {
    let mut r = KktRecord {
        t: state.t,
        crack_face_nodes: 0,
        compressive_nodes: 0,
        violating_nodes: 0,
        violating_share: 0.0,
        max_violating_traction: 0.0,
        mismatch_nodes: 0,
        max_slip: 0.0,
    };
    let Some(row) = &model.interface.row else { return r };
    // h: the grid spacing, or the mean facet length of a Gmsh mesh's interface
    let h = match model.grid() {
        Some(_) => model.bulk.x0[1].x - model.bulk.x0[0].x,
        None => row.length.iter().sum::<f64>() / row.num_facets() as f64,
    };
    let tol = TOUCH_TOLERANCE_OVER_H * h;
    for i in 0..row.plus.len() {
        if !adjacent(row, i).any(|c| free_face(model, state, row, c)) {
            continue;
        }
        let (gp, gm) = gaps(model, state, row, i);
        let (pp, pm) = compressive(model, state, row, i);
        for (g, p) in [(gp, pp), (gm, pm)] {
            r.crack_face_nodes += 1;
            r.compressive_nodes += usize::from(p > 0.0);
            if p > 0.0 && g > tol {
                r.violating_nodes += 1;
                r.max_violating_traction = r.max_violating_traction.max(p);
            }
            r.mismatch_nodes += usize::from(p > 0.0 && g > tol || p == 0.0 && g < -tol);
        }
        let n = row.normal[adjacent(row, i).last().expect("invariant: a column has a facet")];
        let tangent = Vector2::new(n.y, -n.x);
        let slip = (state.u[row.plus[i] as usize] - state.u[row.minus[i] as usize]).dot(&tangent);
        r.max_slip = r.max_slip.max(slip.abs());
    }
    if r.crack_face_nodes > 0 {
        r.violating_share = r.violating_nodes as f64 / r.crack_face_nodes as f64;
    }
    r
}

/// Residual stress of eq. (17) [Pa]: ∫ (σ n)·e_x dA over the + facets with midpoint in [x₀, x₁],
/// divided by the x extent those facets cover (x₁ − x₀ up to half an element at each end); σ from
/// the + element extrapolated to the facet Gauss points (docs/fem-model.md §1, §8.4), n the
/// reference facet normal (− → +), so that a flat face gives the mean σ_xy.
pub(crate) fn residual_stress(model: &Model, state: &State, [x0, x1]: [f64; 2]) -> f64 {
    let Some(row) = &model.interface.row else {
        return 0.0;
    };
    let (mut integral, mut extent) = (0.0, 0.0);
    for c in 0..row.num_facets() {
        let [a, b] = row.facet_columns(c);
        let (xa, xb) = (
            model.bulk.x0[row.plus[a] as usize].x,
            model.bulk.x0[row.plus[b] as usize].x,
        );
        if !crate::scene::in_range(0.5 * (xa + xb), [x0, x1]) {
            continue;
        }
        extent += xb - xa;
        let sp = stress::facet_side(
            model,
            row,
            c,
            Side::Plus,
            &state.u,
            facet_gauss().map(|(s, _, _)| s),
        );
        let n = row.normal[c];
        for sig in sp {
            integral += 0.5 * row.length[c] * (sig[0] * n.x + sig[2] * n.y);
        }
    }
    if extent > 0.0 { integral / extent } else { 0.0 }
}

/// Appends the element stresses inside `window` and the upper-face profile of the contact
/// surface for snapshot k.
pub(crate) fn snapshot(
    model: &Model,
    state: &State,
    k: usize,
    window: [[f64; 2]; 2],
    fields: &mut Vec<FieldRecord>,
    profiles: &mut Vec<ProfileRecord>,
) {
    let [[x0, x1], [y0, y1]] = window;
    for e in 0..model.num_elements() {
        let (centre, [sxx, syy, sxy]) = stress::element_mean(model, e, &state.u);
        if centre.x < x0 || centre.x > x1 || centre.y < y0 || centre.y > y1 {
            continue;
        }
        fields.push(FieldRecord {
            snapshot: k,
            t: state.t,
            x: centre.x,
            y: centre.y,
            sxx,
            syy,
            sxy,
        });
    }
    let Some(row) = &model.interface.row else { return };
    for i in 0..row.plus.len() {
        if !adjacent(row, i).any(|c| watched(model, c)) {
            continue;
        }
        let mut syy = 0.0;
        let mut count = 0.0;
        for c in adjacent(row, i) {
            let xi = if row.facet_columns(c)[1] == i { 1.0 } else { -1.0 };
            syy += stress::facet_side(model, row, c, Side::Plus, &state.u, [xi])[0][1];
            count += 1.0;
        }
        let (gp, _) = gaps(model, state, row, i);
        let (pp, _) = compressive(model, state, row, i);
        let x = model.bulk.x0[row.plus[i] as usize];
        profiles.push(ProfileRecord {
            snapshot: k,
            t: state.t,
            x: x.x,
            y: x.y,
            syy: syy / count,
            crack_face: adjacent(row, i).any(|c| free_face(model, state, row, c)),
            gap: gp,
            compressive_traction: pp,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn sinusoid() -> (Scene, Model, State) {
        let scene = Scene::from_toml_str(&crate::test_scenes::scene_text("sinusoidal-interface")).unwrap();
        let (model, state, _) = crate::model::build::build(&scene).unwrap();
        (scene, model, state)
    }

    #[test]
    fn residual_stress_of_simple_shear_is_the_shear_stress_on_the_curved_branch() {
        // u_x = γ y is reproduced exactly by Q4 elements, so σ = (0, 0, Gγ) everywhere and
        // ∫ (σn)·e_x dA = Gγ ∫ n_y dA = Gγ (x₁ − x₀) over any facet row: σ̄ = Gγ exactly
        let (scene, model, mut state) = sinusoid();
        let gamma = 1e-3;
        for (u, x) in state.u.iter_mut().zip(&model.bulk.x0) {
            *u = Vector2::new(gamma * x.y, 0.0);
        }
        let expect = scene.material.shear_modulus * gamma;
        let got = residual_stress(&model, &state, scene.fem.diagnostics.residual_stress_x.unwrap());
        assert!((got - expect).abs() <= 1e-9 * expect, "{got} vs {expect}");
    }

    #[test]
    fn true_gap_of_a_lifted_face_is_the_lift_times_the_cosine_of_the_slope() {
        let (_, model, mut state) = sinusoid();
        let row = model.interface.row.as_ref().unwrap();
        let d = 1e-6;
        for &n in &row.plus {
            state.u[n as usize] = Vector2::new(0.0, d);
        }
        // on flat stretches (pre-crack at column 400, strong interface at column 700) the gap is d;
        // on the sinusoid the point lifted above a vertex is between d cos θ (θ the steeper adjacent
        // slope) and d from the polyline
        for i in [400, 700] {
            let (gp, gm) = gaps(&model, &state, row, i);
            assert!(
                (gp - d).abs() <= 1e-9 * d && (gm - d).abs() <= 1e-9 * d,
                "column {i}: {gp}, {gm}"
            );
        }
        let slope = |k: usize| {
            let (a, b) = (
                model.bulk.x0[row.minus[k] as usize],
                model.bulk.x0[row.minus[k + 1] as usize],
            );
            ((b.y - a.y) / (b.x - a.x)).abs()
        };
        for i in (120..260).chain(490..630) {
            let lower = d / (1.0 + slope(i - 1).max(slope(i)).powi(2)).sqrt();
            let (gp, gm) = gaps(&model, &state, row, i);
            for g in [gp, gm] {
                assert!(
                    g >= lower * (1.0 - 1e-6) && g <= d * (1.0 + 1e-6),
                    "column {i}: {g} not in [{lower}, {d}]"
                );
            }
        }
        // pushed through instead: negative on both sides
        for &n in &row.plus {
            state.u[n as usize] = Vector2::new(0.0, -d);
        }
        let (gp, gm) = gaps(&model, &state, row, 200);
        assert!(gp < 0.0 && gm < 0.0, "{gp}, {gm}");
    }
}
