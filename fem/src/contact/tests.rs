//! Unit tests of the contact pass on small hand-built configurations.

use nalgebra::Vector2;

use super::search::{BucketGrid, Limits, Slave, closest_master};
use super::*;

pub(super) const H: f64 = 1e-3; // m, segment length
pub(super) const EPS: f64 = 2.1e10; // Pa/m, ε_n = ε_t = 300 E per metre (docs/cases.md)
pub(super) const NO_TWIN: u32 = u32::MAX;

pub(super) fn params(friction_coeff: f64) -> ContactParams {
    ContactParams {
        eps_n: EPS,
        eps_t: EPS,
        friction_coeff,
        max_gap: H,
        projection_tolerance: 1e-3,
        prakash_ratio: None,
    }
}

/// Two flat faces: the lower block's top face (nodes 0..=n_low at y = 0, segments right → left
/// so the normal is +y) and the upper block's bottom face (nodes after them at y = y_up,
/// x = offset + k h_up, segments left → right so the normal is −y).
pub(super) struct Faces {
    pub(super) x: Vec<Vector2<f64>>,
    pub(super) surface: DetectionSurface,
    pub(super) lower: Vec<u32>,
    pub(super) upper: Vec<u32>,
}

pub(super) fn faces(n_low: usize, h_low: f64, n_up: usize, h_up: f64, offset: f64, y_up: f64) -> Faces {
    let mut x = Vec::new();
    let lower: Vec<u32> = (0..=n_low).map(|k| k as u32).collect();
    x.extend((0..=n_low).map(|k| Vector2::new(k as f64 * h_low, 0.0)));
    let upper: Vec<u32> = (0..=n_up).map(|k| (n_low + 1 + k) as u32).collect();
    x.extend((0..=n_up).map(|k| Vector2::new(offset + k as f64 * h_up, y_up)));
    let mut surface = DetectionSurface::with_capacity(x.len(), n_low + n_up);
    for w in lower.windows(2) {
        surface.add_segment(w[1], w[0]);
    }
    for w in upper.windows(2) {
        surface.add_segment(w[0], w[1]);
    }
    Faces {
        x,
        surface,
        lower,
        upper,
    }
}

pub(super) fn frames_of(segments: &[[u32; 2]], x: &[Vector2<f64>]) -> Vec<Option<geometry::SegmentFrame>> {
    segments
        .iter()
        .map(|s| geometry::segment_frame(x[s[0] as usize], x[s[1] as usize]))
        .collect()
}

pub(super) struct Pass {
    pub(super) state: ContactState,
    pub(super) ws: ContactWorkspace,
    pub(super) f: Vec<Vector2<f64>>,
    pub(super) summary: ContactSummary,
}

pub(super) fn new_pass(c: &Faces) -> Pass {
    let n = c.x.len();
    Pass {
        state: ContactState::new(n, c.surface.num_segments()),
        ws: ContactWorkspace::new(n, c.surface.num_segments()),
        f: vec![Vector2::zeros(); n],
        summary: ContactSummary::default(),
    }
}

pub(super) fn run(c: &mut Faces, pass: &mut Pass, p: &ContactParams, twins: &[u32]) {
    pass.f.iter_mut().for_each(|f| *f = Vector2::zeros());
    pass.summary = resolve(
        p,
        &mut c.surface,
        &c.x,
        twins,
        &[],
        &mut pass.state,
        &mut pass.ws,
        &mut pass.f,
    );
}

pub(super) fn total(f: &[Vector2<f64>]) -> (Vector2<f64>, f64) {
    let sum = f.iter().sum::<Vector2<f64>>();
    let scale = f.iter().map(|v| v.norm()).sum::<f64>();
    (sum, scale)
}

