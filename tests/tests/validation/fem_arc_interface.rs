//! Insertion and contact on a curved interface read from a Gmsh mesh
//! (`scenes/tiny-fem-arc-shear.toml`, `meshes/arc.msh`): a circular arc of radius R = 1.80278 m
//! cut into 22 facets (chords of h ≈ 0.096 m) that slope between −32° and +32°, pressed and then
//! sheared until the whole arc has broken and its faces slide on each other with friction. Three
//! claims (docs/claims.md, rows M.1–M.3), read from one run through its records and through field
//! snapshots taken after every step by a sink in this module, which measures the geometry itself:
//! - M.1: the cohesive energy the run's audit books as dissipated is G_c times the length of the
//!   broken facets, and every facet is fully broken (no partly damaged facet holds energy that
//!   would still be dissipated or returned);
//! - M.2: no crack-face node penetrates the opposite face deeper than p_max/ε_n, the penetration
//!   measured here from the node positions along the normal of the opposite facet the node lies
//!   over; every node in contact carries exactly ε_n times that penetration, and none penetrates
//!   without a contact pressure;
//! - M.3: each facet is inserted at the first step at which the mean stress of its two elements,
//!   resolved on the facet's own normal, reaches σ_c (paper App. A), and its cohesive element
//!   starts from that resolved traction σ n_f. The same stresses resolved on the straight
//!   interface's normal (0, 1) miss σ_c by up to 79 % at those steps, so insertion on a global
//!   normal would fail both checks.

use fem::nalgebra::Vector2;
use fem::records::fields::{FieldPiece, FieldSink, FieldSnapshot, FieldValues};
use std::sync::OnceLock;
use validation::{repo_root, scene_text, with_overrides};

/// `facet_state` of the crack piece (docs/outputs.md): a cohesive facet not yet inserted.
const FACET_INTACT: i32 = 1;
/// `facet_state`: both Gauss points fully damaged, a traction-free crack face.
const FACET_FREE: i32 = 3;

// Claim M.1. A Gauss point that breaks dissipates exactly G_c in the law (κ = 1: whatever its mode
// mix, paper eq. 1). The run integrates ∫T·dΔ per step with the trapezoid rule, exact on the
// linear softening branch and on the secant unloading; what is left are the steps holding a kink
// (insertion, full failure, a switch between loading, unloading and closing), each
// O(G_c (Δδ/δ_c)²): a time-integration error. Measured for the whole arc: +0.075 % at α = 0.5,
// +0.016 % at 0.25, +0.002 % at 0.125; per Gauss point at most 0.46 %, 0.07 %, 0.05 %. The
// whole-arc tolerance is the single element's G_c test's (`fem_cohesive_law`), 0.5 %; per point
// 1 %, twice the largest measured. Not tuned.
const TOL_DISSIPATION_REL: f64 = 0.005;
const TOL_POINT_WORK_REL: f64 = 0.01;
// The energy balance of the other FE tests, |residual| < 1 % of W_ext (measured 5.7e-4): the
// dissipation is booked in an audit that closes.
const TOL_BALANCE_REL: f64 = 0.01;
// Claim M.2. The model projects a slave node on its master facet as this test does, so the two
// penetrations agree to the round-off of positions of ~2 m (measured 1.2e-17 m); 1e-10 m leaves
// five orders of magnitude below the smallest penetrations that matter (1e-5 m). A gap measured
// vertically instead of along each facet's normal is off by the factor 1/cos θ, 6 to 18 % on the
// flanks (θ = 20° to 32°): the model edited so fails with 7.9e-4 m (tried, not kept), while the
// bound p_max/ε_n alone would still hold. Not tuned.
const TOL_PENETRATION_M: f64 = 1e-10; // m
// Claim M.3. The snapshots carry the model's own element stresses (a T3's constant stress), so the
// resolved stress and traction are the model's up to the round-off of a few products: 1e-9 σ_c
// (measured: 0, the same operations in the same order). Not tuned.
const TOL_RESOLVED_REL: f64 = 1e-9;
// Claim M.3 can fail: at the insertion steps, the stresses resolved on (0, 1) must miss σ_c by far
// more than the tolerance on some facet (measured 79 %); 25 % is a floor, not a measurement. The
// model edited to resolve on (0, 1) (tried, not kept) fails at its first insertion (σ_eff on the
// facet's own normal 0.79 σ_c, T_ins off by 8.3e4 Pa), and claim M.1's per-point check with it.
const MIN_GLOBAL_NORMAL_MISS: f64 = 0.25;

