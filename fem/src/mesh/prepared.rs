//! A Gmsh mesh made ready for the cohesive-contact model: the physical groups the scene names
//! given their roles (bulk surfaces, pre-crack and cohesive curves), the interface chain oriented
//! and split into twins, and the interface row built on it with each facet's own geometry
//! (docs/meshes.md, "Scenes on a Gmsh mesh").
//!
//! The pre-crack and cohesive curves form one or several simple chains of mesh edges, which share
//! no node but at a junction (a node where three or more lines meet, where they end; its columns
//! are listed in the row's `junctions`). An open chain ends on the outer boundary, at a crack tip
//! inside the body or at a junction and runs from its end with the smaller x (then the smaller
//! y), so that the + side is on its left (above a horizontal interface, as on the built-in
//! grids); a closed chain runs counter-clockwise from its node with the smaller x (then y), so
//! that its + side, on its left, is the region it encloses. Each chain's columns are measured by
//! the arc length from its first node, plus that node's x; the chains follow each other in the
//! interface row in the order of their smallest line tag.

use crate::mesh::gmsh::{Chain, MeshError, UnstructuredMesh, interface_chains_of, split_interface};
use crate::mesh::interfaces::{FacetKind, InterfaceRow, NO_JUNCTION, column_facets};
use nalgebra::Vector2;
use std::collections::{HashMap, HashSet};

/// The roles of the mesh's physical groups, by name as the scene gives them.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct MeshRoles {
    /// Physical surfaces that make the body; empty: every element.
    pub bulk: Vec<String>,
    /// Physical curves that are free crack faces from t = 0.
    pub pre_crack: Vec<String>,
    /// Physical curves where cohesive elements may be inserted.
    pub interface: Vec<String>,
}

/// Which role's list named the group behind an error: `bulk`, `pre_crack` or `interface`.
#[derive(Debug, Clone, PartialEq)]
pub struct RoleError {
    /// The role (`bulk`, `pre_crack` or `interface`).
    pub role: &'static str,
    /// What is wrong.
    pub error: MeshError,
}

/// The nodes of a boundary part (`[fem.boundary.NAME]`) of a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryNodes {
    /// Node indices, ascending.
    pub nodes: Vec<u32>,
    /// Per node: its tributary length [m] on a curve, 1 on a point [-].
    pub weight: Vec<f64>,
    /// The part is a physical point (dimension 0), not a curve.
    pub point: bool,
}

/// A mesh split along its interface, with the data the model is built from.
#[derive(Debug, Clone)]
pub struct PreparedMesh {
    /// The mesh with the interface's twins appended to its nodes.
    pub mesh: UnstructuredMesh,
    /// Per node: on the outer boundary of the body (twins of a chain end on it too).
    pub outer: Vec<bool>,
    /// Per node: the + copy of a twin pair.
    pub plus: Vec<bool>,
    /// The interface row (`None` without pre-crack and interface curves).
    pub(crate) row: Option<InterfaceRow>,
    /// Smallest element length of the stable step [m].
    pub h_min: f64,
    /// Per facet of the interface row: the index in `MeshRoles::interface` of the curve it lies
    /// on (`u16::MAX` on the pre-crack).
    pub facet_curve: Vec<u16>,
    /// Bounding box [[x_min, x_max], [y_min, y_max]] [m].
    pub bbox: [[f64; 2]; 2],
}

impl PreparedMesh {
    /// Whether the point `p` [m] lies in an element of the body, its edges included (to 1e-9 of
    /// each edge's length): every element is convex and counter-clockwise.
    pub fn contains(&self, p: Vector2<f64>) -> bool {
        let x = &self.mesh.positions;
        self.mesh.elements.iter().any(|e| {
            let n = e.nodes.len();
            (0..n).all(|k| {
                let (a, b) = (x[e.nodes[k]], x[e.nodes[(k + 1) % n]]);
                let (ab, ap) = (b - a, p - a);
                ab.perp(&ap) >= -1e-9 * ab.norm_squared()
            })
        })
    }

