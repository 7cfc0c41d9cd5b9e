//! The Gmsh reader and the interface topology on the committed meshes of `meshes/` (generated
//! by Gmsh from the `.geo` beside them) and on small broken MSH texts written here.

use fem::gmsh::{Chain, ElementKind, MeshError, UnstructuredMesh, interface_chains, split_interface};
use fem::nalgebra::Vector2;
use std::collections::BTreeSet;
use std::path::PathBuf;

fn path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../meshes")
        .join(name)
}

fn read(name: &str) -> UnstructuredMesh {
    UnstructuredMesh::read(&path(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn text(name: &str) -> String {
    std::fs::read_to_string(path(name)).unwrap()
}

/// Every committed ASCII mesh covers the rectangle [0, 2] × [0, 1] m.
const ASCII: [&str; 4] = ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"];

#[test]
fn areas_sum_to_the_domain_area() {
    for name in ASCII {
        let mesh = read(name);
        let total: f64 = (0..mesh.elements.len()).map(|e| mesh.area(e)).sum();
        // A few hundred shoelace sums of coordinates printed to 16 digits: round-off ≈ 1e-15
        // relative, so 1e-12 relative leaves margin and still catches any missing element.
        assert!((total - 2.0).abs() <= 1e-12 * 2.0, "{name}: area {total}");
        assert!(
            (0..mesh.elements.len()).all(|e| mesh.area(e) > 0.0),
            "{name}: not counter-clockwise"
        );
        assert_eq!(
            mesh.reoriented, 0,
            "{name}: Gmsh writes counter-clockwise elements"
        );
        assert!(mesh.warnings.is_empty(), "{name}: {:?}", mesh.warnings);
        for g in ["bulk", "interface", "bottom", "top", "left", "right"] {
            mesh.group(g).unwrap();
        }
    }
    let kinds = |name: &str| {
        read(name)
            .elements
            .iter()
            .map(|e| e.kind)
            .collect::<BTreeSet<_>>()
    };
    assert_eq!(kinds("rect_tri.msh"), BTreeSet::from([ElementKind::T3]));
    assert_eq!(kinds("rect_quad.msh"), BTreeSet::from([ElementKind::Q4]));
    assert_eq!(
        kinds("rect_mixed.msh"),
        BTreeSet::from([ElementKind::T3, ElementKind::Q4])
    );
}

#[test]
fn ascii_and_binary_give_the_same_mesh() {
    let (a, b) = (read("rect_mixed.msh"), read("rect_mixed_bin.msh"));
    assert_eq!(a.node_tags, b.node_tags);
    assert_eq!(a.elements, b.elements);
    assert_eq!(a.lines, b.lines);
    assert_eq!(a.groups, b.groups);
    // The binary file holds the exact doubles, the ASCII one prints them to 16 significant
    // digits (Gmsh's %.16g): they may differ by one unit in the 16th digit, ≤ 1e-15 of 2 m.
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!((p - q).norm() <= 2e-15, "{p} vs {q}");
    }
}

fn chain(mesh: &UnstructuredMesh, group: &str) -> Chain {
    let mut chains = interface_chains(mesh, group).unwrap();
    assert_eq!(chains.len(), 1, "{group}: one chain");
    chains.remove(0)
}

fn length(mesh: &UnstructuredMesh, c: &Chain) -> f64 {
    c.nodes
        .windows(2)
        .map(|w| (mesh.positions[w[1]] - mesh.positions[w[0]]).norm())
        .sum()
}

/// Both faces of every segment: the + element has the segment as its edge in chain direction,
/// the − element in the opposite direction.
fn check_sides(mesh: &UnstructuredMesh, c: &Chain) {
    let n = c.nodes.len();
    for (i, s) in c.segments.iter().enumerate() {
        let (p, q) = (c.nodes[i], c.nodes[(i + 1) % n]);
        let edge = |f: fem::gmsh::Face| {
            let el = &mesh.elements[f.element].nodes;
            (el[f.local_edge], el[(f.local_edge + 1) % el.len()])
        };
        assert_eq!(edge(s.plus), (p, q));
        assert_eq!(edge(s.minus), (q, p));
        assert_ne!(s.plus.element, s.minus.element);
        assert_eq!(
            mesh.lines[s.line].nodes.iter().collect::<BTreeSet<_>>(),
            BTreeSet::from([&p, &q])
        );
    }
}

#[test]
fn straight_interface_chain_is_ordered_with_an_element_on_each_side() {
    for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh"] {
        let mesh = read(name);
        let c = chain(&mesh, "interface");
        assert!(!c.closed);
        let x: Vec<Vector2<f64>> = c.nodes.iter().map(|&n| mesh.positions[n]).collect();
        // Nodes on y = 0.5 m as printed to 16 digits: 1e-15 m.
        assert!(x.iter().all(|p| (p.y - 0.5).abs() <= 1e-15), "{name}");
        assert!(
            x.windows(2).all(|w| w[1].x > w[0].x),
            "{name}: ordered from x = 0 to x = 2"
        );
        assert_eq!((x[0].x, x[x.len() - 1].x), (0.0, 2.0));
        // Straight: the polyline is the segment itself, up to summing ~20 rounded lengths.
        assert!((length(&mesh, &c) - 2.0).abs() <= 1e-13, "{name}");
        check_sides(&mesh, &c);
        // + is the left of the direction (+x): above the line.
        for s in &c.segments {
            let centroid = |e: usize| {
                let el = &mesh.elements[e].nodes;
                el.iter().map(|&n| mesh.positions[n]).sum::<Vector2<f64>>() / el.len() as f64
            };
            assert!(centroid(s.plus.element).y > 0.5 && centroid(s.minus.element).y < 0.5);
        }
    }
}

#[test]
fn arc_interface_chain_has_the_arc_length_within_the_chord_error() {
    let mesh = read("arc.msh");
    let c = chain(&mesh, "interface");
    check_sides(&mesh, &c);
    let (centre, r) = (Vector2::new(1.0, -1.1), (1.0f64 + 1.5 * 1.5).sqrt());
    // Gmsh puts the nodes on the circle; 16-digit printing: ≤ 1e-14 m off.
    for &n in &c.nodes {
        assert!(((mesh.positions[n] - centre).norm() - r).abs() <= 1e-14);
    }
    assert!(
        c.nodes
            .windows(2)
            .all(|w| mesh.positions[w[1]].x > mesh.positions[w[0]].x)
    );
    let arc = 2.0 * r * (1.0 / r).asin();
    // Chord error: a chord subtending θ is shorter than its arc by R(θ − 2 sin(θ/2)) ≤ Rθ³/24,
    // so the polyline is shorter than the arc by at most arc · θ_max² / 24.
    let theta_max = c
        .nodes
        .windows(2)
        .map(|w| 2.0 * ((mesh.positions[w[1]] - mesh.positions[w[0]]).norm() / (2.0 * r)).asin())
        .fold(0.0, f64::max);
    let bound = arc * theta_max * theta_max / 24.0;
    let poly = length(&mesh, &c);
    assert!(
        poly < arc && arc - poly <= bound,
        "arc {arc} polyline {poly} bound {bound}"
    );
}

#[test]
fn split_twins_the_interface_and_a_translation_of_the_plus_side_opens_it() {
    for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh", "arc.msh"] {
        let mesh = read(name);
        let c = chain(&mesh, "interface");
        let split = split_interface(&mesh, std::slice::from_ref(&c)).unwrap();
        // Both ends are on the outer boundary: every node is twinned.
        assert!(split.tips.is_empty());
        assert_eq!(split.twins.len(), c.nodes.len(), "{name}");
        let m = &split.mesh;
        assert_eq!(m.positions.len(), mesh.positions.len() + c.nodes.len());
        let originals: BTreeSet<usize> = c.nodes.iter().copied().collect();
        for e in 0..m.elements.len() {
            assert!(m.area(e) > 0.0, "{name}: still counter-clockwise");
            // Twins are exact copies of positions: the areas are bit for bit the same.
            assert_eq!(m.area(e), mesh.area(e), "{name}: same shape");
        }
        for s in &c.segments {
            let face = |f: fem::gmsh::Face| {
                let el = &m.elements[f.element].nodes;
                [el[f.local_edge], el[(f.local_edge + 1) % el.len()]]
            };
            let (plus, minus) = (face(s.plus), face(s.minus));
            assert!(
                plus.iter().all(|n| !originals.contains(n)),
                "{name}: + side uses twins"
            );
            assert!(
                minus.iter().all(|n| originals.contains(n)),
                "{name}: − side keeps originals"
            );
            // Coincident faces: same points, opposite directions (exact copies of positions).
            assert_eq!(m.positions[plus[0]], m.positions[minus[1]]);
            assert_eq!(m.positions[plus[1]], m.positions[minus[0]]);
        }
        // No element above the interface still uses an original interface node.
        let plus_elements: BTreeSet<usize> = c.segments.iter().map(|s| s.plus.element).collect();
        for &e in &plus_elements {
            assert!(m.elements[e].nodes.iter().all(|n| !originals.contains(n)));
        }
        // Rigid translation of the + side (the part connected to the + faces once split): the
        // two parts share no node, so the − side does not move and the faces open by d.
        let d = Vector2::new(0.01, 0.2);
        let plus_nodes = connected_nodes(m, c.segments[0].plus.element);
        let minus_nodes = connected_nodes(m, c.segments[0].minus.element);
        assert!(
            plus_nodes.is_disjoint(&minus_nodes),
            "{name}: the interface cuts the body in two"
        );
        let moved: Vec<Vector2<f64>> = (0..m.positions.len())
            .map(|n| {
                if plus_nodes.contains(&n) {
                    m.positions[n] + d
                } else {
                    m.positions[n]
                }
            })
            .collect();
        for t in &split.twins {
            assert_eq!(moved[t.minus], mesh.positions[t.minus], "− side fixed");
            // (x + d) − x rounds once per coordinate: ≤ 1 ulp of 2 m ≈ 4.4e-16 m.
            assert!(
                (moved[t.plus] - moved[t.minus] - d).norm() <= 1e-15,
                "opening = d"
            );
        }
        // Boundary lines follow their element: "left" now has both the original and the twin
        // of the interface end at x = 0.
        let left = &m.groups["left"].nodes;
        let end = split.twins[0];
        assert!(left.contains(&end.minus) && left.contains(&end.plus), "{name}");
    }
}

