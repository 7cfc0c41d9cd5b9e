//! Gmsh MSH 4.1 meshes (ASCII and binary) read into a neutral, validated 2D mesh, and the
//! interface topology built on it: chains of line elements along a physical curve, and the split
//! of their nodes into twins. Scenes use them through `[fem.mesh]` (`crate::mesh::prepared`,
//! docs/meshes.md).
//!
//! The file is parsed by the `mshio` crate (header, entities, nodes, elements, both encodings).
//! `mshio` skips the `$PhysicalNames` section, which MSH 4.1 writes as text in both encodings;
//! [`UnstructuredMesh::from_msh_bytes`] reads the names from it (one `dim tag "name"` per line).
//!
//! Conventions: node and element indices are positions in [`UnstructuredMesh::positions`] and
//! [`UnstructuredMesh::elements`]; the tags the user wrote in the file are kept beside them
//! ([`UnstructuredMesh::node_tags`], [`BulkElement::tag`], [`LineElement::tag`]) and every error
//! names those tags. Bulk elements are counter-clockwise; local edge `k` of an element joins its
//! nodes `k` and `k + 1` (cyclically), so the element lies to the left of its edges.

use mshio::{ElementType, MshFile};
use nalgebra::Vector2;
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};
use std::path::Path;
use thiserror::Error;

