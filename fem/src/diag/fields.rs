//! ParaView field snapshots (`[fem.paraview]`): the state as a bulk piece (every node, every T3 or Q4
//! element) and a crack piece (the interface row as line cells, each twin its own point so the
//! crack opens when warped), and the schedule that takes them during a run. Read-only; computed
//! only at snapshot steps, and nothing at all unless the scene declares the table and the caller
//! passes a [`FieldSink`].

use crate::diag::section4;
use crate::mesh::interfaces::{FacetKind, InterfaceRow};
use crate::model::cohesive::midline_normal;
use crate::model::state::{Model, State};
use crate::model::stress;
use crate::records::fields::{CellShape, FieldArray, FieldPiece, FieldSink, FieldSnapshot, FieldValues};
use crate::scene::Scene;
use nalgebra::Vector2;
use std::io;

/// `facet_state` of a facet that never opens (its twins stay tied).
pub const FACET_PLAIN: i32 = 0;
/// `facet_state` of a cohesive facet not yet inserted (tied).
pub const FACET_INTACT: i32 = 1;
/// `facet_state` of an inserted cohesive element with a Gauss point not fully damaged.
pub const FACET_COHESIVE: i32 = 2;
/// `facet_state` of a traction-free crack face: pre-crack, or both Gauss points at d = 1.
pub const FACET_FREE: i32 = 3;

fn vectors(v: &[Vector2<f64>], nodes: impl Iterator<Item = usize>) -> FieldValues {
    FieldValues::Vectors(nodes.map(|n| [v[n].x, v[n].y]).collect())
}

/// The snapshot of the current state.
pub(crate) fn snapshot(model: &Model, state: &State) -> FieldSnapshot {
    FieldSnapshot {
        step: state.step,
        t: state.t,
        bulk: bulk_piece(model, state),
        crack: model
            .interface
            .row
            .as_ref()
            .map(|row| crack_piece(model, state, row)),
    }
}

/// Every node at its reference position with u [m] and v [m/s]; every element with its stresses
/// [Pa]: the mean of a Q4's four Gauss-point stresses σ = D B u_e (docs/fem-model.md §1) or a T3's
/// constant stress, σ_zz = ν (σ_xx + σ_yy) of plane strain, and the von Mises stress of the
/// three-dimensional tensor.
fn bulk_piece(model: &Model, state: &State) -> FieldPiece {
    let ne = model.num_elements();
    let mut piece = FieldPiece {
        points: model.bulk.x0.iter().map(|x| [x.x, x.y]).collect(),
        connectivity: Vec::with_capacity(4 * ne),
        offsets: Vec::with_capacity(ne),
        shapes: Vec::with_capacity(ne),
        ..FieldPiece::default()
    };
    let mut s = [(); 5].map(|_| Vec::with_capacity(ne));
    for e in 0..ne {
        // plane strain: σ_zz = λ (ε_xx + ε_yy) = λ/(2(λ + μ)) (σ_xx + σ_yy), with D₀₀ = λ + 2μ,
        // D₀₁ = λ of the element's own material
        let d = model.d_of(e);
        let nu = d[0][1] / (d[0][0] + d[0][1]);
        let nodes = model.element_nodes(e);
        let shape = match nodes.as_slice().len() {
            3 => CellShape::Triangle,
            _ => CellShape::Quad,
        };
        piece.push_cell(shape, nodes.as_slice());
        let (_, [xx, yy, xy]) = stress::element_mean(model, e, &state.u);
        let zz = nu * (xx + yy);
        let mises =
            (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2)) + 3.0 * xy * xy).sqrt();
        for (k, v) in [xx, yy, xy, zz, mises].into_iter().enumerate() {
            s[k].push(v);
        }
    }
    let all = 0..model.num_nodes();
    piece.point_data = vec![
        FieldArray::new("displacement", vectors(&state.u, all.clone())),
        FieldArray::new("velocity", vectors(&state.v, all)),
    ];
    let [xx, yy, xy, zz, mises] = s;
    piece.cell_data = vec![
        FieldArray::new("sigma_xx", FieldValues::Scalars(xx)),
        FieldArray::new("sigma_yy", FieldValues::Scalars(yy)),
        FieldArray::new("sigma_xy", FieldValues::Scalars(xy)),
        FieldArray::new("sigma_zz", FieldValues::Scalars(zz)),
        FieldArray::new("von_mises", FieldValues::Scalars(mises)),
    ];
    piece
}