fn connected_nodes(m: &UnstructuredMesh, seed: usize) -> BTreeSet<usize> {
    let mut nodes: BTreeSet<usize> = m.elements[seed].nodes.iter().copied().collect();
    loop {
        let before = nodes.len();
        for el in &m.elements {
            if el.nodes.iter().any(|n| nodes.contains(n)) {
                nodes.extend(el.nodes.iter().copied());
            }
        }
        if nodes.len() == before {
            return nodes;
        }
    }
}

#[test]
fn an_interior_crack_tip_is_not_twinned() {
    for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh"] {
        let mesh = read(name);
        let c = chain(&mesh, "crack");
        check_sides(&mesh, &c);
        let first = mesh.positions[c.nodes[0]];
        let last = mesh.positions[*c.nodes.last().unwrap()];
        assert_eq!((first, last), (Vector2::new(0.0, 0.25), Vector2::new(1.0, 0.25)));
        let split = split_interface(&mesh, std::slice::from_ref(&c)).unwrap();
        assert_eq!(
            split.tips,
            vec![*c.nodes.last().unwrap()],
            "{name}: the tip at x = 1 m"
        );
        assert_eq!(split.twins.len(), c.nodes.len() - 1, "{name}");
        // The tip stays shared by both faces of the last segment: the crack closes there.
        let s = c.segments.last().unwrap();
        let tip = split.tips[0];
        assert!(split.mesh.elements[s.plus.element].nodes.contains(&tip));
        assert!(split.mesh.elements[s.minus.element].nodes.contains(&tip));
        // Both chains together: disjoint, so they split at once.
        let both = [chain(&mesh, "interface"), c.clone()];
        let split = split_interface(&mesh, &both).unwrap();
        assert_eq!(split.twins.len(), both[0].nodes.len() + c.nodes.len() - 1);
    }
}

