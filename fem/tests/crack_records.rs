//! `cracks.csv`: the cracked extent of every interface chain, checked against the tip walk (an
//! independent computation from the same damage), the geometry, and the rule that a crack does
//! not heal; and `tips.csv` only where a pre-crack gives the tips a meaning.

use fem::Scene;
use std::path::Path;

fn scene(name: &str) -> Scene {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../scenes")
            .join(format!("{name}.toml")),
    )
    .unwrap();
    Scene::from_toml_str(&text).unwrap()
}

/// The tiny centre crack grows from its pre-crack on each side. The tip walk (tips.csv) follows
/// the contiguous broken points from the pre-crack and then the damaged ones; the crack records
/// scan every point. So the extremes of the broken points lie between each crack tip and its
/// cohesive-zone tip, compared exactly (both take the same Gauss-point coordinate). A record that
/// mixed up Gauss points and facets, counted a pre-crack facet or lost a chain's coordinate fails
/// here.
#[test]
fn the_broken_extent_of_the_centre_crack_ends_at_its_tips() {
    let s = scene("tiny-fem-center-crack");
    let out = fem::run(&s).unwrap();
    assert_eq!(
        out.cracks.len(),
        out.tips.len(),
        "one chain: one record per sample"
    );
    let crack = s.crack.unwrap();
    // the cohesive facets: the whole width but the pre-crack (whole facets of h, so exact to
    // round-off of the coordinates)
    let width = s.fem.x_range[1] - s.fem.x_range[0];
    let cohesive = width - 2.0 * crack.half_length;
    let h = s.fem.element_size;
    let mut grew = 0;
    let mut ahead = 0;
    let mut last_broken = 0.0;
    for (c, t) in out.cracks.iter().zip(&out.tips) {
        assert_eq!(c.t, t.t);
        assert_eq!(c.chain, 0);
        assert!(
            (c.cohesive_length - cohesive).abs() <= 1e-12 * width,
            "{}",
            c.cohesive_length
        );
        // a broken point stays broken (d never decreases)
        assert!(c.broken_length >= last_broken, "t = {}: the crack healed", c.t);
        last_broken = c.broken_length;
        // half a facet per Gauss point: the lengths are multiples of h/2
        for l in [c.broken_length, c.process_zone_length] {
            let halves = l / (0.5 * h);
            assert!((halves - halves.round()).abs() < 1e-9, "t = {}: {l} m", c.t);
        }
        if c.broken_length == 0.0 {
            assert!(c.broken_from.is_nan() && c.broken_to.is_nan());
            continue;
        }
        grew += 1;
        // the walk's broken points are a subset of the broken points, and the walk's cohesive
        // zone runs on through every damaged point beyond them (broken ones included)
        for (x, lo, hi, what) in [
            (c.broken_to, t.tip_right, t.cz_tip_right, "to"),
            (c.broken_from, t.cz_tip_left, t.tip_left, "from"),
        ] {
            assert!(
                lo <= x && x <= hi,
                "t = {}: broken {what} {x} outside [{lo}, {hi}]",
                c.t
            );
        }
        if c.broken_to != t.tip_right || c.broken_from != t.tip_left {
            // a Gauss point broke ahead of a damaged one behind it
            ahead += 1;
        }
    }
    assert!(
        grew > 5,
        "the crack must grow for the check to mean anything: {grew} samples"
    );
    // measured: 1 of the samples (a point broke one Gauss point ahead of the tip walk)
    println!("{grew} samples with a crack, {ahead} with a broken point ahead of the tips");
    // at the end: the broken points lie between the pre-crack and the tips, half a facet each
    let end = out.cracks.last().unwrap();
    let span = (end.broken_to - crack.center_x - crack.half_length)
        + (crack.center_x - crack.half_length - end.broken_from);
    // each side's walk ends on a Gauss point (1 ± 1/√3)/2 h inside its last broken facet
    assert!(
        (end.broken_length - span).abs() <= h,
        "{} m against {span} m",
        end.broken_length
    );
}