    /// Interface-coordinate range [s₀, s₁] [m] of the pre-crack facets (`None`: none), from the
    /// start of the first to the end of the last in the row's order.
    pub fn pre_crack_extent(&self) -> Option<[f64; 2]> {
        let row = self.row.as_ref()?;
        let pre = |c: &FacetKind| *c == FacetKind::PreCrack;
        let (first, last) = (row.kind.iter().position(pre)?, row.kind.iter().rposition(pre)?);
        Some([row.facet_span(first)[0], row.facet_span(last)[1]])
    }

    /// Number of interface chains (0 without an interface).
    pub fn num_chains(&self) -> usize {
        self.row.as_ref().map_or(0, InterfaceRow::num_chains)
    }

    /// The largest |y| [m] of the pre-crack's nodes (0 on a crack along y = 0).
    pub fn pre_crack_max_abs_y(&self) -> f64 {
        let Some(row) = &self.row else { return 0.0 };
        (0..row.num_facets())
            .filter(|&c| row.kind[c] == FacetKind::PreCrack)
            .flat_map(|c| row.facet_columns(c).map(|i| row.minus[i]))
            .map(|n| self.mesh.positions[n as usize].y.abs())
            .fold(0.0, f64::max)
    }

    /// Shortest and mean facet length of the interface [m] (`None` without one).
    pub fn facet_lengths(&self) -> Option<(f64, f64)> {
        let row = self.row.as_ref()?;
        let min = row.length.iter().copied().fold(f64::INFINITY, f64::min);
        Some((min, row.length.iter().sum::<f64>() / row.num_facets() as f64))
    }

    /// Nodes of the boundary part `name` and, per node, the weight of a load on it: on a physical
    /// curve the node's tributary length [m] (half of each adjacent line element of the group), on
    /// a physical point 1 (each point carries the whole force given). A point must not lie on a
    /// node the interface splits.
    pub fn boundary_nodes(&self, name: &str) -> Result<BoundaryNodes, MeshError> {
        let g = self.mesh.group(name)?;
        match g.dim {
            0 => {
                let split: HashSet<u32> = self.row.as_ref().map_or_else(HashSet::new, |row| {
                    row.minus
                        .iter()
                        .zip(&row.plus)
                        .filter(|(m, p)| m != p)
                        .flat_map(|(&m, &p)| [m, p])
                        .collect()
                });
                if let Some(&n) = g.nodes.iter().find(|&&n| split.contains(&(n as u32))) {
                    let x = self.mesh.positions[n];
                    return Err(MeshError::PointOnInterface {
                        group: name.to_string(),
                        node: self.mesh.node_tags[n],
                        x: x.x,
                        y: x.y,
                    });
                }
                Ok(BoundaryNodes {
                    nodes: g.nodes.iter().map(|&n| n as u32).collect(),
                    weight: vec![1.0; g.nodes.len()],
                    point: true,
                })
            }
            _ => {
                let (nodes, weight) = self.curve_nodes(name)?;
                Ok(BoundaryNodes {
                    nodes,
                    weight,
                    point: false,
                })
            }
        }
    }

    /// Nodes of the physical curve `name` and, per node, its tributary length [m] (half of each
    /// adjacent line element of the group).
    fn curve_nodes(&self, name: &str) -> Result<(Vec<u32>, Vec<f64>), MeshError> {
        let g = self.mesh.group_of_dim(
            name,
            1,
            "a boundary part is a physical curve (dimension 1) or point (dimension 0)",
        )?;
        let mut weight = vec![0.0; g.nodes.len()];
        for &l in &g.elements {
            let [a, b] = self.mesh.lines[l].nodes;
            let half = 0.5 * (self.mesh.positions[b] - self.mesh.positions[a]).norm();
            g.add_to_ends([a, b], half, &mut weight);
        }
        Ok((g.nodes.iter().map(|&n| n as u32).collect(), weight))
    }
}