/// Per-step observations of one run, gathered by the field sink.
#[derive(Debug, Default)]
struct Watch {
    /// ε_n [Pa/m] and β [-] of the scene.
    eps_n: f64,
    beta: f64,
    /// Per facet: the reference unit normal (− → +) [-], the reference length [m] and the bulk
    /// cells on its + and − sides, from the first snapshot.
    normal: Vec<Vector2<f64>>,
    length: Vec<f64>,
    cells: Vec<[usize; 2]>,
    /// Per facet: the last snapshot's `facet_state`, and the largest effective stress resolved
    /// on its own normal over the snapshots so far [Pa].
    state: Vec<i32>,
    peak: Vec<f64>,
    /// Every insertion seen.
    insertions: Vec<Insertion>,
    /// Largest contact pressure of any node [Pa], when [s], and the largest penetration [m].
    p_max: f64,
    p_max_t: f64,
    penetration_max: f64,
    /// Largest |penetration − p_N/ε_n| over the nodes in contact, and the largest penetration of
    /// a node without a contact pressure [m].
    mismatch_max: f64,
    uncovered_max: f64,
    /// Node-samples in contact on a facet steeper than 20°, and the steepest such facet [rad].
    steep_contacts: usize,
    steepest_contact: f64,
    /// Snapshots taken [-].
    snapshots: usize,
}

/// One facet's insertion, seen at the step it happened.
#[derive(Debug, Clone, Copy)]
struct Insertion {
    facet: usize,
    /// Time of the step [s].
    t: f64,
    /// Slope of the facet [rad].
    slope: f64,
    /// σ_eff on the facet's own normal at the insertion step, and the largest over every
    /// earlier step [Pa].
    effective: f64,
    peak_before: f64,
    /// σ_eff on the global normal (0, 1) at the insertion step [Pa].
    effective_global: f64,
    /// |T_ins − σ n_f| of the cohesive element's traction at insertion, both in its current
    /// mid-line frame [Pa].
    traction_error: f64,
}

fn scalars<'p>(p: &'p FieldPiece, name: &str) -> &'p [f64] {
    match p.cell_array(name).or_else(|| p.point_array(name)) {
        Some(FieldValues::Scalars(v)) => v,
        other => panic!("{name}: {other:?}"),
    }
}

fn vectors<'p>(p: &'p FieldPiece, name: &str) -> &'p [[f64; 2]] {
    match p.point_array(name) {
        Some(FieldValues::Vectors(v)) => v,
        other => panic!("{name}: {other:?}"),
    }
}

fn v(p: [f64; 2]) -> Vector2<f64> {
    Vector2::new(p[0], p[1])
}

/// The effective stress √(⟨σ_nn⟩₊² + τ²/β²) of paper App. A [Pa] of the stress
/// [σ_xx, σ_yy, σ_xy] [Pa] on the unit normal `n`, and the traction σ n [Pa] itself.
fn resolved(sig: [f64; 3], n: Vector2<f64>, beta: f64) -> (f64, Vector2<f64>) {
    let t = Vector2::new(sig[0] * n.x + sig[2] * n.y, sig[2] * n.x + sig[1] * n.y);
    let (snn, tau) = (t.dot(&n), t.dot(&Vector2::new(n.y, -n.x)));
    ((snn.max(0.0).powi(2) + (tau / beta).powi(2)).sqrt(), t)
}

