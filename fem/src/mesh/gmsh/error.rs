//! [`MeshError`]: every way a mesh file, a mesh or an interface can break a rule of the reader.

use super::split::MAX_JUNCTION_SECTORS;
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
    /// A line (ASCII) or a record (binary) that is not what its section holds there.
    #[error("{section}, {at}: expected {expected}, found \"{found}\"")]
    Malformed {
        /// The section, as `$Nodes`.
        section: String,
        /// Where: `line N` (1-based) or `byte N`.
        at: String,
        /// What the format puts there.
        expected: String,
        /// The line as found, at most 64 bytes of it.
        found: String,
    },
    /// A count of a section's header (or of a block's) that its body does not match.
    #[error("{section} header at {at} declares {expected} {what}, found {found}")]
    CountMismatch {
        /// The section or block, as `$Nodes block`.
        section: String,
        /// Where the count stands: `line N` (1-based) or `byte N`.
        at: String,
        /// What is counted.
        what: &'static str,
        /// The count declared.
        expected: u64,
        /// The count found in the body.
        found: u64,
    },
    /// A section opened and never closed by its `$End…` line.
    #[error("{section} opened on line {line} has no $End{} line", &section[1..])]
    Unclosed {
        /// The section, as `$PhysicalNames`.
        section: String,
        /// Line of its header (1-based).
        line: usize,
    },
    /// A node tag that is 0, outside the `$Nodes` header's range, or defined twice.
    #[error("node tag {tag} at {at} is {reason}")]
    BadNodeTag {
        /// The tag.
        tag: u64,
        /// Where: `line N` (1-based) or `byte N`.
        at: String,
        /// Why it is refused.
        reason: String,
    },
    /// An element tag that is 0, outside the `$Elements` header's range, or given twice.
    #[error("element tag {tag} at {at} is {reason}")]
    BadElementTag {
        /// The tag.
        tag: u64,
        /// Where: `line N` (1-based) or `byte N`.
        at: String,
        /// Why it is refused.
        reason: String,
    },
    /// A node coordinate that is NaN or infinite.
    #[error("node {node} ({at}) has a coordinate that is not a finite number")]
    NonFiniteNode {
        /// Node tag.
        node: u64,
        /// Where: `line N` (1-based) of its coordinates, or the section.
        at: String,
    },
    /// An `$Elements` section that declares no element.
    #[error(
        "$Elements header on line {line} declares 0 elements: the mesh has no 2D element (triangle or quadrangle)"
    )]
    NoElements {
        /// Line of the header (1-based).
        line: usize,
    },
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
    /// Two chains given to [`split_interface`](super::split_interface) meet at a node.
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
