//! Interface chains: the line elements of physical curves ordered into simple chains, with the
//! bulk element on either side of every segment ([`interface_chains`], [`Chain`]).

use super::{Face, MeshError, PhysicalGroup, UnstructuredMesh, edge_start, key};
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
    let mut lines = Vec::new();
    for &name in groups {
        let g = mesh.group_of_dim(name, 1, "an interface is a physical curve (dimension 1)")?;
        lines.extend(g.elements.iter().copied());
    }
    lines.sort_unstable();
    let group = groups.join(" + ");
    let group = group.as_str();
    let g = PhysicalGroup {
        dim: 1,
        tag: 0,
        elements: lines,
        nodes: Vec::new(),
    };
    let edges = mesh.edge_map();
    let line_tag = |l: usize| mesh.lines[l].tag;
    let ntag = |n: usize| mesh.node_tags[n];

    // Each line: an interior edge, once.
    let mut seen: HashMap<(usize, usize), usize> = HashMap::new();
    for &l in &g.elements {
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

    // A node of three or more lines is a junction: the chains end there.
    let mut at: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &l in &g.elements {
        for n in mesh.lines[l].nodes {
            at.entry(n).or_default().push(l);
        }
    }
    // a node of the outer boundary (on an edge with one element) may end one line only
    let outer: HashSet<usize> = edges
        .iter()
        .filter(|(_, faces)| faces.len() == 1)
        .flat_map(|(&(a, b), _)| [a, b])
        .collect();
    if let Some((&n, ls)) = at.iter().find(|(n, ls)| ls.len() >= 2 && outer.contains(n)) {
        let p = mesh.positions[n];
        return Err(MeshError::JunctionOnBoundary {
            group: group.to_string(),
            node: ntag(n),
            lines: ls.len(),
            x: p.x,
            y: p.y,
        });
    }
    let other_line = |n: usize, l: usize| {
        let ls = &at[&n];
        if ls.len() > 2 {
            return None;
        }
        ls.iter().copied().find(|&m| m != l)
    };
    let other_end = |l: usize, n: usize| {
        let [a, b] = mesh.lines[l].nodes;
        if a == n { b } else { a }
    };

    let mut done: HashSet<usize> = HashSet::new();
    let mut chains = Vec::new();
    for &first in &g.elements {
        if !done.insert(first) {
            continue;
        }
        let [a, b] = mesh.lines[first].nodes;
        let (mut nodes, mut lines) = (vec![a, b], vec![first]);
        let mut closed = false;
        let (mut cur, mut last) = (b, first);
        while let Some(l) = other_line(cur, last) {
            done.insert(l);
            lines.push(l);
            let n = other_end(l, cur);
            // back at the start: a loop, unless the start is a junction where the chain ends
            if n == a && at[&a].len() <= 2 {
                closed = true;
                break;
            }
            nodes.push(n);
            (cur, last) = (n, l);
        }
        if !closed {
            let (mut back_nodes, mut back_lines) = (Vec::new(), Vec::new());
            let (mut cur, mut last) = (a, first);
            while let Some(l) = other_line(cur, last) {
                done.insert(l);
                back_lines.push(l);
                let n = other_end(l, cur);
                back_nodes.push(n);
                (cur, last) = (n, l);
            }
            back_nodes.reverse();
            back_lines.reverse();
            back_nodes.extend(nodes);
            back_lines.extend(lines);
            (nodes, lines) = (back_nodes, back_lines);
        }
        let count = nodes.len();
        let segments = lines
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
            .collect();
        chains.push(Chain {
            nodes,
            closed,
            segments,
        });
    }
    Ok(chains)
}