impl Watch {
    /// Facet normals, lengths and cells from the first snapshot. The crack piece lists the − copies
    /// of the row's nodes in order, then the + copies (docs/outputs.md); a facet's two bulk cells
    /// are those holding both its end points, the + one left of the row's direction.
    fn geometry(&mut self, bulk: &FieldPiece, crack: &FieldPiece) {
        let np = crack.points.len() / 2;
        let mut start = 0usize;
        let cell_nodes: Vec<&[u64]> = bulk
            .offsets
            .iter()
            .map(|&end| {
                let s = &bulk.connectivity[start..end as usize];
                start = end as usize;
                s
            })
            .collect();
        assert!(cell_nodes.iter().all(|c| c.len() == 3), "the arc mesh is T3");
        for c in 0..np - 1 {
            let (a, b) = (v(crack.points[c]), v(crack.points[c + 1]));
            let d = b - a;
            self.normal.push(Vector2::new(-d.y, d.x) / d.norm());
            self.length.push(d.norm());
            let mut sides = [usize::MAX; 2];
            for (k, nodes) in cell_nodes.iter().enumerate() {
                let at = |p: Vector2<f64>| nodes.iter().any(|&n| v(bulk.points[n as usize]) == p);
                if at(a) && at(b) {
                    let centroid = nodes
                        .iter()
                        .map(|&n| v(bulk.points[n as usize]))
                        .sum::<Vector2<f64>>()
                        / 3.0;
                    let side = usize::from(d.perp(&(centroid - a)) < 0.0);
                    assert_eq!(sides[side], usize::MAX, "facet {c}: two cells on one side");
                    sides[side] = k;
                }
            }
            assert!(
                sides.iter().all(|&s| s != usize::MAX),
                "facet {c}: cells {sides:?}"
            );
            self.cells.push(sides);
        }
        let nf = self.normal.len();
        self.state = vec![FACET_INTACT; nf];
        self.peak = vec![0.0; nf];
    }

    /// Claim M.3 at one step: each facet's stress resolved on its own normal; an insertion is
    /// recorded with the resolved stress now and its largest value before.
    fn insertions(&mut self, t: f64, bulk: &FieldPiece, crack: &FieldPiece) {
        let (sxx, syy, sxy) = (
            scalars(bulk, "sigma_xx"),
            scalars(bulk, "sigma_yy"),
            scalars(bulk, "sigma_xy"),
        );
        let Some(FieldValues::Integers(state)) = crack.cell_array("facet_state") else {
            panic!("facet_state")
        };
        let (tn, tt) = (
            scalars(crack, "cohesive_normal_traction"),
            scalars(crack, "cohesive_tangential_traction"),
        );
        let np = crack.points.len() / 2;
        let u = vectors(crack, "displacement");
        let pos = |k: usize| v(crack.points[k]) + v(u[k]);
        for c in 0..self.normal.len() {
            // the mean of the two elements' stresses, as insertion averages the two sides
            let [p, m] = self.cells[c];
            let sig = [sxx, syy, sxy].map(|s| 0.5 * (s[p] + s[m]));
            let (eff, traction) = resolved(sig, self.normal[c], self.beta);
            if self.state[c] == FACET_INTACT && state[c] != FACET_INTACT {
                // the cohesive element's traction in its current mid-line frame (n from − to +,
                // t along the row) against σ n_f in the same frame
                let mid = |k: usize| 0.5 * (pos(k) + pos(np + k));
                let d = (mid(c + 1) - mid(c)).normalize();
                let n = Vector2::new(-d.y, d.x);
                let expect = Vector2::new(traction.dot(&n), traction.dot(&d));
                let n0 = self.normal[c];
                self.insertions.push(Insertion {
                    facet: c,
                    t,
                    slope: (-n0.x).atan2(n0.y),
                    effective: eff,
                    peak_before: self.peak[c],
                    effective_global: resolved(sig, Vector2::new(0.0, 1.0), self.beta).0,
                    traction_error: (Vector2::new(tn[c], tt[c]) - expect).norm(),
                });
            }
            self.state[c] = state[c];
            self.peak[c] = self.peak[c].max(eff);
        }
    }