// ---- Broken inputs ------------------------------------------------------------------------

/// An n × n grid of unit Q4 on [0, n]² (nodes 1..(n+1)², row by row: node t at ((t−1) mod
/// (n+1), (t−1) div (n+1)); element tags 1..n² row by row), surface 1 in group 1 "bulk", curve 1
/// in group 2 "interface" with the given lines (tag, a, b). Node 5 is lifted to z = `z5`;
/// `extra_block` is a further element block (its header line first).
fn grid_msh(n: usize, z5: f64, lines: &[(u64, u64, u64)], extra_block: &str) -> String {
    let w = n + 1;
    let mut s = format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n1 2 \"interface\"\n2 1 \"bulk\"\n\
         $EndPhysicalNames\n$Entities\n0 1 1 0\n1 0 0 0 {n} {n} 0 1 2 0\n1 0 0 0 {n} {n} 0 1 1 0\n$EndEntities\n"
    );
    s += &format!("$Nodes\n1 {0} 1 {0}\n2 1 0 {0}\n", w * w);
    for t in 1..=w * w {
        s += &format!("{t}\n");
    }
    for t in 0..w * w {
        let z = if t == 4 { z5 } else { 0.0 };
        s += &format!("{} {} {z}\n", t % w, t / w);
    }
    s += "$EndNodes\n";
    let blocks = 2 + usize::from(!extra_block.is_empty());
    let extra_count = extra_block.lines().count().saturating_sub(1);
    s += &format!(
        "$Elements\n{blocks} {} 1 100\n2 1 3 {}\n",
        n * n + lines.len() + extra_count,
        n * n
    );
    for r in 0..n {
        for c in 0..n {
            let a = w * r + c + 1;
            s += &format!("{} {a} {} {} {}\n", n * r + c + 1, a + 1, a + w + 1, a + w);
        }
    }
    s += &format!("1 1 1 {}\n", lines.len());
    for (t, a, b) in lines {
        s += &format!("{t} {a} {b}\n");
    }
    s += extra_block;
    s += "$EndElements\n";
    s
}