#[test]
fn node_matched_faces_pressed_give_eps_n_p_area_per_node() {
    let delta = 2.4e-6; // m: p_N = ε_n δ = 5.04e4 Pa
    let mut c = faces(4, H, 4, H, 0.0, -delta);
    let mut pass = new_pass(&c);
    run(&mut c, &mut pass, &params(0.0), &[]);
    for (&i, sign) in c
        .lower
        .iter()
        .map(|i| (i, -1.0))
        .chain(c.upper.iter().map(|i| (i, 1.0)))
    {
        let a = pass.state.at(i as usize).area;
        let expected = sign * EPS * delta * a; // upper nodes pushed up (+y), lower down
        let fy = pass.f[i as usize].y;
        assert!(
            (fy - expected).abs() <= 1e-12 * expected.abs(),
            "node {i}: {fy} vs {expected}"
        );
        assert!(pass.f[i as usize].x.abs() <= 1e-12 * expected.abs());
        assert!((pass.state.at(i as usize).penetration - delta).abs() < 1e-15);
    }
    assert_eq!(pass.state.at(c.upper[0] as usize).area, 0.5 * H);
    assert!((pass.state.at(c.upper[2] as usize).area - H).abs() < 1e-18);
    assert_eq!(pass.summary.contacts, 10);
}

#[test]
fn non_matching_faces_offset_carry_uniform_force_at_interior_nodes() {
    let delta = 2.4e-6;
    let mut c = faces(10, H, 9, H, 0.37 * H, -delta);
    let mut pass = new_pass(&c);
    run(&mut c, &mut pass, &params(0.0), &[]);
    // Interior upper nodes see ½ ε_n δ h as slaves + ½ Σ_k N_j(ξ_k) ε_n δ h = ½ ε_n δ h as masters.
    for &i in &c.upper[1..c.upper.len() - 1] {
        let expected = EPS * delta * H;
        assert!((pass.f[i as usize].y - expected).abs() < 1e-9 * expected);
    }
    let (sum, scale) = total(&pass.f);
    assert!(sum.norm() <= 1e-14 * scale);
}

#[test]
fn forces_sum_to_zero_with_unequal_areas_and_friction() {
    // Unequal spacings, offset, tilted contact with friction sliding: Σ f = 0 (action = reaction).
    let mut c = faces(7, H, 5, 1.37 * H, 0.21 * H, -1e-6);
    for (k, &i) in c.upper.iter().enumerate() {
        c.x[i as usize].y -= 1e-7 * k as f64;
    }
    let mut pass = new_pass(&c);
    let p = params(0.3);
    for _ in 0..5 {
        run(&mut c, &mut pass, &p, &[]);
        let (sum, scale) = total(&pass.f);
        assert!(
            scale > 0.0 && sum.norm() <= 1e-14 * scale,
            "Σf = {sum:?}, scale {scale}"
        );
        for &i in &c.upper {
            c.x[i as usize].x += 2e-7;
        }
    }
    assert!(pass.summary.friction_dissipation > 0.0);
}

#[test]
fn tied_twins_never_pair() {
    let mut c = faces(4, H, 4, H, 0.0, -1e-6);
    let mut twins = vec![NO_TWIN; c.x.len()];
    let (lo, up) = (c.lower[2], c.upper[2]);
    twins[lo as usize] = up;
    twins[up as usize] = lo;
    let mut pass = new_pass(&c);
    run(&mut c, &mut pass, &params(0.0), &twins);
    assert!(!pass.state.at(up as usize).in_contact && !pass.state.at(lo as usize).in_contact);
    assert!(pass.state.at(c.upper[1] as usize).in_contact && pass.state.at(c.lower[3] as usize).in_contact);
}