    /// Claim M.2 at one step: every crack-face node's penetration of the opposite face, measured
    /// along the normal of the opposite facet it lies over, against its contact pressure.
    fn penetrations(&mut self, t: f64, crack: &FieldPiece) {
        let np = crack.points.len() / 2;
        let u = vectors(crack, "displacement");
        let pressure = scalars(crack, "contact_normal_traction");
        let pos = |k: usize| v(crack.points[k]) + v(u[k]);
        let h = self.length.iter().sum::<f64>() / self.length.len() as f64;
        let left = |d: Vector2<f64>| Vector2::new(-d.y, d.x) / d.norm();
        for (face, other) in [(0, np), (np, 0)] {
            // the + side is left of the row's direction: a − node penetrates when it lies on the
            // + side of the + face, a + node when it lies on the − side of the − face; g < 0
            // is a penetration
            let flip = if face == 0 { -1.0 } else { 1.0 };
            for i in 0..np {
                let x = pos(face + i);
                // signed distance to the opposite facet the node lies over (foot within the facet
                // up to the model's projection tolerance, 1e-3 in ξ), the nearest if several
                let mut depth: Option<f64> = None;
                for j in 0..np - 1 {
                    let (a, b) = (pos(other + j), pos(other + j + 1));
                    let d = b - a;
                    let xi = 2.0 * (x - a).dot(&d) / d.norm_squared() - 1.0;
                    let g = flip * (x - a).dot(&left(d));
                    if xi.abs() <= 1.0 + 1e-3 && g.abs() < 0.5 * h && depth.is_none_or(|q| g.abs() < q.abs())
                    {
                        depth = Some(g);
                    }
                }
                // over no facet, near the vertex where two facets meet at an angle: the distance to
                // that vertex, signed by the mean normal of the two facets; beyond an end of the
                // face, the node faces nothing and penetrates nothing
                let depth = depth.unwrap_or_else(|| {
                    let k = (0..np)
                        .min_by(|&k, &l| {
                            (x - pos(other + k))
                                .norm()
                                .total_cmp(&(x - pos(other + l)).norm())
                        })
                        .expect("invariant: a face has nodes");
                    if k == 0 || k == np - 1 {
                        return f64::INFINITY;
                    }
                    let n =
                        left(pos(other + k) - pos(other + k - 1)) + left(pos(other + k + 1) - pos(other + k));
                    let r = x - pos(other + k);
                    flip * r.norm() * r.dot(&n).signum()
                });
                let penetration = (-depth).max(0.0);
                let p = pressure[face + i];
                if p > self.p_max {
                    (self.p_max, self.p_max_t) = (p, t);
                }
                self.penetration_max = self.penetration_max.max(penetration);
                if p > 0.0 {
                    self.mismatch_max = self.mismatch_max.max((penetration - p / self.eps_n).abs());
                    let slope = self.normal[i.min(np - 2)].x.asin().abs();
                    if slope > 20f64.to_radians() {
                        self.steep_contacts += 1;
                    }
                    self.steepest_contact = self.steepest_contact.max(slope);
                } else {
                    self.uncovered_max = self.uncovered_max.max(penetration);
                }
            }
        }
    }
}

impl FieldSink for Watch {
    fn snapshot(&mut self, s: FieldSnapshot) -> std::io::Result<()> {
        let crack = s.crack.as_ref().expect("invariant: the scene has an interface");
        if self.normal.is_empty() {
            self.geometry(&s.bulk, crack);
        }
        self.insertions(s.t, &s.bulk, crack);
        self.penetrations(s.t, crack);
        self.snapshots += 1;
        Ok(())
    }
}

