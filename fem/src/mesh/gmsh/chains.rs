//! Interface chains: the line elements of physical curves ordered into simple chains, with the
//! bulk element on either side of every segment ([`interface_chains`], [`Chain`]).

use super::{EdgeMap, Face, MeshError, UnstructuredMesh, edge_start, key};
use std::collections::{BTreeMap, HashMap, HashSet};

/// One segment of a chain, between `nodes[i]` and `nodes[i + 1]` (cyclically if closed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Segment {
    /// Index into [`UnstructuredMesh::lines`].
    pub line: usize,
    /// Element on the + side (left of the chain direction).
    pub plus: Face,
    /// Element on the − side (right of the chain direction).
    pub minus: Face,
}

/// An ordered simple chain of mesh edges of an interface.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// Node indices in chain order; a closed chain does not repeat its first node.
    pub nodes: Vec<usize>,
    /// Whether the last node joins the first.
    pub closed: bool,
    /// Segment `i` joins `nodes[i]` and `nodes[i + 1]` (`nodes[0]` for the last of a closed
    /// chain).
    pub segments: Vec<Segment>,
}

impl Chain {
    /// The same chain run the other way: the nodes and segments reversed, each segment's + and −
    /// faces swapped (the + side is the left of the direction of travel).
    pub fn reversed(&self) -> Chain {
        let mut nodes = self.nodes.clone();
        let mut segments: Vec<Segment> = self
            .segments
            .iter()
            .map(|s| Segment {
                line: s.line,
                plus: s.minus,
                minus: s.plus,
            })
            .collect();
        // a closed chain keeps its first node first: the new segment j joins the old nodes
        // m − j and m − j − 1 (mod m), i.e. it is the old segment m − 1 − j, as on an open chain
        if self.closed {
            nodes[1..].reverse();
        } else {
            nodes.reverse();
        }
        segments.reverse();
        Chain {
            nodes,
            closed: self.closed,
            segments,
        }
    }
}

/// The chains of the line elements of physical curve `group`, each ordered and with the bulk
/// element on either side of every segment.
///
/// Rules: every line must be an edge of a bulk element with an element on both sides (a line
/// with one element is a boundary); a node of three or more lines is a junction, where the chains
/// that meet there end; a node of the outer boundary ends one line at most; the lines
/// fall into disjoint simple chains, open or closed, returned separately in order of their
/// smallest line tag. A chain runs in the direction of its smallest-tagged line (Gmsh writes a
/// curve's lines along the curve), so the + side is the left of the curve as drawn in the `.geo`.
pub fn interface_chains(mesh: &UnstructuredMesh, group: &str) -> Result<Vec<Chain>, MeshError> {
    interface_chains_of(mesh, &[group])
}

/// As [`interface_chains`], over the line elements of several physical curves together (a
/// pre-crack and the cohesive interface that continues it form one chain); errors name the
/// groups joined by " + ".
pub fn interface_chains_of(mesh: &UnstructuredMesh, groups: &[&str]) -> Result<Vec<Chain>, MeshError> {
    let lines = joined_lines(mesh, groups)?;
    let group = groups.join(" + ");
    let group = group.as_str();
    let edges = mesh.edge_map();
    check_lines(mesh, &edges, group, &lines)?;
    let walk = Walk {
        mesh,
        at: lines_at(mesh, &lines),
    };
    check_boundary_ends(mesh, &edges, &walk.at, group)?;

    let mut done: HashSet<usize> = HashSet::new();
    let mut chains = Vec::new();
    for &first in &lines {
        if !done.insert(first) {
            continue;
        }
        let (nodes, lines, closed) = walk.chain_from(first, &mut done);
        let segments = segments_of(mesh, &edges, &nodes, &lines);
        chains.push(Chain {
            nodes,
            closed,
            segments,
        });
    }
    Ok(chains)
}

/// The line elements (indices into [`UnstructuredMesh::lines`]) of the physical curves `groups`,
/// ascending; each group must be a curve.
fn joined_lines(mesh: &UnstructuredMesh, groups: &[&str]) -> Result<Vec<usize>, MeshError> {
    let mut lines = Vec::new();
    for &name in groups {
        let g = mesh.group_of_dim(name, 1, "an interface is a physical curve (dimension 1)")?;
        lines.extend(g.elements.iter().copied());
    }
    lines.sort_unstable();
    Ok(lines)
}

/// Checks that each line of the interface `group` is an interior edge (a bulk element on either
/// side), and the only line on its edge.
fn check_lines(
    mesh: &UnstructuredMesh,
    edges: &EdgeMap,
    group: &str,
    lines: &[usize],
) -> Result<(), MeshError> {
    let line_tag = |l: usize| mesh.lines[l].tag;
    let ntag = |n: usize| mesh.node_tags[n];
    let mut seen: HashMap<(usize, usize), usize> = HashMap::new();
    for &l in lines {
        let [a, b] = mesh.lines[l].nodes;
        let faces = edges
            .get(&key(a, b))
            .filter(|_| a != b)
            .ok_or_else(|| MeshError::NotAnEdge {
                group: group.to_string(),
                line: line_tag(l),
                a: ntag(a),
                b: ntag(b),
            })?;
        if faces.len() == 1 {
            return Err(MeshError::OneSided {
                group: group.to_string(),
                line: line_tag(l),
                element: mesh.elements[faces[0].element].tag,
            });
        }
        if let Some(&other) = seen.get(&key(a, b)) {
            return Err(MeshError::DuplicateLine {
                group: group.to_string(),
                line: line_tag(l),
                other: line_tag(other),
            });
        }
        seen.insert(key(a, b), l);
    }
    Ok(())
}