/// A mesh file that cannot be read, or a mesh or interface that breaks a rule of this module.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeshError {
    /// The file cannot be opened or read.
    #[error("cannot read mesh file {path}: {message}")]
    Io {
        /// The path as given.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The bytes are not a Gmsh MSH 4.1 file (ASCII or binary) that `mshio` understands.
    #[error("the mesh file does not parse as Gmsh MSH 4.1: {0}")]
    Parse(String),
    /// A section the mesh needs is absent.
    #[error("the mesh file has no {0} section")]
    MissingSection(&'static str),
    /// A node off the plane z = 0.
    #[error("the mesh is not 2D: node {node} has z = {z} m (allowed |z| <= {tolerance} m)")]
    Not2d {
        /// Node tag in the file.
        node: u64,
        /// Its z coordinate [m].
        z: f64,
        /// Largest |z| accepted [m].
        tolerance: f64,
    },
    /// An element type other than 2-node lines, 3-node triangles, 4-node quadrangles and points.
    #[error(
        "element type {type_id} ({name}) is not supported (element {element}); supported: \
         1 (2-node line), 2 (3-node triangle), 3 (4-node quadrangle), 15 (point)"
    )]
    UnsupportedElement {
        /// Gmsh element type number.
        type_id: u8,
        /// Gmsh element type name, as `mshio` spells it.
        name: String,
        /// Tag of the first element of that type.
        element: u64,
    },
    /// A node tag defined twice.
    #[error("node {0} is defined twice")]
    DuplicateNode(u64),
    /// An element tag used twice.
    #[error("element {0} is defined twice")]
    DuplicateElement(u64),
    /// An element naming a node the file does not define.
    #[error("element {element} references node {node}, which the file does not define")]
    UnknownNode {
        /// Element tag.
        element: u64,
        /// Node tag.
        node: u64,
    },
    /// A bulk element of zero area, or a quadrangle that is not strictly convex once
    /// counter-clockwise.
    #[error(
        "element {element} is degenerate: area {area} m^2 after orientation, smallest corner \
         area {corner} m^2 (both must exceed {tolerance} m^2)"
    )]
    Degenerate {
        /// Element tag.
        element: u64,
        /// Area after counter-clockwise orientation [m²].
        area: f64,
        /// Smallest corner cross product / 2 [m²] (equals the area for a triangle).
        corner: f64,
        /// Threshold [m²]: 1e-12 × (longest edge)².
        tolerance: f64,
    },
    /// The file holds no triangle or quadrangle.
    #[error("the mesh has no 2D element (triangle or quadrangle)")]
    NoBulk,
    /// More than two bulk elements on one edge.
    #[error("edge {a}-{b} is shared by {count} elements ({elements}); at most two may share an edge")]
    NonManifoldEdge {
        /// Node tag.
        a: u64,
        /// Node tag.
        b: u64,
        /// Number of elements on the edge.
        count: usize,
        /// Their tags, comma-separated.
        elements: String,
    },
    /// Two elements on the same side of their common edge (they overlap).
    #[error("elements {a} and {b} overlap: both lie on the same side of their common edge")]
    Overlap {
        /// Element tag.
        a: u64,
        /// Element tag.
        b: u64,
    },
    /// Two physical groups with one name.
    #[error("physical name \"{0}\" is given to two groups")]
    DuplicateGroupName(String),
    /// A physical group name that the mesh does not have.
    #[error("physical group \"{group}\" is not in the mesh; it has: {available}")]
    MissingGroup {
        /// The name asked for.
        group: String,
        /// The names the mesh has, comma-separated.
        available: String,
    },
    /// A physical group of the wrong dimension for its role.
    #[error("physical group \"{group}\" has dimension {dim}; {expected}")]
    WrongDimension {
        /// Group name.
        group: String,
        /// Its dimension.
        dim: usize,
        /// What the role needs.
        expected: &'static str,
    },
    /// A line of an interface that is not an edge of a bulk element.
    #[error("physical group \"{group}\": line {line} (nodes {a}-{b}) is not an edge of any bulk element")]
    NotAnEdge {
        /// Group name.
        group: String,
        /// Line element tag.
        line: u64,
        /// Node tag.
        a: u64,
        /// Node tag.
        b: u64,
    },
    /// Two lines of an interface on the same edge.
    #[error("physical group \"{group}\": lines {line} and {other} lie on the same edge")]
    DuplicateLine {
        /// Group name.
        group: String,
        /// Line element tag.
        line: u64,
        /// Line element tag.
        other: u64,
    },
    /// A line of a pressure curve that is not on the outer boundary.
    #[error(
        "physical group \"{group}\": line {line} has {elements} bulk elements beside it; a pressure \
         acts on a curve of the outer boundary (one element per line)"
    )]
    NotOuter {
        /// Group name.
        group: String,
        /// Line element tag.
        line: u64,
        /// Bulk elements on the line's edge (0 or 2).
        elements: usize,
    },
    /// A line of an interface with a bulk element on one side only.
    #[error(
        "physical group \"{group}\": line {line} has a bulk element on one side only (element \
         {element}); it is a boundary, not an interface"
    )]
    OneSided {
        /// Group name.
        group: String,
        /// Line element tag.
        line: u64,
        /// Tag of the only element.
        element: u64,
    },
    /// A junction of more sectors than the contact search's ties hold.
    #[error("node {node} is a junction of {sectors} sectors; at most {MAX_JUNCTION_SECTORS} are supported")]
    JunctionTooWide {
        /// Node tag.
        node: u64,
        /// Number of sectors around it.
        sectors: usize,
    },
    /// Interface lines meet at a node of the outer boundary: two lines (a curve through the
    /// boundary, or two curves from one boundary point) or more. Their node would be split into
    /// sectors that the contact search does not tell apart once they open: not supported.
    #[error(
        "physical group \"{group}\": {lines} interface lines meet at node {node} ({x}, {y}) m on \
         the outer boundary; a junction there is not supported: end each curve at a boundary node \
         of its own"
    )]
    JunctionOnBoundary {
        /// Group name.
        group: String,
        /// Node tag.
        node: u64,
        /// Number of interface lines at the node.
        lines: usize,
        /// Node position [m].
        x: f64,
        /// Node position [m].
        y: f64,
    },
    /// A physical point on a node that the interface splits in two: a condition there would
    /// hold one side of the crack only.
    #[error(
        "physical point \"{group}\": node {node} ({x}, {y}) m lies on an interface, whose nodes are \
         split in two at set-up; a point condition there would hold one side only: move the point \
         off the interface"
    )]
    PointOnInterface {
        /// Group name.
        group: String,
        /// Node tag.
        node: u64,
        /// Node position [m].
        x: f64,
        /// Node position [m].
        y: f64,
    },
    /// Two chains given to [`split_interface`] meet at a node.
    #[error("two interface chains share node {0} without a junction there (three or more lines)")]
    ChainsMeet(u64),
    /// A bulk element outside every surface the scene names as bulk.
    #[error("element {element} lies in none of the bulk surfaces {groups}: every element must belong to one")]
    OutsideBulk {
        /// Element tag.
        element: u64,
        /// The bulk surfaces named, comma-separated.
        groups: String,
    },
}