/// The arc scene's run (once for all the tests of this module), with a snapshot after every step
/// watched by a [`Watch`]: (scene, output, watch, wall time [s]).
fn arc_run() -> &'static (fem::Scene, fem::RunOutput, Watch, f64) {
    static RUN: OnceLock<(fem::Scene, fem::RunOutput, Watch, f64)> = OnceLock::new();
    RUN.get_or_init(|| {
        let dir = repo_root().join("scenes");
        let text = scene_text("tiny-fem-arc-shear");
        let dt = fem::Scene::from_toml_str_in(&text, &dir).unwrap().time_step();
        // an interval of one step: a snapshot after every step. The sink writes no file, but the
        // scene check caps [fem.paraview] at 10 000 files, 2 per snapshot: the run must stay
        // below 5 000 steps (it has 3 515)
        let every_step = with_overrides(&text, &[("fem.paraview.interval", Some(toml::Value::Float(dt)))]);
        let scene = fem::Scene::from_toml_str_in(&every_step, &dir).unwrap();
        let law = scene
            .interface
            .expect("invariant: the scene has an interface law");
        let mut watch = Watch {
            eps_n: scene.fem.eps_n,
            beta: law.beta,
            ..Watch::default()
        };
        let stop = std::sync::atomic::AtomicBool::new(false);
        let clock = std::time::Instant::now();
        let out = fem::run_with_fields(&scene, &mut |_, _| {}, &stop, Some(&mut watch)).unwrap();
        let wall = clock.elapsed().as_secs_f64();
        println!(
            "arc shear: {} steps of {:.4e} s, {} elements, {} snapshots, {wall:.2} s wall",
            out.steps, out.time_step, out.elements, watch.snapshots
        );
        (scene, out, watch, wall)
    })
}

#[test]
fn the_broken_arc_dissipates_g_c_times_the_length_of_its_facets() {
    let (scene, out, w, _) = arc_run();
    let law = scene.interface.unwrap();
    let g_c = 0.5 * law.sigma_c * law.delta_c; // J/m²
    // every facet fully broken: both Gauss points at d = 1, the faces traction-free
    assert!(
        out.arrivals.iter().all(|a| a.failure_time.is_finite()),
        "every Gauss point must fail"
    );
    assert!(
        w.state.iter().all(|&s| s == FACET_FREE),
        "facet states {:?}",
        w.state
    );
    let last_failure = out.arrivals.iter().map(|a| a.failure_time).fold(0.0, f64::max);
    // the facets are chords of the arc: their total is shorter than the arc by (h/R)²/24 of it
    let total: f64 = w.length.iter().sum(); // m
    let r = (1.0f64 + 1.5 * 1.5).sqrt(); // m, meshes/arc.geo
    let arc = 2.0 * r * (1.0 / r).asin(); // m
    let h = total / w.length.len() as f64;
    let chord_deficit = (arc - total) / arc;
    let predicted = (h / r).powi(2) / 24.0;
    println!(
        "{} facets, h = {h:.5} m: chords {total:.6} m, arc {arc:.6} m, shorter by {chord_deficit:.3e} \
         ((h/R)²/24 = {predicted:.3e})",
        w.length.len()
    );
    assert!((chord_deficit / predicted - 1.0).abs() < 0.05);
    // the audit: E_coh,diss of the last record, against G_c × the chords' length
    let e = out.energy.last().unwrap();
    let expect = g_c * total; // J/m
    let rel = e.cohesive_dissipated / expect - 1.0;
    println!(
        "dissipated {:.3} J/m, G_c L = {expect:.3} J/m ({:+.4} %); all broken at t = {last_failure:.4} s \
         of T = {:.2} s",
        e.cohesive_dissipated,
        100.0 * rel,
        scene.duration()
    );
    assert!(rel.abs() <= TOL_DISSIPATION_REL);
    // broken facets carry no traction: the dissipation has not moved since the last failure
    let after: Vec<f64> = out
        .energy
        .iter()
        .filter(|r| r.t >= last_failure)
        .map(|r| r.cohesive_dissipated)
        .collect();
    assert!(after.len() > 10 && after.iter().all(|&x| x == e.cohesive_dissipated));
    // point by point: each Gauss point's work ∫T·dΔ is G_c
    let worst = out
        .arrivals
        .iter()
        .map(|a| (a.work_density / g_c - 1.0).abs())
        .fold(0.0, f64::max);
    println!("worst Gauss point: {:.3} % off G_c", 100.0 * worst);
    assert!(worst <= TOL_POINT_WORK_REL);
    let (balance, w_ext) = validation::worst_energy_residual(out);
    println!("energy residual: worst {balance:.2e} of W_ext ({w_ext:.1} J/m at T)");
    assert!(balance < TOL_BALANCE_REL);
}