/// Without a pre-crack there is no tip to speak of: no tip records (tips.csv is not written), and
/// the crack records alone tell how far the interface broke. The cohesive pull breaks its whole
/// interface (10 facets of 1 mm).
#[test]
fn without_a_pre_crack_there_are_crack_records_and_no_tips() {
    let s = scene("tiny-fem-cohesive-pull");
    assert!(s.crack.is_none());
    let out = fem::run(&s).unwrap();
    assert!(out.tips.is_empty());
    let end = out.cracks.last().unwrap();
    let width = s.fem.x_range[1] - s.fem.x_range[0];
    assert!((end.cohesive_length - width).abs() <= 1e-12 * width);
    // the sum of 20 half facets against the width: round-off only
    assert!(
        (end.broken_length - end.cohesive_length).abs() <= 1e-12 * width,
        "the pull breaks every point: {} of {} m",
        end.broken_length,
        end.cohesive_length
    );
    let dir = std::env::temp_dir().join(format!("fem-crack-records-{}", std::process::id()));
    let files = fem::write_csv(&out, &dir).unwrap();
    let names: Vec<_> = files
        .iter()
        .map(|p| p.file_name().unwrap().to_str().unwrap())
        .collect();
    assert!(
        names.contains(&"cracks.csv") && !names.contains(&"tips.csv"),
        "{names:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `crack_tips.csv` on the grid: the crack that holds the pre-crack is the one the tip walk
/// (tips.csv) follows, so its four tips equal the walk's at every sample. Both take the same
/// Gauss-point coordinates; where nothing has broken yet the walk starts from x_c ± a and the
/// record from the pre-crack's end node, equal to round-off of the node coordinates (1e-12 of
/// the width).
#[test]
fn the_crack_that_holds_the_pre_crack_has_the_tip_walks_tips() {
    let s = scene("tiny-fem-center-crack");
    let out = fem::run(&s).unwrap();
    let crack = s.crack.unwrap();
    let tol = 1e-12 * (s.fem.x_range[1] - s.fem.x_range[0]);
    let mut others = 0;
    for t in &out.tips {
        let now: Vec<_> = out.crack_tips.iter().filter(|r| r.t == t.t).collect();
        let holds = |r: &&&fem::CrackTipRecord| r.tip_start <= crack.center_x && crack.center_x <= r.tip_end;
        let mut it = now.iter().filter(holds);
        let r = it.next().expect("a crack holds the pre-crack");
        assert!(it.next().is_none(), "t = {}: two cracks hold the pre-crack", t.t);
        for (a, b, what) in [
            (r.tip_start, t.tip_left, "left tip"),
            (r.tip_end, t.tip_right, "right tip"),
            (r.cz_start, t.cz_tip_left, "left cohesive-zone tip"),
            (r.cz_end, t.cz_tip_right, "right cohesive-zone tip"),
        ] {
            assert!((a - b).abs() <= tol, "t = {}: {what} {a} against {b}", t.t);
        }
        others += now.len() - 1;
    }
    // measured: 4 records beside the main crack over the run (at one sample a process zone at
    // each end of the interface, at another a single broken point one Gauss point ahead of each
    // tip)
    println!("{others} records beside the crack that holds the pre-crack");
}

/// The crack records against their definition, checked on the damage of every Gauss point
/// (interface.csv's records, in chain order) for each chain and sample: each crack is a stretch of
/// broken points whose outer neighbours are not broken, inside a run of damaged points whose outer
/// neighbours are undamaged; every broken point lies in exactly one crack, every damaged point in
/// one run; a process zone holds no broken point. On a closed chain (the inclusion's circle, which
/// breaks all round) the neighbours wrap round the chain.
fn check_crack_tips(name: &str, closed: bool) -> (usize, usize) {
    let s = scene(name);
    let out = fem::run(&s).unwrap();
    let (mut cracks, mut wrapped) = (0, 0);
    let mut times: Vec<f64> = out.cracks.iter().map(|r| r.t).collect();
    times.dedup();
    for &t in &times {
        let chains = out.cracks.iter().filter(|r| r.t == t).count();
        for k in 0..chains as u16 {
            let points: Vec<_> = out
                .interface
                .iter()
                .filter(|p| p.t == t && p.chain.unwrap_or(0) == k)
                .collect();
            let n = points.len();
            let at = |x: f64| {
                points
                    .iter()
                    .position(|p| p.x == x)
                    .unwrap_or_else(|| panic!("t = {t}: {x} is no Gauss point of chain {k}"))
            };
            // the points from i to j along the chain (wrapping on a closed chain)
            let stretch = |i: usize, j: usize| -> Vec<usize> {
                assert!(closed || i <= j, "t = {t}: a stretch from {i} back to {j}");
                (0..=(j + n - i) % n).map(|d| (i + d) % n).collect()
            };
            let outside = |i: usize, j: usize| -> Vec<usize> {
                if closed {
                    if (j + 1) % n == i {
                        vec![]
                    } else {
                        vec![(i + n - 1) % n, (j + 1) % n]
                    }
                } else {
                    [i.checked_sub(1), (j + 1 < n).then_some(j + 1)]
                        .into_iter()
                        .flatten()
                        .collect()
                }
            };
            let records: Vec<_> = out
                .crack_tips
                .iter()
                .filter(|r| r.t == t && r.chain == k)
                .collect();
            let (mut broken, mut damaged) = (0, 0);
            let mut runs = std::collections::BTreeSet::new();
            for r in &records {
                let (j0, j1) = (at(r.cz_start), at(r.cz_end));
                let run = stretch(j0, j1);
                assert!(
                    run.iter().all(|&i| points[i].damage > 0.0),
                    "t = {t}: an undamaged point in {r:?}"
                );
                assert!(
                    outside(j0, j1).iter().all(|&i| points[i].damage == 0.0),
                    "t = {t}: the run of {r:?} goes on"
                );
                if runs.insert((j0, j1)) {
                    damaged += run.len();
                }
                if r.tip_start.is_nan() {
                    assert!(
                        r.tip_end.is_nan() && run.iter().all(|&i| points[i].damage < 1.0),
                        "t = {t}: {r:?}"
                    );
                    continue;
                }
                let (i0, i1) = (at(r.tip_start), at(r.tip_end));
                let crack = stretch(i0, i1);
                assert!(
                    crack.iter().all(|&i| points[i].damage >= 1.0),
                    "t = {t}: an unbroken point in {r:?}"
                );
                assert!(
                    crack.iter().all(|i| run.contains(i)),
                    "t = {t}: {r:?} outside its run"
                );
                assert!(
                    outside(i0, i1).iter().all(|&i| points[i].damage < 1.0),
                    "t = {t}: the crack of {r:?} goes on"
                );
                broken += crack.len();
                cracks += 1;
                wrapped += usize::from(i1 < i0);
            }
            assert_eq!(
                broken,
                points.iter().filter(|p| p.damage >= 1.0).count(),
                "t = {t}, chain {k}: broken points"
            );
            assert_eq!(
                damaged,
                points.iter().filter(|p| p.damage > 0.0).count(),
                "t = {t}, chain {k}: damaged points"
            );
            assert!(
                records.windows(2).all(|w| w[1].crack == w[0].crack + 1)
                    && records.first().is_none_or(|r| r.crack == 0),
                "t = {t}: the cracks' ranks"
            );
        }
    }
    (cracks, wrapped)
}

/// Without a pre-crack, on open chains meeting at a T and on a closed one: every crack and process
/// zone of every chain (what tips.csv cannot give without a pre-crack).
#[test]
fn every_crack_of_every_chain_has_its_tips() {
    let (cracks, _) = check_crack_tips("tiny-fem-t-junction", false);
    assert!(
        cracks > 50,
        "the T's chains must crack for the check to mean anything: {cracks}"
    );
    let (cracks, wrapped) = check_crack_tips("tiny-fem-inclusion", true);
    // the circle breaks all round, across its first node: the wrap is exercised
    assert!(
        cracks > 50 && wrapped > 10,
        "{cracks} cracks, {wrapped} across the first node"
    );
    println!("inclusion: {cracks} crack records, {wrapped} across the chain's first node");
}