/// The interface row: points = the − copies of its nodes, then the + copies (each twin its own
/// point); cells = the − faces of its facets, then their + faces.
fn crack_piece(model: &Model, state: &State, row: &InterfaceRow) -> FieldPiece {
    let (nf, np) = (row.num_facets(), row.plus.len());
    let nodes: Vec<usize> = row.minus.iter().chain(&row.plus).map(|&n| n as usize).collect();
    let mut piece = FieldPiece {
        points: nodes
            .iter()
            .map(|&n| [model.bulk.x0[n].x, model.bulk.x0[n].y])
            .collect(),
        ..FieldPiece::default()
    };
    for side in 0..2u32 {
        for c in 0..nf {
            let [a, b] = row.ends[c].map(|i| side * np as u32 + i);
            piece.push_cell(CellShape::Line, &[a, b]);
        }
    }
    // per node: true gap, contact penetration and tractions (− copies, then + copies)
    let mut gap = vec![0.0; 2 * np];
    let mut pressure = vec![0.0; 2 * np];
    for i in 0..np {
        let (gp, gm) = section4::gaps(model, state, row, i);
        let (pp, pm) = section4::compressive(model, state, row, i);
        (gap[i], gap[np + i]) = (gm, gp);
        (pressure[i], pressure[np + i]) = (pm, pp);
    }
    let (mut penetration, mut tangential) = (vec![0.0; 2 * np], vec![0.0; 2 * np]);
    if let Some(cp) = &state.contact {
        let cs = &cp.state;
        for (k, &n) in nodes.iter().enumerate() {
            let c = cs.at(n);
            if c.in_contact {
                (penetration[k], tangential[k]) = (c.penetration, c.tangential_traction.abs());
            }
        }
    }
    piece.point_data = vec![
        FieldArray::new("displacement", vectors(&state.u, nodes.iter().copied())),
        FieldArray::new("velocity", vectors(&state.v, nodes.iter().copied())),
        FieldArray::new("gap", FieldValues::Scalars(gap)),
        FieldArray::new("contact_penetration", FieldValues::Scalars(penetration)),
        FieldArray::new("contact_normal_traction", FieldValues::Scalars(pressure)),
        FieldArray::new("contact_tangential_traction", FieldValues::Scalars(tangential)),
    ];
    // per facet, the same on its two faces
    let facets: Vec<FacetFields> = (0..nf).map(|c| facet_fields(model, state, row, c)).collect();
    let both = |f: &dyn Fn(&FacetFields) -> f64| -> FieldValues {
        FieldValues::Scalars(facets.iter().chain(&facets).map(f).collect())
    };
    piece.cell_data = vec![
        FieldArray::new(
            "face",
            FieldValues::Integers((0..2 * nf).map(|k| if k < nf { -1 } else { 1 }).collect()),
        ),
        FieldArray::new(
            "facet_state",
            FieldValues::Integers(facets.iter().chain(&facets).map(|f| f.state).collect()),
        ),
        FieldArray::new("damage", both(&|f| f.damage)),
        FieldArray::new("normal_opening", both(&|f| f.opening[0])),
        FieldArray::new("tangential_opening", both(&|f| f.opening[1])),
        FieldArray::new("cohesive_normal_traction", both(&|f| f.traction[0])),
        FieldArray::new("cohesive_tangential_traction", both(&|f| f.traction[1])),
    ];
    piece
}

/// What the crack piece shows of one facet.
struct FacetFields {
    /// FACET_PLAIN, FACET_INTACT, FACET_COHESIVE or FACET_FREE.
    state: i32,
    /// Mean damage of the two Gauss points [-] (0 if not inserted).
    damage: f64,
    /// Opening Δ = u⁺ − u⁻ at the facet midpoint along (n, t) [m].
    opening: [f64; 2],
    /// Mean cohesive traction of the two Gauss points along (n, t) [Pa] (0 if not inserted).
    traction: [f64; 2],
}