fn parse(s: &str) -> Result<UnstructuredMesh, MeshError> {
    UnstructuredMesh::from_msh_bytes(s.as_bytes())
}

const MIDDLE: [(u64, u64, u64); 2] = [(10, 4, 5), (11, 5, 6)];

#[test]
fn the_small_grid_reads_and_its_middle_line_is_an_interface() {
    let mesh = parse(&grid_msh(2, 0.0, &MIDDLE, "")).unwrap();
    assert_eq!(mesh.elements.len(), 4);
    let chains = interface_chains(&mesh, "interface").unwrap();
    assert_eq!(chains.len(), 1);
    assert_eq!(
        chains[0]
            .nodes
            .iter()
            .map(|&n| mesh.node_tags[n])
            .collect::<Vec<_>>(),
        vec![4, 5, 6]
    );
}

#[test]
fn a_missing_group_is_named() {
    let mesh = parse(&grid_msh(2, 0.0, &MIDDLE, "")).unwrap();
    let err = interface_chains(&mesh, "crack").unwrap_err();
    assert_eq!(
        err,
        MeshError::MissingGroup {
            group: "crack".into(),
            available: "bulk, interface".into()
        }
    );
    assert!(err.to_string().contains("\"crack\""));
    let err = interface_chains(&mesh, "bulk").unwrap_err();
    assert!(matches!(err, MeshError::WrongDimension { dim: 2, .. }), "{err}");
}