/// The lines at each node of the interface, in the order of `lines`. A node of three or more
/// lines is a junction: the chains end there.
fn lines_at(mesh: &UnstructuredMesh, lines: &[usize]) -> BTreeMap<usize, Vec<usize>> {
    let mut at: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &l in lines {
        for n in mesh.lines[l].nodes {
            at.entry(n).or_default().push(l);
        }
    }
    at
}

/// Checks that a node of the outer boundary (on an edge with one element) ends one line of the
/// interface `group` only; the error names the node of smallest index that ends more.
fn check_boundary_ends(
    mesh: &UnstructuredMesh,
    edges: &EdgeMap,
    at: &BTreeMap<usize, Vec<usize>>,
    group: &str,
) -> Result<(), MeshError> {
    let outer: HashSet<usize> = edges
        .iter()
        .filter(|(_, faces)| faces.len() == 1)
        .flat_map(|(&(a, b), _)| [a, b])
        .collect();
    if let Some((&n, ls)) = at.iter().find(|(n, ls)| ls.len() >= 2 && outer.contains(n)) {
        let p = mesh.positions[n];
        return Err(MeshError::JunctionOnBoundary {
            group: group.to_string(),
            node: mesh.node_tags[n],
            lines: ls.len(),
            x: p.x,
            y: p.y,
        });
    }
    Ok(())
}

/// The lines of an interface around each of its nodes, to walk along its chains.
struct Walk<'a> {
    /// The mesh.
    mesh: &'a UnstructuredMesh,
    /// The interface's lines at each of its nodes ([`lines_at`]).
    at: BTreeMap<usize, Vec<usize>>,
}

impl Walk<'_> {
    /// The line that continues line `l` through node `n`: none at a chain end or a junction.
    fn other_line(&self, n: usize, l: usize) -> Option<usize> {
        let ls = &self.at[&n];
        if ls.len() > 2 {
            return None;
        }
        ls.iter().copied().find(|&m| m != l)
    }

    /// The end of line `l` other than node `n`.
    fn other_end(&self, l: usize, n: usize) -> usize {
        let [a, b] = self.mesh.lines[l].nodes;
        if a == n { b } else { a }
    }

    /// The chain of line `first`: its nodes and lines in the direction of `first`, and whether
    /// it is closed. Every line reached is added to `done`.
    fn chain_from(&self, first: usize, done: &mut HashSet<usize>) -> (Vec<usize>, Vec<usize>, bool) {
        let (mut nodes, mut lines, closed) = self.forward(first, done);
        if !closed {
            let (mut back_nodes, mut back_lines) = self.backward(first, done);
            back_nodes.extend(nodes);
            back_lines.extend(lines);
            (nodes, lines) = (back_nodes, back_lines);
        }
        (nodes, lines, closed)
    }

    /// From line `first` forward through its end node: the nodes (both of `first`'s, then one
    /// per line), the lines, and whether the walk came back to the start (a loop, unless the
    /// start is a junction where the chain ends).
    fn forward(&self, first: usize, done: &mut HashSet<usize>) -> (Vec<usize>, Vec<usize>, bool) {
        let [a, b] = self.mesh.lines[first].nodes;
        let (mut nodes, mut lines) = (vec![a, b], vec![first]);
        let (mut cur, mut last) = (b, first);
        while let Some(l) = self.other_line(cur, last) {
            done.insert(l);
            lines.push(l);
            let n = self.other_end(l, cur);
            // back at the start: a loop, unless the start is a junction where the chain ends
            if n == a && self.at[&a].len() <= 2 {
                return (nodes, lines, true);
            }
            nodes.push(n);
            (cur, last) = (n, l);
        }
        (nodes, lines, false)
    }

    /// From line `first` backward through its start node: the nodes and lines before `first`, in
    /// chain order.
    fn backward(&self, first: usize, done: &mut HashSet<usize>) -> (Vec<usize>, Vec<usize>) {
        let a = self.mesh.lines[first].nodes[0];
        let (mut back_nodes, mut back_lines) = (Vec::new(), Vec::new());
        let (mut cur, mut last) = (a, first);
        while let Some(l) = self.other_line(cur, last) {
            done.insert(l);
            back_lines.push(l);
            let n = self.other_end(l, cur);
            back_nodes.push(n);
            (cur, last) = (n, l);
        }
        back_nodes.reverse();
        back_lines.reverse();
        (back_nodes, back_lines)
    }
}

/// The segments of the chain of `nodes` and `lines` (segment `i` on line `lines[i]`, from
/// `nodes[i]` to the next node, cyclically), each with the element on its left as + face.
fn segments_of(mesh: &UnstructuredMesh, edges: &EdgeMap, nodes: &[usize], lines: &[usize]) -> Vec<Segment> {
    let count = nodes.len();
    lines
        .iter()
        .enumerate()
        .map(|(i, &line)| {
            let p = nodes[i];
            let faces = &edges[&key(p, nodes[(i + 1) % count])];
            let (plus, minus) = if edge_start(mesh, faces[0]) == p {
                (faces[0], faces[1])
            } else {
                (faces[1], faces[0])
            };
            Segment { line, plus, minus }
        })
        .collect()
}
