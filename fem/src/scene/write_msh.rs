//! The built-in grid of a scene written as a Gmsh MSH 4.1 (ASCII) mesh, so that a user can start
//! from it in Gmsh, and so that the Gmsh path can be checked against the built-in one on the same
//! mesh. The node row y = 0 is written once (the reader's split twins it again).
//!
//! Physical groups: `body` (every Q4), `crack` (the facets of y = 0 with |x − x_c| < a), `interface`
//! (the other facets of y = 0, when the scene has an `[interface]`), and `bottom`, `right`, `top`,
//! `left` (the sides). Coordinates are written in Rust's shortest round-trip form, so they read
//! back to the same bits.

use crate::mesh::structured::{Grid, GridSpec};
use crate::scene::Scene;
use std::fmt::Write;

/// The MSH 4.1 text of the scene's built-in grid (flat or mapped); `None` for a scene on a mesh.
pub fn grid_as_msh(scene: &Scene) -> Option<String> {
    let f = &scene.fem;
    if f.mesh.is_some() {
        return None;
    }
    let h = f.element_size;
    let nx = ((f.x_range[1] - f.x_range[0]) / h).round() as usize;
    let ny = ((f.y_range[1] - f.y_range[0]) / h).round() as usize;
    let jc = (-f.y_range[0] / h).round() as usize;
    let row_map = |x: f64| f.interface_y(x);
    let grid = Grid::new(&GridSpec {
        x_range: f.x_range,
        y_range: f.y_range,
        nx,
        ny,
        twinned_row: None,
        upper_shift: 0.0,
        row_map: f
            .interface_polyline
            .as_ref()
            .map(|_| (jc, &row_map as &dyn Fn(f64) -> f64)),
    });
    let curves = curves(scene, &grid, [nx, ny], jc);
    Some(msh_text(&grid, &curves, f.x_range, f.y_range))
}

/// A physical curve: its name and its line elements as (first, second) node tags.
type Curve<'a> = (&'a str, Vec<(usize, usize)>);

/// The physical curves of the grid of nx × ny elements whose row jc is the interface row: the
/// crack and interface facets of that row, and the four sides counter-clockwise; empty ones left
/// out.
fn curves<'a>(scene: &Scene, grid: &Grid, [nx, ny]: [usize; 2], jc: usize) -> Vec<Curve<'a>> {
    let w = nx + 1;
    let tag = |l: usize, i: usize| l * w + i + 1;
    let crack = scene.crack.map(|c| (c.center_x, c.half_length));
    // (name, line elements as node tag pairs)
    let mut crack_lines = Vec::new();
    let mut iface_lines = Vec::new();
    for i in 0..nx {
        let mid = 0.5 * (grid.x0[tag(jc, i) - 1].x + grid.x0[tag(jc, i + 1) - 1].x);
        let pair = (tag(jc, i), tag(jc, i + 1));
        if crack.is_some_and(|(xc, a)| (mid - xc).abs() < a) {
            crack_lines.push(pair);
        } else if scene.interface.is_some() {
            iface_lines.push(pair);
        }
    }
    let curves: Vec<Curve> = vec![
        ("crack", crack_lines),
        ("interface", iface_lines),
        ("bottom", (0..nx).map(|i| (tag(0, i), tag(0, i + 1))).collect()),
        ("right", (0..ny).map(|l| (tag(l, nx), tag(l + 1, nx))).collect()),
        (
            "top",
            (0..nx).rev().map(|i| (tag(ny, i + 1), tag(ny, i))).collect(),
        ),
        (
            "left",
            (0..ny).rev().map(|l| (tag(l + 1, 0), tag(l, 0))).collect(),
        ),
    ];
    curves.into_iter().filter(|(_, l)| !l.is_empty()).collect()
}

/// The MSH 4.1 text: the physical names, one entity per curve and the surface over the box
/// `x_range` × `y_range` [m], the nodes, the Q4 elements of `body`, the curves' line elements.
fn msh_text(grid: &Grid, curves: &[Curve], [x0, x1]: [f64; 2], [y0, y1]: [f64; 2]) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n{}\n",
        curves.len() + 1
    );
    for (k, (name, _)) in curves.iter().enumerate() {
        let _ = writeln!(s, "1 {} \"{name}\"", k + 1);
    }
    let body = curves.len() + 1;
    let _ = write!(
        s,
        "2 {body} \"body\"\n$EndPhysicalNames\n$Entities\n0 {} 1 0\n",
        curves.len()
    );
    for k in 0..curves.len() {
        let _ = writeln!(s, "{} {x0} {y0} 0 {x1} {y1} 0 1 {} 0", k + 1, k + 1);
    }
    let _ = write!(s, "1 {x0} {y0} 0 {x1} {y1} 0 1 {body} 0\n$EndEntities\n");
    let nn = grid.num_nodes();
    let _ = write!(s, "$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}\n");
    for t in 1..=nn {
        let _ = writeln!(s, "{t}");
    }
    for p in &grid.x0 {
        let _ = writeln!(s, "{} {} 0", p.x, p.y);
    }
    let ne = grid.num_elements();
    let nl: usize = curves.iter().map(|(_, l)| l.len()).sum();
    let _ = write!(
        s,
        "$EndNodes\n$Elements\n{} {} 1 {}\n2 1 3 {ne}\n",
        curves.len() + 1,
        ne + nl,
        ne + nl
    );
    for e in 0..ne {
        let n = grid.element_nodes(e).map(|n| n + 1);
        let _ = writeln!(s, "{} {} {} {} {}", e + 1, n[0], n[1], n[2], n[3]);
    }
    let mut next = ne + 1;
    for (k, (_, lines)) in curves.iter().enumerate() {
        let _ = writeln!(s, "1 {} 1 {}", k + 1, lines.len());
        for (a, b) in lines {
            let _ = writeln!(s, "{next} {a} {b}");
            next += 1;
        }
    }
    s += "$EndElements\n";
    s
}
