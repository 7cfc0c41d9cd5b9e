//! The split of an interface's nodes into twins (and of junctions into one copy per sector):
//! [`split_interface`].

use super::chains::{Chain, Segment};
use super::{EdgeMap, MeshError, UnstructuredMesh, key};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

/// A twinned node: the − side keeps `minus`, the + side uses `plus`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TwinPair {
    /// Original node index (− side).
    pub minus: usize,
    /// New node index (+ side), at the same position.
    pub plus: usize,
}

/// The mesh after [`split_interface`].
#[derive(Debug, Clone, PartialEq)]
pub struct SplitMesh {
    /// The mesh with the twins appended to its nodes.
    pub mesh: UnstructuredMesh,
    /// The twin pairs, in chain order.
    pub twins: Vec<TwinPair>,
    /// Chain nodes left single because the chain does not separate their elements (a crack
    /// tip inside the body), in chain order.
    pub tips: Vec<usize>,
    /// Per junction (in order of its node index), its copies: the original node (the sector of
    /// the smallest element index), then the new node of each other sector.
    pub junctions: Vec<Vec<usize>>,
    /// Per chain, per node: its − and + copies (the same node at a crack tip; at a junction,
    /// the nodes of the sectors on the two sides of the chain's end segment).
    pub columns: Vec<Vec<[usize; 2]>>,
}

/// The most sectors a junction may have: a slave node of the contact search carries at most 7
/// nodes it is tied to.
pub const MAX_JUNCTION_SECTORS: usize = 8;

/// Splits the nodes of `chains` into twins: elements on the − side of a segment keep the
/// original node, elements on the + side get the twin (a new node at the same position).
///
/// A chain node is twinned when the chain separates the elements around it into two fans: every
/// interior chain node, and a chain end on the outer boundary. A chain end inside the body (a
/// crack tip) is not separated (its elements form one fan around it) and stays single, so the
/// crack closes there; it is listed in [`SplitMesh::tips`]. The chains' own line elements keep the
/// − side nodes; other line elements (boundary parts) follow the bulk element they border.
///
/// A **junction** (a node where three or more chain edges meet, where the chains end) gets one
/// copy per sector of its elements between consecutive chain edges: the sector of the smallest
/// element index keeps the node, the others get new nodes (appended after the twins), listed in
/// [`SplitMesh::junctions`]. Chains must not share other nodes.
pub fn split_interface(mesh: &UnstructuredMesh, chains: &[Chain]) -> Result<SplitMesh, MeshError> {
    let edges = mesh.edge_map();
    let (cut, chain_lines) = cut_edges(chains);
    let plan = plan_split(mesh, &edges, &cut, chains)?;

    let mut out = mesh.clone();
    let mut next_tag = mesh.node_tags.iter().copied().max().unwrap_or(0);
    let (twins, twin_of) = make_twins(
        mesh,
        &mut out,
        (&edges, &chain_lines),
        &plan.twinned,
        &mut next_tag,
    );
    let (junctions, copy_in) = split_junctions(
        mesh,
        &mut out,
        (&edges, &chain_lines),
        &plan.sectors,
        &mut next_tag,
    )?;
    let columns = chains
        .iter()
        .map(|c| chain_column(c, &plan.sectors, &twin_of, &copy_in))
        .collect();
    out.refresh_group_nodes();
    Ok(SplitMesh {
        mesh: out,
        twins,
        tips: plan.tips,
        junctions,
        columns,
    })
}

/// The sectors of each junction, by node: the fans of its elements between consecutive cut
/// edges ([`junction_sectors`]).
type Sectors = BTreeMap<usize, Vec<BTreeSet<usize>>>;

/// Per (junction, element of one of its sectors): the node of that sector.
type CopyIn = HashMap<(usize, usize), usize>;

/// What the split does, decided on the unsplit mesh.
struct SplitPlan {
    /// Each node to twin with its + fan (the elements that get the twin), in chain order.
    twinned: Vec<(usize, BTreeSet<usize>)>,
    /// Chain nodes left single (crack tips), in chain order.
    tips: Vec<usize>,
    /// The sectors of each junction.
    sectors: Sectors,
}