#[test]
fn node_behind_bulk_farther_than_max_gap_is_not_paired() {
    // Upper face 1.5 h below the lower face: facing normals, in range, but |g| > d_max = h.
    let mut c = faces(4, H, 4, H, 0.3 * H, -1.5 * H);
    let mut pass = new_pass(&c);
    run(&mut c, &mut pass, &params(0.0), &[]);
    assert_eq!(pass.summary.contacts, 0);
    assert!(pass.f.iter().all(|f| *f == Vector2::zeros()));
    // ... and none is lost silently: upper nodes 0-3 (x = 0.3 h ... 3.3 h) and lower nodes 1-4
    // face a segment within the projection tolerance, 1.5 h deep; the rest project outside
    assert_eq!(
        pass.summary.dropped, 8,
        "every facing node deeper than d_max is counted"
    );
    // separated faces (the same faces 1.5 h apart, not penetrating) are not contacts at all
    let mut apart = faces(4, H, 4, H, 0.3 * H, 1.5 * H);
    let mut pass = new_pass(&apart);
    run(&mut apart, &mut pass, &params(0.0), &[]);
    assert_eq!((pass.summary.contacts, pass.summary.dropped), (0, 0));
}

#[test]
fn smallest_penetration_wins_over_the_deepest_candidate() {
    // Slave node 0 with normal −y; two master faces facing it (+y normals): one 0.1 h above
    // (g = −0.1 h), one 0.6 h above (g = −0.6 h, bulk between). The literal arg min g would pick
    // the deeper one; the rule picks the closer one.
    let x = vec![
        Vector2::new(0.5 * H, 0.0),
        Vector2::new(H, 0.0),
        Vector2::new(H, 0.1 * H),
        Vector2::new(0.0, 0.1 * H),
        Vector2::new(H, 0.6 * H),
        Vector2::new(0.0, 0.6 * H),
    ];
    let segments = [[0, 1], [2, 3], [4, 5]];
    let mut grid = BucketGrid::with_capacity(3);
    grid.rebuild(&segments, &x, H, 1e-3);
    let frames = frames_of(&segments, &x);
    let slave = Slave {
        node: 0,
        tied: super::search::UNTIED,
        normal: Vector2::new(0.0, -1.0),
    };
    let limits = Limits {
        max_gap: H,
        projection_tolerance: 1e-3,
    };
    let (e, proj) = closest_master(&slave, &grid, &segments, &frames, &x, &limits).unwrap();
    assert_eq!(e, 1);
    assert!((proj.gap + 0.1 * H).abs() < 1e-15);
    // Same-facing segments (n_i·n_e ≥ 0) are excluded: flip the slave normal.
    let same = Slave {
        normal: Vector2::new(0.0, 1.0),
        ..slave
    };
    assert!(closest_master(&same, &grid, &segments, &frames, &x, &limits).is_none());
}

#[test]
fn grid_search_matches_brute_force() {
    // Pseudo-random segments around two wavy faces; every slave's grid answer equals the answer
    // from a grid with one cell (brute force).
    let mut c = faces(40, 0.9 * H, 37, H, 0.13 * H, -3e-5);
    let mut seed = 12345u64;
    for v in c.x.iter_mut() {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        v.y += 4e-4 * ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5);
    }
    let segments = c.surface.segments();
    let limits = Limits {
        max_gap: H,
        projection_tolerance: 1e-3,
    };
    let mut grid = BucketGrid::with_capacity(segments.len());
    grid.rebuild(segments, &c.x, H, 1e-3);
    let frames = frames_of(segments, &c.x);
    let mut one_cell = BucketGrid::with_capacity(1);
    one_cell.rebuild(segments, &c.x, 1.0, 0.0); // huge margin: one cell holds everything
    assert!(grid.num_entries() < 3 * segments.len());
    let mut found = 0;
    for &node in c.surface.nodes() {
        let normal = if c.upper.contains(&node) { -1.0 } else { 1.0 };
        let slave = Slave {
            node,
            tied: super::search::UNTIED,
            normal: Vector2::new(0.0, normal),
        };
        let a = closest_master(&slave, &grid, segments, &frames, &c.x, &limits);
        let b = closest_master(&slave, &one_cell, segments, &frames, &c.x, &limits);
        assert_eq!(a.map(|r| r.0), b.map(|r| r.0), "node {node}");
        found += usize::from(a.is_some());
    }
    assert!(found > 20, "only {found} contacts");
}