/// Kind of a bulk element.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ElementKind {
    /// Linear triangle (Gmsh type 2).
    T3,
    /// Bilinear quadrangle (Gmsh type 3).
    Q4,
}

/// A bulk (2D) element, counter-clockwise.
#[derive(Debug, Clone, PartialEq)]
pub struct BulkElement {
    /// Element tag in the file.
    pub tag: u64,
    /// T3 or Q4.
    pub kind: ElementKind,
    /// Node indices (3 or 4), counter-clockwise.
    pub nodes: Vec<usize>,
}

/// A 2-node line element (Gmsh type 1), as written in the file (its direction is the curve's).
#[derive(Debug, Clone, PartialEq)]
pub struct LineElement {
    /// Element tag in the file.
    pub tag: u64,
    /// Node indices, start then end.
    pub nodes: [usize; 2],
}

/// A named physical group.
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicalGroup {
    /// 0 (points), 1 (curves) or 2 (surfaces).
    pub dim: usize,
    /// Physical tag in the file.
    pub tag: i32,
    /// Indices into [`UnstructuredMesh::elements`] (dim 2) or [`UnstructuredMesh::lines`]
    /// (dim 1), ascending; empty for dim 0.
    pub elements: Vec<usize>,
    /// Node indices of the group, ascending and unique.
    pub nodes: Vec<usize>,
}

impl PhysicalGroup {
    /// Adds `value` to the entries of `per_node` (one per node of the group, in its order) of the
    /// line ends `ends`.
    pub fn add_to_ends<T: std::ops::AddAssign + Copy>(&self, ends: [usize; 2], value: T, per_node: &mut [T]) {
        for n in ends {
            let k = self
                .nodes
                .binary_search(&n)
                .expect("invariant: a group lists its lines' nodes");
            per_node[k] += value;
        }
    }
}

/// A validated 2D mesh of T3 and Q4 elements with its line elements and physical groups.
#[derive(Debug, Clone, PartialEq)]
pub struct UnstructuredMesh {
    /// Node positions [m], in ascending tag order.
    pub positions: Vec<Vector2<f64>>,
    /// Node tag in the file, per node (twins made by [`split_interface`] get new tags above the
    /// file's largest).
    pub node_tags: Vec<u64>,
    /// Bulk elements, counter-clockwise, in ascending tag order.
    pub elements: Vec<BulkElement>,
    /// Line elements, in ascending tag order.
    pub lines: Vec<LineElement>,
    /// Physical groups by name (groups without a name are left out, with a warning).
    pub groups: BTreeMap<String, PhysicalGroup>,
    /// Number of bulk elements the file gave clockwise and the reader turned counter-clockwise.
    pub reoriented: usize,
    /// Remarks that are not errors (unused nodes, unnamed groups).
    pub warnings: Vec<String>,
}

/// One side of an interface segment: a bulk element and its local edge on the segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Face {
    /// Index into [`UnstructuredMesh::elements`].
    pub element: usize,
    /// Local edge (joins the element's nodes `local_edge` and `local_edge + 1`).
    pub local_edge: usize,
}

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

/// Relative tolerance on z against the in-plane size of the mesh: Gmsh prints coordinates to 16
/// significant digits, so a planar mesh has |z| far below 1e-10 of its size.
const Z_TOLERANCE: f64 = 1e-10;
/// Relative tolerance on element areas against the longest edge squared: a genuine element of a
/// Gmsh mesh is far above it, a collapsed one is at round-off (≈ 1e-16).
const AREA_TOLERANCE: f64 = 1e-12;