#[test]
fn a_clockwise_element_is_reoriented_and_counted() {
    // Element 3 written clockwise (4 7 8 5 instead of 4 5 8 7).
    let s = grid_msh(2, 0.0, &MIDDLE, "").replace("3 4 5 8 7\n", "3 4 7 8 5\n");
    let mesh = parse(&s).unwrap();
    assert_eq!(mesh.reoriented, 1);
    assert!(
        (0..4).all(|e| (mesh.area(e) - 1.0).abs() <= 1e-15),
        "unit squares, exact"
    );
    // The same in a Gmsh mesh: reverse the first triangle of rect_tri.msh.
    let t = text("rect_tri.msh");
    let (tag, a, b, c, line) = first_triangle(&t);
    let mesh = parse(&t.replacen(&line, &format!("{tag} {a} {c} {b}"), 1)).unwrap();
    assert_eq!(mesh.reoriented, 1);
    // The reader keeps the first node and reverses the others: [a, c, b] becomes [a, b, c], the
    // triangle as Gmsh wrote it, so the mesh is the original one but for the count.
    assert_eq!(
        mesh,
        UnstructuredMesh {
            reoriented: 1,
            ..read("rect_tri.msh")
        }
    );
}

/// The first triangle line of an ASCII MSH 4.1 text: (tag, a, b, c, the line).
fn first_triangle(t: &str) -> (String, String, String, String, String) {
    let body = t.split("$Elements\n").nth(1).unwrap();
    let mut lines = body.lines().skip(1);
    while let Some(header) = lines.next() {
        let h: Vec<&str> = header.split_whitespace().collect();
        let n: usize = h[3].parse().unwrap();
        if h[2] == "2" {
            let line = lines.next().unwrap().trim_end().to_string();
            let p: Vec<String> = line.split_whitespace().map(String::from).collect();
            return (p[0].clone(), p[1].clone(), p[2].clone(), p[3].clone(), line);
        }
        for _ in 0..n {
            lines.next();
        }
    }
    panic!("no triangle")
}

#[test]
fn a_degenerate_element_is_named() {
    // Element 2 with node 3 moved onto node 2: 2 3 6 5 → 2 2 6 5 (a zero-length edge, a corner
    // of zero area).
    let s = grid_msh(2, 0.0, &MIDDLE, "").replace("2 2 3 6 5\n", "2 2 2 6 5\n");
    let err = parse(&s).unwrap_err();
    assert!(matches!(err, MeshError::Degenerate { element: 2, .. }), "{err}");
    assert!(err.to_string().contains("element 2 "));
    // A triangle of rect_tri.msh collapsed onto one node.
    let t = text("rect_tri.msh");
    let (tag, a, _, c, line) = first_triangle(&t);
    let err = parse(&t.replacen(&line, &format!("{tag} {a} {a} {c}"), 1)).unwrap_err();
    assert!(
        matches!(&err, MeshError::Degenerate { element, .. } if element.to_string() == tag),
        "{err}"
    );
}