#[test]
fn resolve_does_not_allocate_after_warm_up() {
    let mut c = faces(30, H, 30, H, 0.37 * H, -2e-6);
    let mut pass = new_pass(&c);
    let p = params(0.3);
    run(&mut c, &mut pass, &p, &[]);
    let caps = |pass: &Pass, c: &Faces| {
        (
            pass.ws.grid.capacities(),
            pass.ws.area_sum.capacity(),
            pass.ws.frames.capacity(),
            pass.ws.normal.capacity(),
            pass.state.capacity(),
            c.surface.segments.capacity(),
            c.surface.nodes.capacity(),
            pass.f.capacity(),
        )
    };
    let before = caps(&pass, &c);
    for _ in 0..50 {
        for &k in &c.upper {
            c.x[k as usize].x += 3e-6;
        }
        run(&mut c, &mut pass, &p, &[]);
    }
    assert_eq!(before, caps(&pass, &c));
    assert!(pass.summary.contacts > 50);
}

#[test]
fn a_face_that_joins_later_gets_the_state_of_one_there_from_the_start() {
    // Γ_det grows as facets are inserted: the nodes that join take the places after those already
    // there, and every node's state must be its own, as if the surface had been whole throughout
    let delta = 2.4e-6;
    let mut whole = faces(4, H, 4, H, 0.37 * H, -delta);
    let mut grown = faces(4, H, 4, H, 0.37 * H, -delta);
    let segments = grown.surface.segments().to_vec();
    grown.surface = DetectionSurface::with_capacity(grown.x.len(), segments.len());
    let (first, later) = segments.split_at(4);
    for s in first {
        grown.surface.add_segment(s[0], s[1]);
    }
    let mut pass_whole = new_pass(&whole);
    let mut pass_grown = new_pass(&grown);
    let p = params(0.0);
    run(&mut grown, &mut pass_grown, &p, &[]);
    assert_eq!(
        pass_grown.summary.contacts, 0,
        "the lower face alone has no master"
    );
    for s in later {
        grown.surface.add_segment(s[0], s[1]);
    }
    run(&mut grown, &mut pass_grown, &p, &[]);
    run(&mut whole, &mut pass_whole, &p, &[]);
    assert!(pass_whole.summary.contacts > 5);
    assert_eq!(pass_grown.summary, pass_whole.summary);
    for n in 0..whole.x.len() {
        assert_eq!(pass_grown.state.at(n), pass_whole.state.at(n), "node {n}");
        assert_eq!(pass_grown.f[n], pass_whole.f[n], "node {n}");
    }
}

/// The nodes of N_det come out in increasing node id, each with its own state, whatever the
/// order in which they joined it: at the first and last node of a block of the scan, in a block
/// of its own, and at the mesh's last node. It fails if the ids are offset within or across
/// blocks, if a node is skipped, or if N_det's own order is given.
#[test]
fn the_nodes_of_n_det_come_in_node_order_with_their_states() {
    let num_nodes = 70;
    let mut state = ContactState::new(num_nodes, 8);
    let joined = [47u32, 15, 16, 3, 69, 31, 32];
    state.admit(&joined[..4]);
    state.admit(&joined);
    for (k, &n) in joined.iter().enumerate() {
        state.nodes[state.place[n as usize] as usize].area = k as f64;
    }
    let got: Vec<(usize, f64)> = state.in_node_order().map(|(n, c)| (n, c.area)).collect();
    let mut want: Vec<(usize, f64)> = joined
        .iter()
        .enumerate()
        .map(|(k, &n)| (n as usize, k as f64))
        .collect();
    want.sort_by_key(|&(n, _)| n);
    assert_eq!(got, want);
    assert_eq!(ContactState::new(num_nodes, 8).in_node_order().count(), 0);
}
