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
//!
//! Parts: the mesh types are here; `scan` checks a file's structure (counts, tags, lines) with
//! `lines` (the file as lines), `scan_elements` (an ASCII `$Elements`), `scan_binary` (a binary
//! `$Nodes` and `$Elements`) and `located` (the tag rules they share); `read` reads and checks a
//! file, `query` answers questions on a read mesh, `chains` orders an interface's lines into
//! chains, `split` twins their nodes, and `error` holds [`MeshError`].

mod chains;
mod error;
mod lines;
mod located;
mod query;
mod read;
mod scan;
mod scan_binary;
mod scan_elements;
mod split;

pub use chains::{Chain, Segment, interface_chains, interface_chains_of};
pub use error::MeshError;
pub(crate) use query::first_surface;
pub use split::{MAX_JUNCTION_SECTORS, SplitMesh, TwinPair, split_interface};

use nalgebra::Vector2;
use std::collections::{BTreeMap, HashMap};

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

/// The faces on each edge, by its (smaller, larger) node pair.
type EdgeMap = HashMap<(usize, usize), Vec<Face>>;

/// The key of the edge between nodes `a` and `b` in an [`EdgeMap`]: (smaller, larger).
fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// Area [m²] of the polygon through the nodes `nodes` of `x` [m] (shoelace formula), positive when
/// they run counter-clockwise.
fn signed_area(nodes: &[usize], x: &[Vector2<f64>]) -> f64 {
    let n = nodes.len();
    (0..n)
        .map(|k| x[nodes[k]].perp(&x[nodes[(k + 1) % n]]))
        .sum::<f64>()
        / 2.0
}

/// First node of a face's edge, in the element's (counter-clockwise) order.
fn edge_start(mesh: &UnstructuredMesh, f: Face) -> usize {
    mesh.elements[f.element].nodes[f.local_edge]
}