#[test]
fn crack_faces_penetrate_no_deeper_than_the_penalty_along_each_facet_normal() {
    let (scene, out, w, _) = arc_run();
    let bound = w.p_max / w.eps_n; // m
    let applied = 0.1e6; // Pa, the top's compression (scene)
    let friction_after = {
        let last_failure = out.arrivals.iter().map(|a| a.failure_time).fold(0.0, f64::max);
        let at = out.energy.iter().find(|r| r.t >= last_failure).unwrap();
        out.energy.last().unwrap().friction_dissipated - at.friction_dissipated
    };
    println!(
        "p_max = {:.4e} Pa at t = {:.4} s ({:.1} × the applied compression), bound p_max/ε_n = {bound:.4e} m; largest \
         penetration {:.4e} m; largest |penetration − p_N/ε_n| {:.2e} m; largest penetration without \
         pressure {:.2e} m; {} node-samples in contact on facets steeper than 20° (steepest {:.1}°); \
         friction dissipated after the last failure {friction_after:.1} J/m; contacts dropped {}",
        w.p_max,
        w.p_max_t,
        w.p_max / applied,
        w.penetration_max,
        w.mismatch_max,
        w.uncovered_max,
        w.steep_contacts,
        w.steepest_contact.to_degrees(),
        out.record().dropped_contacts
    );
    assert_eq!(w.snapshots as u64, out.steps + 1, "a snapshot after every step");
    // the faces did meet on the curved part and slid with friction once broken
    assert!(w.steep_contacts > 0 && w.steepest_contact > 25f64.to_radians());
    assert!(scene.friction_coeff > 0.0 && friction_after > 0.0);
    assert_eq!(out.record().dropped_contacts, 0);
    assert!(w.penetration_max <= bound + TOL_PENETRATION_M);
    assert!(w.mismatch_max <= TOL_PENETRATION_M);
    assert!(w.uncovered_max <= TOL_PENETRATION_M);
}

#[test]
fn each_facet_is_inserted_when_the_stress_on_its_own_normal_reaches_sigma_c() {
    let (scene, _, w, wall) = arc_run();
    let sigma_c = scene.interface.unwrap().sigma_c; // Pa
    let mut global_miss = 0.0f64;
    for i in &w.insertions {
        println!(
            "facet {:2} at t = {:.5} s, slope {:+6.2}°: σ_eff {:.6e} Pa (largest before {:.6e} Pa), on (0, 1) \
             {:.4e} Pa ({:+.1} %), |T_ins − σ n_f| = {:.1e} Pa",
            i.facet,
            i.t,
            i.slope.to_degrees(),
            i.effective,
            i.peak_before,
            i.effective_global,
            100.0 * (i.effective_global / sigma_c - 1.0),
            i.traction_error
        );
        assert!(
            i.effective >= sigma_c * (1.0 - TOL_RESOLVED_REL),
            "facet {}",
            i.facet
        );
        assert!(
            i.peak_before < sigma_c * (1.0 + TOL_RESOLVED_REL),
            "facet {}",
            i.facet
        );
        assert!(
            i.traction_error <= TOL_RESOLVED_REL * sigma_c,
            "facet {}",
            i.facet
        );
        global_miss = global_miss.max((i.effective_global / sigma_c - 1.0).abs());
    }
    let mut facets: Vec<usize> = w.insertions.iter().map(|i| i.facet).collect();
    facets.sort_unstable();
    assert_eq!(
        facets,
        (0..w.normal.len()).collect::<Vec<_>>(),
        "each facet inserted once"
    );
    println!("runtime of the run: {wall:.2} s");
    assert!(global_miss > MIN_GLOBAL_NORMAL_MISS, "{global_miss}");
}