/// Gives the groups their roles, checks them, orients and splits the interface chain.
pub fn prepare(mesh: UnstructuredMesh, roles: &MeshRoles) -> Result<PreparedMesh, RoleError> {
    let role = |role: &'static str| move |error: MeshError| RoleError { role, error };
    check_bulk(&mesh, &roles.bulk).map_err(role("bulk"))?;
    let mut curves: Vec<&str> = Vec::new();
    for (key, names) in [("pre_crack", &roles.pre_crack), ("interface", &roles.interface)] {
        for name in names {
            mesh.group_of_dim(
                name,
                1,
                "a crack or an interface is a physical curve (dimension 1)",
            )
            .map_err(role(key))?;
            curves.push(name);
        }
    }
    let outer_before = mesh.outer_nodes();
    let h_min = crate::mesh::lengths::min_element_length(&mesh);
    let bbox = bounding_box(&mesh.positions);
    if curves.is_empty() {
        let n = mesh.positions.len();
        return Ok(PreparedMesh {
            mesh,
            outer: outer_before,
            plus: vec![false; n],
            row: None,
            h_min,
            facet_curve: Vec::new(),
            bbox,
        });
    }
    let key = if roles.interface.is_empty() {
        "pre_crack"
    } else {
        "interface"
    };
    let chains: Vec<Chain> = interface_chains_of(&mesh, &curves)
        .map_err(role(key))?
        .into_iter()
        .map(|c| oriented(&mesh.positions, c))
        .collect();
    let pre_lines: HashSet<usize> = roles
        .pre_crack
        .iter()
        .flat_map(|name| mesh.groups[name].elements.iter().copied())
        .collect();
    let mut curve_of_line: HashMap<usize, u16> = HashMap::new();
    for (k, name) in roles.interface.iter().enumerate() {
        for &l in &mesh.groups[name].elements {
            curve_of_line.insert(l, k as u16);
        }
    }
    let facet_curve = chains
        .iter()
        .flat_map(|chain| &chain.segments)
        .map(|s| curve_of_line.get(&s.line).copied().unwrap_or(u16::MAX))
        .collect();
    let split = split_interface(&mesh, &chains).map_err(role(key))?;
    let n = split.mesh.positions.len();
    let mut outer = outer_before;
    let mut plus = vec![false; n];
    outer.resize(n, false);
    for t in &split.twins {
        outer[t.plus] = outer[t.minus];
        plus[t.plus] = true;
    }
    for copies in &split.junctions {
        for &c in &copies[1..] {
            outer[c] = outer[copies[0]];
            plus[c] = true;
        }
    }
    let mut row = row_of(&split.mesh, &chains, &split.columns, &pre_lines);
    for copies in &split.junctions {
        let cols: Vec<u32> = (0..row.minus.len() as u32)
            .filter(|&i| copies.contains(&(row.minus[i as usize] as usize)))
            .collect();
        for &i in &cols {
            row.col_junction[i as usize] = row.junctions.len() as u32;
        }
        row.junctions.push(cols);
    }
    Ok(PreparedMesh {
        mesh: split.mesh,
        outer,
        plus,
        row: Some(row),
        h_min,
        facet_curve,
        bbox,
    })
}

/// Every element must lie in one of the listed surfaces (none listed: every element is bulk).
fn check_bulk(mesh: &UnstructuredMesh, bulk: &[String]) -> Result<(), MeshError> {
    if bulk.is_empty() {
        return Ok(());
    }
    let mut covered = vec![false; mesh.elements.len()];
    for name in bulk {
        let g = mesh.group_of_dim(name, 2, "a bulk region is a physical surface (dimension 2)")?;
        for &e in &g.elements {
            covered[e] = true;
        }
    }
    match covered.iter().position(|c| !c) {
        None => Ok(()),
        Some(e) => Err(MeshError::OutsideBulk {
            element: mesh.elements[e].tag,
            groups: bulk.join(", "),
        }),
    }
}

fn bounding_box(x: &[Vector2<f64>]) -> [[f64; 2]; 2] {
    let mut b = [[f64::INFINITY, f64::NEG_INFINITY]; 2];
    for p in x {
        for (k, v) in [p.x, p.y].into_iter().enumerate() {
            b[k][0] = b[k][0].min(v);
            b[k][1] = b[k][1].max(v);
        }
    }
    b
}