/// Facet c: n is the normal of the current mid-line, oriented − → + by the sign fixed at
/// insertion (upwards before), as in the cohesive element (paper eqs. 2–3: δ_n = Δ·n > 0 opens,
/// T·n > 0 pulls the faces together); t = (n_y, −n_x) turned back along the row when the sign is
/// negative, i.e. the direction from column c to c + 1.
fn facet_fields(model: &Model, state: &State, row: &InterfaceRow, c: usize) -> FacetFields {
    let f = &state.facets;
    let inserted = f.inserted[c];
    let sign = f.sign[c];
    let n = midline_normal(row, &model.bulk.x0, &state.u, c, sign);
    let t = sign * Vector2::new(n.y, -n.x);
    let opening_at = |i: usize| state.u[row.plus[i] as usize] - state.u[row.minus[i] as usize];
    let mid = 0.5 * (opening_at(c) + opening_at(c + 1));
    let damages = f.gauss[c].map(|g| g.damage);
    let (damage, traction) = if inserted {
        let mean = 0.5 * (f.prev_traction[c][0] + f.prev_traction[c][1]);
        (0.5 * (damages[0] + damages[1]), [mean.dot(&n), mean.dot(&t)])
    } else {
        (0.0, [0.0, 0.0])
    };
    let state = match row.kind[c] {
        FacetKind::PreCrack => FACET_FREE,
        FacetKind::Plain => FACET_PLAIN,
        FacetKind::Cohesive if !inserted => FACET_INTACT,
        FacetKind::Cohesive if damages.iter().all(|&d| d >= 1.0) => FACET_FREE,
        FacetKind::Cohesive => FACET_COHESIVE,
    };
    FacetFields {
        state,
        damage,
        opening: [mid.dot(&n), mid.dot(&t)],
        traction,
    }
}

/// When a run takes its snapshots, and where they go: at step 0, every
/// [`crate::scene::ParaviewSpec::every`] steps, and at the last step (however the run ends).
pub(crate) struct Snapshots<'a> {
    sink: Option<&'a mut dyn FieldSink>,
    /// Steps between snapshots; 0: none are taken.
    every: u64,
    /// Step of the last snapshot taken.
    last: Option<u64>,
    /// The sink's first error; no snapshot is taken after it.
    error: Option<io::Error>,
}