impl UnstructuredMesh {
    /// Reads a Gmsh MSH 4.1 file, ASCII or binary.
    pub fn read(path: &Path) -> Result<Self, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| MeshError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_msh_bytes(&bytes)
    }

    /// Scales every node position by `factor` (the length of one unit of the file's
    /// coordinates [m], e.g. 1e-3 for a mesh drawn in millimetres), so that the mesh is in metres.
    /// Orientation, shapes and groups are unchanged: every check of the reader is relative to the
    /// mesh's own size.
    pub fn scale(&mut self, factor: f64) {
        for p in &mut self.positions {
            *p *= factor;
        }
    }

    /// Builds the mesh from the bytes of a Gmsh MSH 4.1 file, ASCII or binary.
    pub fn from_msh_bytes(bytes: &[u8]) -> Result<Self, MeshError> {
        // mshio 0.4 still has a few `unimplemented!`/`expect` on malformed headers: a panic there
        // becomes a parse error here, never a panic of the caller.
        let parsed = std::panic::catch_unwind(|| {
            mshio::parse_msh_bytes(bytes).map_err(|e| MeshError::Parse(e.to_string()))
        })
        .map_err(|_| MeshError::Parse("the MSH reader stopped on a malformed header".into()))??;
        let names = physical_names(bytes)?;
        build(&parsed, &names)
    }

    /// The named physical group.
    pub fn group(&self, name: &str) -> Result<&PhysicalGroup, MeshError> {
        self.groups.get(name).ok_or_else(|| MeshError::MissingGroup {
            group: name.to_string(),
            available: self.groups.keys().cloned().collect::<Vec<_>>().join(", "),
        })
    }

    /// The named physical group, which must have dimension `dim`; `expected` says so in the
    /// error (e.g. "an interface is a physical curve (dimension 1)").
    pub fn group_of_dim(
        &self,
        name: &str,
        dim: usize,
        expected: &'static str,
    ) -> Result<&PhysicalGroup, MeshError> {
        let g = self.group(name)?;
        if g.dim != dim {
            return Err(MeshError::WrongDimension {
                group: name.to_string(),
                dim: g.dim,
                expected,
            });
        }
        Ok(g)
    }

    /// Area of bulk element `e` [m²], positive for a counter-clockwise element.
    pub fn area(&self, e: usize) -> f64 {
        signed_area(&self.elements[e].nodes, &self.positions)
    }

    /// The nodes of the physical curve `name` and, per node, the vector w_a = −∫ N_a n ds [m] over
    /// its line elements (n the outward unit normal, N_a the node's linear shape function along the
    /// line): a pressure p [Pa] pushing on the curve, t = −p n, gives the consistent nodal forces
    /// f_a = p w_a [N/m]. Each line must be on the outer boundary (one bulk element beside it),
    /// which fixes its outward side whatever the line's direction.
    pub fn pressure_weights(&self, name: &str) -> Result<(Vec<usize>, Vec<Vector2<f64>>), MeshError> {
        let g = self.group_of_dim(name, 1, "a boundary part is a physical curve (dimension 1)")?;
        let edges = self.edge_map();
        let mut w = vec![Vector2::zeros(); g.nodes.len()];
        for &l in &g.elements {
            let [a, b] = self.lines[l].nodes;
            let faces = edges.get(&key(a, b)).map_or(&[][..], |f| f.as_slice());
            let [face] = faces else {
                return Err(MeshError::NotOuter {
                    group: name.to_string(),
                    line: self.lines[l].tag,
                    elements: faces.len(),
                });
            };
            // the element runs counter-clockwise, so its edge p → q has the body on its left and
            // the outward normal times the length is (d_y, −d_x)
            let el = &self.elements[face.element].nodes;
            let (p, q) = (el[face.local_edge], el[(face.local_edge + 1) % el.len()]);
            let d = self.positions[q] - self.positions[p];
            let half = -0.5 * Vector2::new(d.y, -d.x);
            g.add_to_ends([a, b], half, &mut w);
        }
        Ok((g.nodes.clone(), w))
    }

    /// Bulk elements on each edge: key (smaller node, larger node) → (element, local edge).
    fn edge_map(&self) -> HashMap<(usize, usize), Vec<Face>> {
        let mut map: HashMap<(usize, usize), Vec<Face>> = HashMap::new();
        for (e, el) in self.elements.iter().enumerate() {
            let n = el.nodes.len();
            for k in 0..n {
                let (a, b) = (el.nodes[k], el.nodes[(k + 1) % n]);
                map.entry(key(a, b)).or_default().push(Face {
                    element: e,
                    local_edge: k,
                });
            }
        }
        map
    }

    /// Recomputes the node lists of the dim-1 and dim-2 groups from their elements.
    fn refresh_group_nodes(&mut self) {
        for g in self.groups.values_mut() {
            let nodes: BTreeSet<usize> = match g.dim {
                2 => g
                    .elements
                    .iter()
                    .flat_map(|&e| self.elements[e].nodes.iter().copied())
                    .collect(),
                1 => g.elements.iter().flat_map(|&l| self.lines[l].nodes).collect(),
                _ => continue,
            };
            g.nodes = nodes.into_iter().collect();
        }
    }
}

fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

fn signed_area(nodes: &[usize], x: &[Vector2<f64>]) -> f64 {
    let n = nodes.len();
    (0..n)
        .map(|k| x[nodes[k]].perp(&x[nodes[(k + 1) % n]]))
        .sum::<f64>()
        / 2.0
}

/// (dim, physical tag) → name, from the `$PhysicalNames` section (text in both encodings).
fn physical_names(bytes: &[u8]) -> Result<HashMap<(usize, i32), String>, MeshError> {
    let mut names = HashMap::new();
    let Some(start) = find(bytes, b"$PhysicalNames") else {
        return Ok(names);
    };
    let body = &bytes[start + b"$PhysicalNames".len()..];
    let end = find(body, b"$EndPhysicalNames")
        .ok_or_else(|| MeshError::Parse("$PhysicalNames has no $EndPhysicalNames".into()))?;
    let text = std::str::from_utf8(&body[..end])
        .map_err(|_| MeshError::Parse("$PhysicalNames is not UTF-8 text".into()))?;
    let bad =
        |line: &str| MeshError::Parse(format!("$PhysicalNames line \"{line}\" is not: dim tag \"name\""));
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()).skip(1) {
        let (Some(q0), Some(q1)) = (line.find('"'), line.rfind('"')) else {
            return Err(bad(line));
        };
        let mut it = line[..q0].split_whitespace();
        let (Some(dim), Some(tag), None) = (it.next(), it.next(), it.next()) else {
            return Err(bad(line));
        };
        let dim: usize = dim.parse().map_err(|_| bad(line))?;
        let tag: i32 = tag.parse().map_err(|_| bad(line))?;
        if q1 <= q0 {
            return Err(bad(line));
        }
        names.insert((dim, tag), line[q0 + 1..q1].to_string());
    }
    Ok(names)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// A bulk element as read: tag, kind, node indices, entity (dim, tag).
type RawBulk = (u64, ElementKind, Vec<usize>, (usize, i32));

/// What a raw element block holds.
enum Raw {
    Bulk(ElementKind),
    Line,
    Point,
}