#[test]
fn a_junction_ends_the_chains_and_gets_one_copy_per_sector() {
    // A T on the 2 × 2 grid: 4-5-6 across the middle, 5-8 up from its centre node 5.
    let mesh = parse(&grid_msh(2, 0.0, &[(10, 4, 5), (11, 5, 6), (12, 5, 8)], "")).unwrap();
    let chains = interface_chains(&mesh, "interface").unwrap();
    let tags = |c: &Chain| c.nodes.iter().map(|&n| mesh.node_tags[n]).collect::<Vec<_>>();
    assert_eq!(
        chains.iter().map(tags).collect::<Vec<_>>(),
        vec![vec![4, 5], vec![5, 6], vec![5, 8]]
    );
    let split = split_interface(&mesh, &chains).unwrap();
    // the three outer ends are twinned; node 5 gets a copy for each of its three sectors (the
    // two lower quadrangles together, the upper left, the upper right)
    assert!(split.tips.is_empty());
    assert_eq!(split.twins.len(), 3);
    assert_eq!(split.junctions, vec![vec![4, 12, 13]]);
    let copy_in = |e: usize| {
        let nodes = &split.mesh.elements[e].nodes;
        *nodes.iter().find(|n| split.junctions[0].contains(n)).unwrap()
    };
    assert_eq!(copy_in(0), copy_in(1));
    let sectors = [copy_in(0), copy_in(2), copy_in(3)];
    assert!(sectors[0] != sectors[1] && sectors[1] != sectors[2] && sectors[0] != sectors[2]);
    // each chain's end at the junction names the copies on its − and + sides
    let ends = [split.columns[0][1], split.columns[1][0], split.columns[2][0]];
    assert_eq!(ends[0], [sectors[0], sectors[1]]); // left: below | upper left
    assert_eq!(ends[1], [sectors[0], sectors[2]]); // right: below | upper right
    assert_eq!(ends[2], [sectors[2], sectors[1]]); // up: upper right | upper left
}

#[test]
fn a_line_that_is_not_an_element_edge_is_named() {
    let mesh = parse(&grid_msh(2, 0.0, &[(10, 4, 5), (11, 5, 9)], "")).unwrap();
    let err = interface_chains(&mesh, "interface").unwrap_err();
    assert_eq!(
        err,
        MeshError::NotAnEdge {
            group: "interface".into(),
            line: 11,
            a: 5,
            b: 9
        }
    );
}

#[test]
fn a_boundary_line_is_not_an_interface() {
    let mesh = parse(&grid_msh(2, 0.0, &[(10, 1, 2)], "")).unwrap();
    let err = interface_chains(&mesh, "interface").unwrap_err();
    assert_eq!(
        err,
        MeshError::OneSided {
            group: "interface".into(),
            line: 10,
            element: 1
        }
    );
}

