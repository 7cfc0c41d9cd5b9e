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