fn build(
    file: &MshFile<u64, i32, f64>,
    names: &HashMap<(usize, i32), String>,
) -> Result<UnstructuredMesh, MeshError> {
    let nodes = file
        .data
        .nodes
        .as_ref()
        .ok_or(MeshError::MissingSection("$Nodes"))?;
    let elements = file
        .data
        .elements
        .as_ref()
        .ok_or(MeshError::MissingSection("$Elements"))?;

    // Nodes, by tag. With dense tags mshio drops them and numbers the nodes in file order from
    // the smallest tag, as Gmsh writes them.
    let mut raw_nodes: Vec<(u64, [f64; 3])> = Vec::with_capacity(nodes.num_nodes as usize);
    let mut next_tag = nodes.min_node_tag;
    for block in &nodes.node_blocks {
        let tags: Option<Vec<u64>> = block.node_tags.as_ref().map(|map| {
            let mut t = vec![0; block.nodes.len()];
            for (&tag, &i) in map {
                t[i] = tag;
            }
            t
        });
        for (i, n) in block.nodes.iter().enumerate() {
            let tag = match &tags {
                Some(t) => t[i],
                None => next_tag + i as u64,
            };
            raw_nodes.push((tag, [n.x, n.y, n.z]));
        }
        next_tag += block.nodes.len() as u64;
    }
    raw_nodes.sort_by_key(|&(t, _)| t);
    if let Some(w) = raw_nodes.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(MeshError::DuplicateNode(w[0].0));
    }
    let index: HashMap<u64, usize> = raw_nodes.iter().enumerate().map(|(i, &(t, _))| (t, i)).collect();

    // Physical tags of each entity.
    let mut entity_groups: HashMap<(usize, i32), Vec<i32>> = HashMap::new();
    if let Some(ent) = &file.data.entities {
        for p in &ent.points {
            entity_groups.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &ent.curves {
            entity_groups.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &ent.surfaces {
            entity_groups.insert((2, s.tag), s.physical_tags.clone());
        }
    }

    // Elements, with their entity.
    let mut bulk: Vec<RawBulk> = Vec::new();
    let mut lines: Vec<(u64, [usize; 2], (usize, i32))> = Vec::new();
    let mut points: Vec<(u64, usize, (usize, i32))> = Vec::new();
    for block in &elements.element_blocks {
        let raw = match block.element_type {
            ElementType::Tri3 => Raw::Bulk(ElementKind::T3),
            ElementType::Qua4 => Raw::Bulk(ElementKind::Q4),
            ElementType::Lin2 => Raw::Line,
            ElementType::Pnt => Raw::Point,
            other => {
                return Err(MeshError::UnsupportedElement {
                    type_id: other as u8,
                    name: format!("{other:?}"),
                    element: block.elements.first().map_or(0, |e| e.element_tag),
                });
            }
        };
        let entity = (block.entity_dim.max(0) as usize, block.entity_tag);
        for el in &block.elements {
            let ids = el
                .nodes
                .iter()
                .map(|t| {
                    index.get(t).copied().ok_or(MeshError::UnknownNode {
                        element: el.element_tag,
                        node: *t,
                    })
                })
                .collect::<Result<Vec<_>, _>>()?;
            match raw {
                Raw::Bulk(kind) => bulk.push((el.element_tag, kind, ids, entity)),
                Raw::Line => lines.push((el.element_tag, [ids[0], ids[1]], entity)),
                Raw::Point => points.push((el.element_tag, ids[0], entity)),
            }
        }
    }
    if bulk.is_empty() {
        return Err(MeshError::NoBulk);
    }
    let mut all_tags: Vec<u64> = bulk
        .iter()
        .map(|b| b.0)
        .chain(lines.iter().map(|l| l.0))
        .chain(points.iter().map(|p| p.0))
        .collect();
    all_tags.sort_unstable();
    if let Some(w) = all_tags.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::DuplicateElement(w[0]));
    }
    bulk.sort_by_key(|b| b.0);
    lines.sort_by_key(|l| l.0);
    points.sort_by_key(|p| p.0);

    // Planarity, against the in-plane size of the mesh.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (_, x) in &raw_nodes {
        for d in 0..2 {
            lo[d] = lo[d].min(x[d]);
            hi[d] = hi[d].max(x[d]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let tolerance = Z_TOLERANCE * size;
    if let Some((tag, x)) = raw_nodes
        .iter()
        .find(|(_, x)| x[2].is_nan() || x[2].abs() > tolerance)
    {
        return Err(MeshError::Not2d {
            node: *tag,
            z: x[2],
            tolerance,
        });
    }
    let positions: Vec<Vector2<f64>> = raw_nodes.iter().map(|(_, x)| Vector2::new(x[0], x[1])).collect();
    let node_tags: Vec<u64> = raw_nodes.iter().map(|(t, _)| *t).collect();

    // Orientation and shape of the bulk elements.
    let mut reoriented = 0;
    let mut out_elements = Vec::with_capacity(bulk.len());
    for (tag, kind, mut ids, _) in bulk.iter().cloned() {
        if signed_area(&ids, &positions) < 0.0 {
            ids[1..].reverse();
            reoriented += 1;
        }
        let n = ids.len();
        let area = signed_area(&ids, &positions);
        let longest = (0..n)
            .map(|k| (positions[ids[(k + 1) % n]] - positions[ids[k]]).norm())
            .fold(0.0, f64::max);
        let corner = (0..n)
            .map(|k| {
                let (p, c, q) = (
                    positions[ids[(k + n - 1) % n]],
                    positions[ids[k]],
                    positions[ids[(k + 1) % n]],
                );
                (q - c).perp(&(p - c)) / 2.0
            })
            .fold(f64::INFINITY, f64::min);
        let tol = AREA_TOLERANCE * longest * longest;
        if !(area > tol && corner > tol) {
            return Err(MeshError::Degenerate {
                element: tag,
                area,
                corner,
                tolerance: tol,
            });
        }
        out_elements.push(BulkElement {
            tag,
            kind,
            nodes: ids,
        });
    }

    // Physical groups, by name.
    let mut warnings = Vec::new();
    let mut members: BTreeMap<(usize, i32), Vec<usize>> = BTreeMap::new();
    let mut point_nodes: BTreeMap<(usize, i32), Vec<usize>> = BTreeMap::new();
    let groups_of = |entity: &(usize, i32)| entity_groups.get(entity).cloned().unwrap_or_default();
    for (i, b) in bulk.iter().enumerate() {
        for g in groups_of(&b.3) {
            members.entry((2, g)).or_default().push(i);
        }
    }
    for (i, l) in lines.iter().enumerate() {
        for g in groups_of(&l.2) {
            members.entry((1, g)).or_default().push(i);
        }
    }
    for p in &points {
        for g in groups_of(&p.2) {
            point_nodes.entry((0, g)).or_default().push(p.1);
        }
    }
    let keys: BTreeSet<(usize, i32)> = members.keys().chain(point_nodes.keys()).copied().collect();
    let mut groups = BTreeMap::new();
    let mut unnamed = Vec::new();
    for k in keys {
        let Some(name) = names.get(&k) else {
            unnamed.push(format!("{}:{}", k.0, k.1));
            continue;
        };
        let group = PhysicalGroup {
            dim: k.0,
            tag: k.1,
            elements: if k.0 == 0 {
                Vec::new()
            } else {
                members.get(&k).cloned().unwrap_or_default()
            },
            nodes: point_nodes.get(&k).cloned().unwrap_or_default(),
        };
        if groups.insert(name.clone(), group).is_some() {
            return Err(MeshError::DuplicateGroupName(name.clone()));
        }
    }
    if !unnamed.is_empty() {
        warnings.push(format!(
            "{} physical group(s) without a name left out (dim:tag {})",
            unnamed.len(),
            unnamed.join(", ")
        ));
    }

    let mut mesh = UnstructuredMesh {
        positions,
        node_tags,
        elements: out_elements,
        lines: lines
            .iter()
            .map(|l| LineElement { tag: l.0, nodes: l.1 })
            .collect(),
        groups,
        reoriented,
        warnings,
    };
    mesh.refresh_group_nodes();
    for g in mesh.groups.values_mut().filter(|g| g.dim == 0) {
        g.nodes.sort_unstable();
        g.nodes.dedup();
    }

    // Conformity: at most two elements per edge, on opposite sides.
    let edges = mesh.edge_map();
    let mut edge_keys: Vec<_> = edges.keys().copied().collect();
    edge_keys.sort_unstable();
    for k in edge_keys {
        let faces = &edges[&k];
        let tags: Vec<u64> = faces.iter().map(|f| mesh.elements[f.element].tag).collect();
        if faces.len() > 2 {
            return Err(MeshError::NonManifoldEdge {
                a: mesh.node_tags[k.0],
                b: mesh.node_tags[k.1],
                count: faces.len(),
                elements: tags.iter().map(u64::to_string).collect::<Vec<_>>().join(", "),
            });
        }
        if faces.len() == 2 && edge_start(&mesh, faces[0]) == edge_start(&mesh, faces[1]) {
            return Err(MeshError::Overlap {
                a: tags[0],
                b: tags[1],
            });
        }
    }

    let mut used = vec![false; mesh.positions.len()];
    for el in &mesh.elements {
        for &n in &el.nodes {
            used[n] = true;
        }
    }
    let unused: Vec<u64> = used
        .iter()
        .zip(&mesh.node_tags)
        .filter(|(u, _)| !**u)
        .map(|(_, t)| *t)
        .collect();
    if !unused.is_empty() {
        let shown: Vec<String> = unused.iter().take(10).map(u64::to_string).collect();
        mesh.warnings.push(format!(
            "{} node(s) used by no bulk element (tags {}{})",
            unused.len(),
            shown.join(", "),
            if unused.len() > 10 { ", ..." } else { "" }
        ));
    }
    Ok(mesh)
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

impl UnstructuredMesh {
    /// Per node: it lies on the outer boundary (an edge with one element only).
    pub fn outer_nodes(&self) -> Vec<bool> {
        let mut outer = vec![false; self.positions.len()];
        for ((a, b), faces) in self.edge_map() {
            if faces.len() == 1 {
                outer[a] = true;
                outer[b] = true;
            }
        }
        outer
    }
}

/// First node of a face's edge, in the element's (counter-clockwise) order.
fn edge_start(mesh: &UnstructuredMesh, f: Face) -> usize {
    mesh.elements[f.element].nodes[f.local_edge]
}

/// For each of `n` bulk elements, the first of `surfaces` (element lists, in order) that holds it,
/// `None` for an element in none. Every later surface that holds an element must `agree(first,
/// later)` (surface positions), else Err((element, first, later)).
pub(crate) fn first_surface<'a>(
    n: usize,
    surfaces: impl IntoIterator<Item = &'a [usize]>,
    agree: impl Fn(usize, usize) -> bool,
) -> Result<Vec<Option<usize>>, (usize, usize, usize)> {
    let mut first: Vec<Option<usize>> = vec![None; n];
    for (s, elements) in surfaces.into_iter().enumerate() {
        for &e in elements {
            match first[e] {
                Some(f) if !agree(f, s) => return Err((e, f, s)),
                Some(_) => {}
                None => first[e] = Some(s),
            }
        }
    }
    Ok(first)
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
    let mut cut: HashSet<(usize, usize)> = HashSet::new();
    let mut chain_lines: HashSet<usize> = HashSet::new();
    for c in chains {
        let n = c.nodes.len();
        for (i, s) in c.segments.iter().enumerate() {
            cut.insert(key(c.nodes[i], c.nodes[(i + 1) % n]));
            chain_lines.insert(s.line);
        }
    }
    let mut cut_at: HashMap<usize, usize> = HashMap::new();
    for &(a, b) in &cut {
        *cut_at.entry(a).or_default() += 1;
        *cut_at.entry(b).or_default() += 1;
    }
    let is_junction = |n: usize| cut_at.get(&n).is_some_and(|&k| k >= 3);

    // + fan of each chain node, on the unsplit mesh; the sectors of each junction.
    let mut seen: HashSet<usize> = HashSet::new();
    let mut plan: Vec<(usize, BTreeSet<usize>)> = Vec::new();
    let mut tips = Vec::new();
    let mut sectors: BTreeMap<usize, Vec<BTreeSet<usize>>> = BTreeMap::new();
    for c in chains {
        let m = c.segments.len();
        for (i, &node) in c.nodes.iter().enumerate() {
            if is_junction(node) {
                sectors
                    .entry(node)
                    .or_insert_with(|| junction_sectors(mesh, &edges, &cut, node));
                continue;
            }
            if !seen.insert(node) {
                return Err(MeshError::ChainsMeet(mesh.node_tags[node]));
            }
            // Segments touching this node: i − 1 and i (cyclically when closed).
            let touching: Vec<&Segment> = if c.closed {
                vec![&c.segments[(i + m - 1) % m], &c.segments[i]]
            } else {
                c.segments[i.saturating_sub(1)..(i + 1).min(m)].iter().collect()
            };
            let seeds = touching.iter().map(|s| s.plus.element).collect();
            let fan = fan_around(mesh, &edges, &cut, node, seeds);
            if touching.iter().any(|s| fan.contains(&s.minus.element)) {
                tips.push(node);
            } else {
                plan.push((node, fan));
            }
        }
    }

    let mut out = mesh.clone();
    let mut next_tag = mesh.node_tags.iter().copied().max().unwrap_or(0);
    let mut twins = Vec::with_capacity(plan.len());
    let mut twin_of: HashMap<usize, usize> = HashMap::new();
    for (node, fan) in &plan {
        let twin = out.positions.len();
        next_tag += 1;
        move_fan(
            mesh,
            &mut out,
            (&edges, &chain_lines),
            (*node, twin, next_tag),
            fan,
        );
        twin_of.insert(*node, twin);
        twins.push(TwinPair {
            minus: *node,
            plus: twin,
        });
    }
    // per junction, the node of each sector; per element at a junction, its sector's node
    let mut junctions = Vec::with_capacity(sectors.len());
    let mut copy_in: HashMap<(usize, usize), usize> = HashMap::new();
    for (&node, fans) in &sectors {
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
                next_tag += 1;
                move_fan(
                    mesh,
                    &mut out,
                    (&edges, &chain_lines),
                    (node, copy, next_tag),
                    fan,
                );
                copies.push(copy);
            }
            for &e in fan {
                copy_in.insert((node, e), copy);
            }
        }
        junctions.push(copies);
    }
    let columns = chains
        .iter()
        .map(|c| {
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
        })
        .collect();
    out.refresh_group_nodes();
    Ok(SplitMesh {
        mesh: out,
        twins,
        tips,
        junctions,
        columns,
    })
}

/// The faces on each edge, by its (smaller, larger) node pair.
type EdgeMap = HashMap<(usize, usize), Vec<Face>>;

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