impl<'a> Snapshots<'a> {
    /// The schedule of `scene` (time step Δt [s]); none without `[fem.paraview]` or without a sink.
    pub(crate) fn new(scene: &Scene, dt: f64, sink: Option<&'a mut dyn FieldSink>) -> Snapshots<'a> {
        let every = match (&sink, &scene.fem.paraview) {
            (Some(_), Some(p)) => p.every(dt),
            _ => 0,
        };
        Snapshots {
            sink,
            every,
            last: None,
            error: None,
        }
    }

    /// Whether a snapshot is due after step `n`.
    #[inline]
    pub(crate) fn due(&self, n: u64) -> bool {
        self.every > 0 && n.is_multiple_of(self.every)
    }

    /// Takes the snapshot of `state` if its step is due. False once the sink has failed (the
    /// run then stops). When off, one compare per step and nothing else.
    #[inline]
    pub(crate) fn after_step(&mut self, model: &Model, state: &State) -> bool {
        if self.every == 0 || !state.step.is_multiple_of(self.every) {
            return self.error.is_none();
        }
        self.take(model, state)
    }

    /// Takes the snapshot of the final state unless it was just taken (the run's last step, or
    /// the step at which it stopped early).
    pub(crate) fn last(&mut self, model: &Model, state: &State) {
        if self.every > 0 && self.last != Some(state.step) {
            self.take(model, state);
        }
    }

    /// Whether the sink has failed (the error is kept for [`Snapshots::error`]).
    pub(crate) fn failed(&self) -> bool {
        self.error.is_some()
    }

    /// Step of the last snapshot taken (`None`: none yet).
    pub(crate) fn last_taken(&self) -> Option<u64> {
        self.last
    }

    /// The sink's list of the snapshots taken, as a checkpoint keeps it.
    pub(crate) fn taken(&self) -> Vec<(f64, Vec<String>)> {
        self.sink.as_deref().map_or_else(Vec::new, FieldSink::taken)
    }

    /// Takes back what [`Snapshots::last_taken`] and [`Snapshots::taken`] gave, when a run
    /// resumes from a checkpoint.
    pub(crate) fn resume(&mut self, last: Option<u64>, taken: Vec<(f64, Vec<String>)>) -> io::Result<()> {
        self.last = last;
        match self.sink.as_deref_mut() {
            Some(sink) => sink.resume(taken),
            None => Ok(()),
        }
    }

    /// The sink's error, if it failed.
    pub(crate) fn error(&mut self) -> Option<io::Error> {
        self.error.take()
    }

    fn take(&mut self, model: &Model, state: &State) -> bool {
        if self.error.is_some() {
            return false;
        }
        let Some(sink) = self.sink.as_deref_mut() else {
            return true;
        };
        self.last = Some(state.step);
        if let Err(e) = sink.snapshot(snapshot(model, state)) {
            self.error = Some(e);
            return false;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scalars<'p>(p: &'p FieldPiece, name: &str) -> &'p [f64] {
        match p.cell_array(name) {
            Some(FieldValues::Scalars(v)) => v,
            other => panic!("{name}: {other:?}"),
        }
    }

    #[test]
    fn a_uniform_strain_gives_the_analytic_stress_in_every_element() {
        // u = H X with a constant gradient H is reproduced exactly by Q4 elements, so every
        // Gauss point has ε = sym(H) and σ = D ε; what is left is round-off of sums of ~10 terms
        // of size |σ| (~1e-16 relative each), hence 1e-10 relative is a wide margin that a wrong
        // Gauss mean, sign or ordering (errors of order 1) cannot pass
        let scene = Scene::from_toml_str(&crate::test_scenes::scene_text("tiny-fem-center-crack")).unwrap();
        let (model, mut state, _) = crate::model::build::build(&scene).unwrap();
        let [[hxx, hxy], [hyx, hyy]] = [[2e-4, 3e-4], [-1e-4, -5e-4]];
        for (u, x) in state.u.iter_mut().zip(&model.bulk.x0) {
            *u = Vector2::new(hxx * x.x + hxy * x.y, hyx * x.x + hyy * x.y);
        }
        let m = &scene.material;
        let (l, g) = (m.lambda, m.shear_modulus);
        let (exx, eyy, gxy) = (hxx, hyy, hxy + hyx);
        let expect = [
            ("sigma_xx", (l + 2.0 * g) * exx + l * eyy),
            ("sigma_yy", l * exx + (l + 2.0 * g) * eyy),
            ("sigma_xy", g * gxy),
            ("sigma_zz", l * (exx + eyy)),
        ];
        let (sxx, syy, sxy, szz) = (expect[0].1, expect[1].1, expect[2].1, expect[3].1);
        let mises = (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2))
            + 3.0 * sxy * sxy)
            .sqrt();
        let snap = snapshot(&model, &state);
        let scale = sxx.abs().max(syy.abs());
        // (that the file holds exactly these values is the writer's test, in output::paraview)
        for (name, value) in expect.into_iter().chain([("von_mises", mises)]) {
            let got = scalars(&snap.bulk, name);
            assert_eq!(got.len(), model.num_elements());
            let worst = got.iter().map(|s| (s - value).abs()).fold(0.0, f64::max);
            assert!(worst <= 1e-10 * scale, "{name}: {worst} Pa off {value} Pa");
        }
        // twins are separate points with their own displacement; the crack piece shows them
        let crack = snap.crack.unwrap();
        let row = model.interface.row.as_ref().unwrap();
        assert_eq!(crack.points.len(), 2 * row.plus.len());
        assert_eq!(crack.num_cells(), 2 * row.num_facets());
    }

    /// Two materials (`scenes/tiny-fem-bimaterial.toml` with the stiff part's ν made 0.25): under
    /// one uniform strain every element's stresses, σ_zz = ν_e(σ_xx + σ_yy) included, are those
    /// of its own material (λ_e, G_e); the same round-off margin as above. Reading the first
    /// material everywhere misses the stiff part's σ_xx by a factor 8.
    #[test]
    fn each_element_shows_the_stress_of_its_own_material() {
        let text = crate::test_scenes::scene_text("tiny-fem-bimaterial").replacen(
            "poisson_ratio = 0.35            # -\ndensity = 2460.0",
            "poisson_ratio = 0.25\ndensity = 2460.0",
            1,
        );
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let scene = Scene::from_toml_str_in(&text, &dir).unwrap();
        let materials = scene.materials();
        assert_eq!(materials[1].poisson_ratio, 0.25);
        let (model, mut state, _) = crate::model::build::build(&scene).unwrap();
        let (exx, eyy, gxy) = (2e-4, -5e-4, 2e-4);
        for (u, x) in state.u.iter_mut().zip(&model.bulk.x0) {
            *u = Vector2::new(exx * x.x + gxy * x.y, eyy * x.y);
        }
        let snap = snapshot(&model, &state);
        let (sxx, szz) = (scalars(&snap.bulk, "sigma_xx"), scalars(&snap.bulk, "sigma_zz"));
        let mut seen = [0usize; 2];
        for e in 0..model.num_elements() {
            let nodes = model.element_nodes(e);
            let cx = nodes
                .as_slice()
                .iter()
                .map(|&n| model.bulk.x0[n as usize].x)
                .sum::<f64>()
                / 4.0;
            let k = usize::from(cx > 1.0);
            seen[k] += 1;
            let (l, g) = (materials[k].lambda, materials[k].shear_modulus);
            let (xx, yy) = ((l + 2.0 * g) * exx + l * eyy, l * exx + (l + 2.0 * g) * eyy);
            let zz = l * (exx + eyy);
            let scale = xx.abs().max(yy.abs());
            assert!(
                (sxx[e] - xx).abs() <= 1e-10 * scale,
                "element {e}: σ_xx {} vs {xx}",
                sxx[e]
            );
            assert!(
                (szz[e] - zz).abs() <= 1e-10 * scale,
                "element {e}: σ_zz {} vs {zz}",
                szz[e]
            );
        }
        assert_eq!(seen, [400, 400]);
    }

    #[test]
    fn an_opened_crack_shows_its_opening_on_both_faces() {
        // lift the + copies of the row by d: the opening is (0, d) everywhere, the true gap d on
        // both faces; exact up to the round-off of positions ~1e-2 m (1e-18 m), far below 1e-6 d
        let scene = Scene::from_toml_str(&crate::test_scenes::scene_text("tiny-fem-center-crack")).unwrap();
        let (model, mut state, _) = crate::model::build::build(&scene).unwrap();
        let row = model.interface.row.as_ref().unwrap();
        let d = 1e-6;
        for &n in &row.plus {
            state.u[n as usize] = Vector2::new(0.0, d);
        }
        let crack = snapshot(&model, &state).crack.unwrap();
        let cells = |name: &str| scalars(&crack, name).to_vec();
        for (c, (&dn, &dt)) in cells("normal_opening")
            .iter()
            .zip(&cells("tangential_opening"))
            .enumerate()
        {
            assert!((dn - d).abs() < 1e-12 && dt.abs() < 1e-12, "cell {c}: {dn}, {dt}");
        }
        let Some(FieldValues::Scalars(gap)) = crack.point_array("gap") else {
            panic!("gap")
        };
        assert!(gap.iter().all(|g| (g - d).abs() < 1e-12), "{gap:?}");
        let Some(FieldValues::Integers(state_of)) = crack.cell_array("facet_state") else {
            panic!()
        };
        // 40 facets: the 20 of the pre-crack |x| < 10 mm are free, the rest intact cohesive
        let nf = row.num_facets();
        let free = state_of[..nf].iter().filter(|&&s| s == FACET_FREE).count();
        assert_eq!(free, 20);
        assert!(
            state_of[..nf]
                .iter()
                .all(|&s| s == FACET_FREE || s == FACET_INTACT)
        );
        assert_eq!(state_of[..nf], state_of[nf..]);
    }
}