/// The edges the chains cut (by (smaller, larger) node pair) and the chains' own line elements.
fn cut_edges(chains: &[Chain]) -> (HashSet<(usize, usize)>, HashSet<usize>) {
    let mut cut: HashSet<(usize, usize)> = HashSet::new();
    let mut chain_lines: HashSet<usize> = HashSet::new();
    for c in chains {
        let n = c.nodes.len();
        for (i, s) in c.segments.iter().enumerate() {
            cut.insert(key(c.nodes[i], c.nodes[(i + 1) % n]));
            chain_lines.insert(s.line);
        }
    }
    (cut, chain_lines)
}

/// The + fan of each chain node on the unsplit mesh, which decides whether it is twinned or a
/// crack tip, and the sectors of each junction (a node of three or more cut edges). A node that
/// two chains share other than at a junction is an error.
fn plan_split(
    mesh: &UnstructuredMesh,
    edges: &EdgeMap,
    cut: &HashSet<(usize, usize)>,
    chains: &[Chain],
) -> Result<SplitPlan, MeshError> {
    let mut cut_at: HashMap<usize, usize> = HashMap::new();
    for &(a, b) in cut {
        *cut_at.entry(a).or_default() += 1;
        *cut_at.entry(b).or_default() += 1;
    }
    let is_junction = |n: usize| cut_at.get(&n).is_some_and(|&k| k >= 3);

    let mut seen: HashSet<usize> = HashSet::new();
    let mut plan = SplitPlan {
        twinned: Vec::new(),
        tips: Vec::new(),
        sectors: BTreeMap::new(),
    };
    for c in chains {
        for (i, &node) in c.nodes.iter().enumerate() {
            if is_junction(node) {
                plan.sectors
                    .entry(node)
                    .or_insert_with(|| junction_sectors(mesh, edges, cut, node));
                continue;
            }
            if !seen.insert(node) {
                return Err(MeshError::ChainsMeet(mesh.node_tags[node]));
            }
            let touching = touching_segments(c, i);
            let seeds = touching.iter().map(|s| s.plus.element).collect();
            let fan = fan_around(mesh, edges, cut, node, seeds);
            if touching.iter().any(|s| fan.contains(&s.minus.element)) {
                plan.tips.push(node);
            } else {
                plan.twinned.push((node, fan));
            }
        }
    }
    Ok(plan)
}

/// The segments of chain `c` touching its node `i`: segments i − 1 and i (cyclically when
/// closed; one of them only at the end of an open chain).
fn touching_segments(c: &Chain, i: usize) -> Vec<&Segment> {
    let m = c.segments.len();
    if c.closed {
        vec![&c.segments[(i + m - 1) % m], &c.segments[i]]
    } else {
        c.segments[i.saturating_sub(1)..(i + 1).min(m)].iter().collect()
    }
}

/// Appends to `out` the twin of each node of `twinned` (tags counting up from `next_tag`) and
/// gives it to the node's + fan; returns the twin pairs and each twinned node's twin.
fn make_twins(
    mesh: &UnstructuredMesh,
    out: &mut UnstructuredMesh,
    (edges, chain_lines): (&EdgeMap, &HashSet<usize>),
    twinned: &[(usize, BTreeSet<usize>)],
    next_tag: &mut u64,
) -> (Vec<TwinPair>, HashMap<usize, usize>) {
    let mut twins = Vec::with_capacity(twinned.len());
    let mut twin_of: HashMap<usize, usize> = HashMap::new();
    for (node, fan) in twinned {
        let twin = out.positions.len();
        *next_tag += 1;
        move_fan(mesh, out, (edges, chain_lines), (*node, twin, *next_tag), fan);
        twin_of.insert(*node, twin);
        twins.push(TwinPair {
            minus: *node,
            plus: twin,
        });
    }
    (twins, twin_of)
}

/// Gives each sector of each junction but the first a new node of `out` (tags counting up from
/// `next_tag`). Returns, per junction, its copies (see [`SplitMesh::junctions`]), and, per
/// (junction, element of a sector), the node of that sector. A junction of more than
/// [`MAX_JUNCTION_SECTORS`] sectors is an error.
fn split_junctions(
    mesh: &UnstructuredMesh,
    out: &mut UnstructuredMesh,
    (edges, chain_lines): (&EdgeMap, &HashSet<usize>),
    sectors: &Sectors,
    next_tag: &mut u64,
) -> Result<(Vec<Vec<usize>>, CopyIn), MeshError> {
    let mut junctions = Vec::with_capacity(sectors.len());
    let mut copy_in: CopyIn = HashMap::new();
    for (&node, fans) in sectors {
        if fans.len() > MAX_JUNCTION_SECTORS {
            return Err(MeshError::JunctionTooWide {
                node: mesh.node_tags[node],
                sectors: fans.len(),
            });
        }
        let mut copies = vec![node];
        for (k, fan) in fans.iter().enumerate() {
            let copy = if k == 0 { node } else { out.positions.len() };
            if k > 0 {
                *next_tag += 1;
                move_fan(mesh, out, (edges, chain_lines), (node, copy, *next_tag), fan);
                copies.push(copy);
            }
            for &e in fan {
                copy_in.insert((node, e), copy);
            }
        }
        junctions.push(copies);
    }
    Ok((junctions, copy_in))
}