#[test]
fn a_second_order_element_is_refused() {
    // A 6-node triangle (type 9) in surface 1.
    let s = grid_msh(2, 0.0, &MIDDLE, "2 1 9 1\n50 1 2 5 1 2 5\n");
    let err = parse(&s).unwrap_err();
    assert!(
        matches!(
            &err,
            MeshError::UnsupportedElement {
                type_id: 9,
                element: 50,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("element type 9"));
}

#[test]
fn a_non_planar_node_is_named() {
    let err = parse(&grid_msh(2, 0.1, &MIDDLE, "")).unwrap_err();
    assert!(matches!(err, MeshError::Not2d { node: 5, .. }), "{err}");
    assert!(err.to_string().starts_with("the mesh is not 2D: node 5"));
    // Far below the tolerance (1e-10 × 2 m) it is accepted: round-off of a planar mesh.
    parse(&grid_msh(2, 1e-14, &MIDDLE, "")).unwrap();
}

#[test]
fn unused_nodes_are_a_warning() {
    // A tenth node, at (3, 3) m, that no element uses.
    let s = grid_msh(2, 0.0, &MIDDLE, "")
        .replace("$Nodes\n1 9 1 9\n2 1 0 9\n", "$Nodes\n1 10 1 10\n2 1 0 10\n")
        .replace("9\n0 0 0\n", "9\n10\n0 0 0\n")
        .replace("2 2 0\n$EndNodes", "2 2 0\n3 3 0\n$EndNodes");
    let mesh = parse(&s).unwrap();
    assert_eq!(
        mesh.warnings,
        vec!["1 node(s) used by no bulk element (tags 10)".to_string()]
    );
}

#[test]
fn garbage_is_a_parse_error_not_a_panic() {
    assert!(matches!(parse("hello"), Err(MeshError::Malformed { .. })));
    // A header declaring 4-byte sizes, and no elements: an error, whatever the reader makes of it.
    let small_size_t =
        "$MeshFormat\n4.1 0 4\n$EndMeshFormat\n$Nodes\n1 1 1 1\n2 1 0 1\n1\n0 0 0\n$EndNodes\n";
    assert_eq!(parse(small_size_t), Err(MeshError::MissingSection("$Elements")));
    let t = text("rect_tri.msh");
    // Cut in the middle of its nodes: the section is not closed.
    assert!(matches!(
        parse(&t[..t.len() / 2]),
        Err(MeshError::Unclosed { .. })
    ));
}

#[test]
fn a_closed_chain_twins_every_node_and_frees_what_it_encloses() {
    // The square around the centre element (tag 5: nodes 6 7 11 10), counter-clockwise.
    let mesh = parse(&grid_msh(
        3,
        0.0,
        &[(20, 6, 7), (21, 7, 11), (22, 11, 10), (23, 10, 6)],
        "",
    ))
    .unwrap();
    let chains = interface_chains(&mesh, "interface").unwrap();
    assert_eq!(chains.len(), 1);
    let c = &chains[0];
    assert!(c.closed);
    assert_eq!(
        c.nodes.iter().map(|&n| mesh.node_tags[n]).collect::<Vec<_>>(),
        vec![6, 7, 11, 10]
    );
    check_sides(&mesh, c);
    // Counter-clockwise loop: the enclosed centre element is on the + (left) side.
    assert!(c.segments.iter().all(|s| mesh.elements[s.plus.element].tag == 5));
    let split = split_interface(&mesh, &chains).unwrap();
    assert!(split.tips.is_empty());
    assert_eq!(split.twins.len(), 4);
    let centre = split.mesh.elements.iter().position(|e| e.tag == 5).unwrap();
    assert_eq!(
        connected_nodes(&split.mesh, centre).len(),
        4,
        "the centre element is cut free"
    );
}

#[test]
fn disjoint_pieces_are_separate_chains_with_their_own_tips() {
    // Two edge cracks: 5-6 from the left side, 12-11 from the right side; each ends inside.
    let mesh = parse(&grid_msh(3, 0.0, &[(30, 5, 6), (31, 12, 11)], "")).unwrap();
    let chains = interface_chains(&mesh, "interface").unwrap();
    let tags = |c: &Chain| c.nodes.iter().map(|&n| mesh.node_tags[n]).collect::<Vec<_>>();
    assert_eq!(
        chains.iter().map(tags).collect::<Vec<_>>(),
        vec![vec![5, 6], vec![12, 11]]
    );
    let split = split_interface(&mesh, &chains).unwrap();
    let tip_tags: Vec<u64> = split.tips.iter().map(|&n| mesh.node_tags[n]).collect();
    let twin_tags: Vec<u64> = split.twins.iter().map(|t| mesh.node_tags[t.minus]).collect();
    assert_eq!((twin_tags, tip_tags), (vec![5, 12], vec![6, 11]));
    // Chains that meet are refused, naming the node.
    let meet = parse(&grid_msh(3, 0.0, &[(30, 5, 6), (31, 6, 7)], "")).unwrap();
    let one = interface_chains(&meet, "interface").unwrap();
    let twice = [one[0].clone(), one[0].clone()];
    assert_eq!(split_interface(&meet, &twice), Err(MeshError::ChainsMeet(5)));
}

#[test]
fn msh_2_2_is_refused() {
    // The same rectangle written by Gmsh in the older MSH 2.2 format.
    let s = text("rect_tri.msh").replacen("4.1 0 8", "2.2 0 8", 1);
    assert!(
        matches!(parse(&s), Err(MeshError::Malformed { ref found, .. }) if found == "2.2 0 8"),
        "{:?}",
        parse(&s).err()
    );
}

#[test]
fn interface_lines_meeting_on_the_outer_boundary_are_refused_with_the_node() {
    // a V of two curves from (1, 0) m on the bottom edge: run before this check, it went through
    // as one chain whose node kept the left and right blocks together (17 391 contacts lost,
    // energy residual 8.6 % of W_ext)
    let mesh = read("v-boundary.msh");
    let err = fem::gmsh::interface_chains_of(&mesh, &["left_cut", "right_cut"]).unwrap_err();
    let MeshError::JunctionOnBoundary {
        group, lines, x, y, ..
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!((group.as_str(), *lines), ("left_cut + right_cut", 2));
    assert!((x - 1.0).abs() < 1e-12 && y.abs() < 1e-12, "({x}, {y})");
    assert!(err.to_string().contains("outer boundary"), "{err}");
    // each curve alone ends at one boundary node: accepted
    assert_eq!(interface_chains(&mesh, "left_cut").unwrap().len(), 1);
}

/// A pressure pushes into the body: on each side of the rectangle [0, 2] × [0, 1] m the weights
/// w_a = −∫ N_a n ds point inward, lie along the side's normal only, and add up to the side's
/// length (exactly the sum of the lines' halves; 1e-12 for the round-off of the coordinates).
/// The same on the Q4 and mixed meshes, whose elements number their edges differently. A curve
/// inside the body has no outward side and is refused naming the group and the line.
#[test]
fn a_pressure_pushes_into_the_body_on_every_side() {
    for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh"] {
        let mesh = read(name);
        for (side, inward, length) in [
            ("bottom", Vector2::new(0.0, 1.0), 2.0),
            ("right", Vector2::new(-1.0, 0.0), 1.0),
            ("top", Vector2::new(0.0, -1.0), 2.0),
            ("left", Vector2::new(1.0, 0.0), 1.0),
        ] {
            let (nodes, w) = mesh.pressure_weights(side).unwrap();
            assert_eq!(nodes.len(), w.len());
            let mut total = Vector2::zeros();
            for wa in &w {
                // along the inward normal only, never outward
                assert!(wa.dot(&inward) > 0.0, "{name} {side}: {wa:?}");
                assert!(
                    (wa - inward * wa.dot(&inward)).norm() <= 1e-15,
                    "{name} {side}: {wa:?}"
                );
                total += wa;
            }
            assert!(
                (total - inward * length).norm() <= 1e-12,
                "{name} {side}: {total:?}"
            );
        }
        match mesh.pressure_weights("interface") {
            Err(e @ MeshError::NotOuter { elements: 2, .. }) => {
                assert!(e.to_string().contains("\"interface\""), "{e}");
            }
            other => panic!("{name}: expected NotOuter, got {other:?}"),
        }
    }
}

/// The dashpots of an absorbing side: ρc_d on the side's normal and ρc_s along it, times each
/// node's tributary length, summing to the side's length; a curve inside the body is refused as
/// for a pressure. A normal and tangent swapped, or a missing half length, would show at once.
#[test]
fn a_dashpot_has_the_normal_impedance_on_the_normal() {
    let (zd, zs) = (3.0, 1.0);
    for name in ["rect_tri.msh", "rect_quad.msh", "rect_mixed.msh"] {
        let mesh = read(name);
        for (side, normal_x, length) in [("bottom", false, 2.0), ("right", true, 1.0), ("top", false, 2.0)] {
            let (nodes, c) = mesh.dashpot_weights(side, &|_| (zd, zs)).unwrap();
            assert_eq!(nodes.len(), c.len());
            let mut total = 0.0;
            for [xx, xy, yy] in &c {
                let w = (xx + yy) / (zd + zs);
                let (cn, ct) = if normal_x { (xx, yy) } else { (yy, xx) };
                assert!(
                    (cn - zd * w).abs() <= 1e-14 && (ct - zs * w).abs() <= 1e-14,
                    "{name} {side}"
                );
                assert!(xy.abs() <= 1e-14, "{name} {side}: {xy}");
                total += w;
            }
            assert!((total - length).abs() <= 1e-12, "{name} {side}: {total}");
        }
        assert!(matches!(
            mesh.dashpot_weights("interface", &|_| (zd, zs)),
            Err(MeshError::NotOuter { elements: 2, .. })
        ));
    }
}