/// The chain in the row's direction: an open chain from its end with the smaller (x, y); a closed
/// chain counter-clockwise (its + side, on the left, inside) from its node with the smaller (x, y).
fn oriented(x: &[Vector2<f64>], mut chain: Chain) -> Chain {
    let key = |n: usize| (x[n].x, x[n].y);
    if !chain.closed {
        let last = *chain.nodes.last().expect("invariant: a chain has nodes");
        return if key(last) < key(chain.nodes[0]) {
            chain.reversed()
        } else {
            chain
        };
    }
    // twice the signed area enclosed (shoelace): negative when clockwise
    let m = chain.nodes.len();
    let area2: f64 = (0..m)
        .map(|i| {
            let (a, b) = (x[chain.nodes[i]], x[chain.nodes[(i + 1) % m]]);
            a.x * b.y - b.x * a.y
        })
        .sum();
    if area2 < 0.0 {
        chain = chain.reversed();
    }
    let start = (0..m)
        .min_by(|&i, &j| {
            key(chain.nodes[i])
                .partial_cmp(&key(chain.nodes[j]))
                .expect("invariant: finite positions")
        })
        .expect("invariant: a chain has nodes");
    chain.nodes.rotate_left(start);
    chain.segments.rotate_left(start);
    chain
}

/// The interface row along `chains` of the split mesh, one after the other: the columns of a
/// chain are its nodes in order (the − copy, and the + copy or the node itself at a crack tip);
/// its facets are its segments, facet k joining columns k and k + 1 of the chain (the last facet
/// of a closed chain joining its last column to its first).
fn row_of(
    mesh: &UnstructuredMesh,
    chains: &[Chain],
    columns: &[Vec<[usize; 2]>],
    pre_lines: &HashSet<usize>,
) -> InterfaceRow {
    let x = &mesh.positions;
    let mut row = InterfaceRow {
        kind: Vec::new(),
        minus: Vec::new(),
        plus: Vec::new(),
        elem_minus: Vec::new(),
        elem_plus: Vec::new(),
        face_edges: Vec::new(),
        length: Vec::new(),
        normal: Vec::new(),
        coord: Vec::new(),
        ends: Vec::new(),
        col_facets: Vec::new(),
        chain: Vec::new(),
        junctions: Vec::new(),
        col_junction: Vec::new(),
    };
    for (k, chain) in chains.iter().enumerate() {
        let first = row.minus.len() as u32;
        let m = chain.nodes.len() as u32;
        row.minus.extend(columns[k].iter().map(|c| c[0] as u32));
        row.plus.extend(columns[k].iter().map(|c| c[1] as u32));
        row.chain.extend(std::iter::repeat_n(k as u16, chain.nodes.len()));
        let mut s = x[chain.nodes[0]].x;
        for (i, seg) in chain.segments.iter().enumerate() {
            let (a, b) = (i as u32, (i as u32 + 1) % m);
            let t = x[chain.nodes[b as usize]] - x[chain.nodes[a as usize]];
            row.coord.push(s);
            s += t.norm();
            row.length.push(t.norm());
            row.normal.push(Vector2::new(-t.y, t.x) / t.norm());
            row.ends.push([first + a, first + b]);
            row.kind.push(if pre_lines.contains(&seg.line) {
                FacetKind::PreCrack
            } else {
                FacetKind::Cohesive
            });
            row.elem_minus.push(seg.minus.element as u32);
            row.elem_plus.push(seg.plus.element as u32);
            row.face_edges
                .push([seg.plus.local_edge as u8, seg.minus.local_edge as u8]);
        }
        if !chain.closed {
            row.coord.push(s);
        }
    }
    row.col_facets = column_facets(row.minus.len(), &row.ends);
    row.col_junction = vec![NO_JUNCTION; row.minus.len()];
    row
}

#[cfg(test)]
mod tests {
    use super::*;

    fn prepared(file: &str, interface: &[&str]) -> PreparedMesh {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../meshes")
            .join(file);
        let roles = MeshRoles {
            interface: interface.iter().map(|s| s.to_string()).collect(),
            ..MeshRoles::default()
        };
        prepare(UnstructuredMesh::read(&path).unwrap(), &roles).unwrap()
    }