/// The − and + copies of each node of chain `c` (see [`SplitMesh::columns`]), from the twin of
/// each twinned node and the sector node of each (junction, element).
fn chain_column(
    c: &Chain,
    sectors: &Sectors,
    twin_of: &HashMap<usize, usize>,
    copy_in: &CopyIn,
) -> Vec<[usize; 2]> {
    let m = c.segments.len();
    let last = c.nodes.len() - 1;
    c.nodes
        .iter()
        .enumerate()
        .map(|(i, &node)| {
            if sectors.contains_key(&node) {
                // a junction is a chain end: its one segment's two sides
                let s = if i == 0 {
                    &c.segments[0]
                } else {
                    &c.segments[m - 1]
                };
                debug_assert!(i == 0 || i == last);
                [
                    copy_in[&(node, s.minus.element)],
                    copy_in[&(node, s.plus.element)],
                ]
            } else {
                [node, twin_of.get(&node).copied().unwrap_or(node)]
            }
        })
        .collect()
}

/// The elements around `node` reached from `seeds` without crossing a `cut` edge.
fn fan_around(
    mesh: &UnstructuredMesh,
    edges: &EdgeMap,
    cut: &HashSet<(usize, usize)>,
    node: usize,
    seeds: Vec<usize>,
) -> BTreeSet<usize> {
    let mut fan: BTreeSet<usize> = BTreeSet::new();
    let mut stack = seeds;
    while let Some(e) = stack.pop() {
        if !fan.insert(e) {
            continue;
        }
        let el = &mesh.elements[e];
        let k = el.nodes.len();
        let at = el.nodes.iter().position(|&x| x == node).unwrap_or(0);
        for other in [el.nodes[(at + 1) % k], el.nodes[(at + k - 1) % k]] {
            if cut.contains(&key(node, other)) {
                continue;
            }
            stack.extend(
                edges[&key(node, other)]
                    .iter()
                    .map(|f| f.element)
                    .filter(|&x| x != e),
            );
        }
    }
    fan
}

/// The sectors of a junction: the fans of its elements between consecutive cut edges, in order of
/// their smallest element index.
fn junction_sectors(
    mesh: &UnstructuredMesh,
    edges: &EdgeMap,
    cut: &HashSet<(usize, usize)>,
    node: usize,
) -> Vec<BTreeSet<usize>> {
    let mut out: Vec<BTreeSet<usize>> = Vec::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        if el.nodes.contains(&node) && !out.iter().any(|f| f.contains(&e)) {
            out.push(fan_around(mesh, edges, cut, node, vec![e]));
        }
    }
    out
}

/// Gives the elements of `fan` the new node `copy` (tag `tag`) in place of `node`, and the line
/// elements other than the chains' that border them.
fn move_fan(
    mesh: &UnstructuredMesh,
    out: &mut UnstructuredMesh,
    (edges, chain_lines): (&EdgeMap, &HashSet<usize>),
    (node, copy, tag): (usize, usize, u64),
    fan: &BTreeSet<usize>,
) {
    debug_assert_eq!(copy, out.positions.len());
    out.positions.push(mesh.positions[node]);
    out.node_tags.push(tag);
    for &e in fan {
        for n in out.elements[e].nodes.iter_mut().filter(|n| **n == node) {
            *n = copy;
        }
    }
    for (l, line) in mesh.lines.iter().enumerate() {
        if chain_lines.contains(&l) || !line.nodes.contains(&node) {
            continue;
        }
        let [a, b] = line.nodes;
        let on_fan = edges
            .get(&key(a, b))
            .is_some_and(|fs| fs.iter().any(|f| fan.contains(&f.element)));
        if on_fan {
            for n in out.lines[l].nodes.iter_mut().filter(|n| **n == node) {
                *n = copy;
            }
        }
    }
}