    #[test]
    fn two_disjoint_chains_share_one_row_but_no_facet() {
        let p = prepared("two-chains.msh", &["left_cut", "right_cut"]);
        let row = p.row.as_ref().unwrap();
        assert_eq!(row.num_chains(), 2);
        for c in 0..row.num_facets() {
            let [a, b] = row.facet_columns(c);
            assert_eq!((b, row.chain[a]), (a + 1, row.chain[b]), "facet {c}");
        }
        // each chain starts at its end with the smaller x, measured from that x
        let first = |k: u16| row.chain.iter().position(|&c| c == k).unwrap();
        assert_eq!(row.coord[first(0)], 0.0);
        assert!((row.coord[first(1)] - 1.2).abs() < 1e-12);
        // a chain's last column ends its last facet and starts none
        let last0 = first(1) - 1;
        assert_eq!(row.column_facets(last0).count(), 1);
        assert!((row.facet_span(last0 - 1)[1] - 0.58f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn a_closed_chain_runs_counter_clockwise_and_closes_on_its_first_column() {
        let p = prepared("inclusion.msh", &["interface"]);
        let row = p.row.as_ref().unwrap();
        let (m, nf) = (row.minus.len(), row.num_facets());
        assert_eq!((row.num_chains(), m), (1, nf));
        assert_eq!(row.ends[nf - 1], [(m - 1) as u32, 0]);
        assert!((0..m).all(|i| row.column_facets(i).count() == 2));
        // from the leftmost node (0.6, 1) m, counter-clockwise: the first facet goes down and the
        // + side, on the left of the direction, is inside (toward the centre (1, 1) m)
        let x = &p.mesh.positions;
        assert!((x[row.minus[0] as usize] - Vector2::new(0.6, 1.0)).norm() < 1e-12);
        assert!(x[row.minus[1] as usize].y < 1.0);
        assert!(row.normal[0].x > 0.9);
        // the closing facet ends at the chain's arc length, not back at its start
        let length: f64 = row.length.iter().sum();
        assert!((row.facet_span(nf - 1)[1] - (0.6 + length)).abs() < 1e-12);
        // every column is a twin pair: the loop has no tip
        assert!((0..m).all(|i| row.minus[i] != row.plus[i]));
    }

    #[test]
    fn a_t_junction_ends_three_chains_whose_copies_untie_as_its_facets_open() {
        use crate::mesh::interfaces::{in_ring, tie_junction};
        let p = prepared("t-junction.msh", &["interface", "branch"]);
        let row = p.row.as_ref().unwrap();
        assert_eq!((row.num_chains(), row.junctions.len()), (3, 1));
        let cols: Vec<usize> = row.junctions[0].iter().map(|&i| i as usize).collect();
        assert_eq!(cols.len(), 3);
        let x = &p.mesh.positions;
        for &i in &cols {
            assert_eq!(row.col_junction[i], 0);
            assert!((x[row.minus[i] as usize] - Vector2::new(1.0, 0.5)).norm() < 1e-12);
            assert_ne!(row.minus[i], row.plus[i]);
        }
        // one copy per sector: below, upper left, upper right
        let mut copies: Vec<u32> = cols.iter().flat_map(|&i| [row.minus[i], row.plus[i]]).collect();
        copies.sort_unstable();
        copies.dedup();
        assert_eq!(copies.len(), 3);
        let facet_at = |i: usize| row.column_facets(i).next().unwrap();
        let mut tied = vec![u32::MAX; x.len()];
        let mut inserted = vec![false; row.num_facets()];
        let group = |tied: &[u32], a: u32| {
            copies
                .iter()
                .filter(|&&b| b == a || in_ring(tied, a as usize, b))
                .count()
        };
        tie_junction(row, &inserted, 0, &mut tied);
        assert!(copies.iter().all(|&c| group(&tied, c) == 3));
        // open the facets at the junction one by one: the copies still joined through a closed
        // facet stay tied
        let mut sizes = Vec::new();
        for &i in &cols {
            inserted[facet_at(i)] = true;
            tie_junction(row, &inserted, 0, &mut tied);
            let mut s: Vec<usize> = copies.iter().map(|&c| group(&tied, c)).collect();
            s.sort_unstable();
            sizes.push(s);
        }
        assert_eq!(sizes, vec![vec![3, 3, 3], vec![1, 2, 2], vec![1, 1, 1]]);
        assert!(copies.iter().all(|&c| tied[c as usize] == u32::MAX));
    }
}
