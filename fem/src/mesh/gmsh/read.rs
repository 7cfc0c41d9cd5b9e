//! Reading a Gmsh MSH 4.1 file through `mshio` into an [`UnstructuredMesh`]: nodes, elements
//! and physical groups, with the checks of the reader (planarity, orientation and shape of the
//! bulk elements, conformity).

use super::{BulkElement, ElementKind, LineElement, MeshError, PhysicalGroup, UnstructuredMesh};
use super::{edge_start, scan, signed_area};
use mshio::{ElementBlock, ElementType, Elements, MshFile, Nodes};
use nalgebra::Vector2;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

/// Relative tolerance on z against the in-plane size of the mesh: Gmsh prints coordinates to 16
/// significant digits, so a planar mesh has |z| far below 1e-10 of its size.
const Z_TOLERANCE: f64 = 1e-10;
/// Relative tolerance on element areas against the longest edge squared: a genuine element of a
/// Gmsh mesh is far above it, a collapsed one is at round-off (≈ 1e-16).
const AREA_TOLERANCE: f64 = 1e-12;

impl UnstructuredMesh {
    /// Reads a Gmsh MSH 4.1 file, ASCII or binary, through the mesh size cap
    /// ([`preflight::input::Cap::mesh`]: 2 GiB unless `COHESIVE_MAX_MESH_BYTES` says otherwise).
    pub fn read(path: &Path) -> Result<Self, MeshError> {
        let io = |e: std::io::Error| MeshError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        let bytes =
            preflight::input::read_capped(path, preflight::input::Cap::mesh().map_err(io)?).map_err(io)?;
        Self::from_msh_bytes(&bytes)
    }

    /// Builds the mesh from the bytes of a Gmsh MSH 4.1 file, ASCII or binary. The file's
    /// structure is checked first (`scan`), so that `mshio` parses only well-formed sections.
    pub fn from_msh_bytes(bytes: &[u8]) -> Result<Self, MeshError> {
        let tags = scan::node_tags(bytes)?;
        // mshio 0.4 still has a few `unimplemented!`/`expect` on malformed headers: a panic there
        // becomes a parse error here, never a panic of the caller.
        let parsed = std::panic::catch_unwind(|| {
            mshio::parse_msh_bytes(bytes).map_err(|e| MeshError::Parse(without_dump(&e.to_string())))
        })
        .map_err(|_| MeshError::Parse("the MSH reader stopped on a malformed header".into()))??;
        let names = physical_names(bytes)?;
        build(&parsed, &names, &tags)
    }
}

/// `mshio`'s message without the hex dump of the rest of the file it appends (megabytes for a
/// large mesh), cut to its first 300 bytes.
fn without_dump(message: &str) -> String {
    let kept = message.split("Hex dump").next().unwrap_or_default().trim_end();
    let cut = (0..=kept.len().min(300))
        .rev()
        .find(|&i| kept.is_char_boundary(i))
        .unwrap_or(0);
    kept[..cut].replace('\n', " ").replace('\t', "")
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

/// Position of the first occurrence of `needle` in `hay`.
fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// A bulk element as read: tag, kind, node indices, entity (dim, tag).
type RawBulk = (u64, ElementKind, Vec<usize>, (usize, i32));
/// A line element as read: tag, node indices (start, end), entity (dim, tag).
type RawLine = (u64, [usize; 2], (usize, i32));
/// A point element as read: tag, node index, entity (dim, tag).
type RawPoint = (u64, usize, (usize, i32));
/// A node as read: tag and coordinates (x, y, z) [m].
type RawNode = (u64, [f64; 3]);
/// Physical tags of each entity, by (dim, entity tag).
type EntityGroups = HashMap<(usize, i32), Vec<i32>>;

/// What a raw element block holds.
enum Raw {
    /// Triangles or quadrangles.
    Bulk(ElementKind),
    /// 2-node lines.
    Line,
    /// Points.
    Point,
}

/// The elements of the file as read, each kind in ascending tag order once checked.
struct RawElements {
    /// Triangles and quadrangles.
    bulk: Vec<RawBulk>,
    /// 2-node lines.
    lines: Vec<RawLine>,
    /// Points.
    points: Vec<RawPoint>,
}

/// The mesh of a parsed file, whose physical groups are named by `names` ((dim, tag) → name),
/// with every check of the reader.
fn build(
    file: &MshFile<u64, i32, f64>,
    names: &HashMap<(usize, i32), String>,
    tags: &[u64],
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

    let raw_nodes = read_nodes(nodes, tags)?;
    let index: HashMap<u64, usize> = raw_nodes.iter().enumerate().map(|(i, &(t, _))| (t, i)).collect();
    let entity_groups = entity_groups(file);
    let mut raw = read_elements(elements, &index)?;
    check_element_tags(&mut raw)?;
    let (positions, node_tags) = planar_positions(&raw_nodes)?;
    let (out_elements, reoriented) = oriented_elements(&raw.bulk, &positions)?;
    let (groups, warnings) = physical_groups(&raw, &entity_groups, names)?;

    let mut mesh = UnstructuredMesh {
        positions,
        node_tags,
        elements: out_elements,
        lines: raw
            .lines
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
    check_conformity(&mesh)?;
    if let Some(warning) = unused_nodes_warning(&mesh) {
        mesh.warnings.push(warning);
    }
    Ok(mesh)
}

/// The nodes of the `$Nodes` section, by ascending tag: `tags` are the file's, in file order (as
/// `scan` read them, checked in range and unique), which `mshio` drops when the header's range is
/// dense. A non-finite coordinate is an error naming the node.
fn read_nodes(nodes: &Nodes<u64, i32, f64>, tags: &[u64]) -> Result<Vec<RawNode>, MeshError> {
    let coordinates = nodes.node_blocks.iter().flat_map(|b| b.nodes.iter());
    if coordinates.clone().count() != tags.len() {
        return Err(MeshError::Parse(format!(
            "$Nodes holds {} nodes for {} tags",
            coordinates.count(),
            tags.len()
        )));
    }
    let mut raw_nodes: Vec<RawNode> = tags
        .iter()
        .zip(coordinates)
        .map(|(&tag, n)| (tag, [n.x, n.y, n.z]))
        .collect();
    if let Some(&(node, _)) = raw_nodes.iter().find(|(_, x)| !x.iter().all(|c| c.is_finite())) {
        return Err(MeshError::NonFiniteNode {
            node,
            at: "$Nodes".into(),
        });
    }
    raw_nodes.sort_by_key(|&(t, _)| t);
    if let Some(w) = raw_nodes.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(MeshError::DuplicateNode(w[0].0));
    }
    Ok(raw_nodes)
}

/// The physical tags of each entity of the `$Entities` section (none without it).
fn entity_groups(file: &MshFile<u64, i32, f64>) -> EntityGroups {
    let mut entity_groups: EntityGroups = HashMap::new();
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
    entity_groups
}

/// What the elements of `block` are; an unsupported type is an error naming the block's first
/// element.
fn block_kind(block: &ElementBlock<u64, i32>) -> Result<Raw, MeshError> {
    Ok(match block.element_type {
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
    })
}

/// The elements of the `$Elements` section, in file order, with their entity and their nodes as
/// indices into the nodes by ascending tag (`index`: tag → index); a node the file does not define
/// is an error.
fn read_elements(
    elements: &Elements<u64, i32>,
    index: &HashMap<u64, usize>,
) -> Result<RawElements, MeshError> {
    let mut bulk: Vec<RawBulk> = Vec::new();
    let mut lines: Vec<RawLine> = Vec::new();
    let mut points: Vec<RawPoint> = Vec::new();
    for block in &elements.element_blocks {
        let raw = block_kind(block)?;
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
    Ok(RawElements { bulk, lines, points })
}

/// Checks that there is a bulk element and that no element tag is used twice, then sorts each
/// kind of element by tag.
fn check_element_tags(raw: &mut RawElements) -> Result<(), MeshError> {
    if raw.bulk.is_empty() {
        return Err(MeshError::NoBulk);
    }
    let mut all_tags: Vec<u64> = raw
        .bulk
        .iter()
        .map(|b| b.0)
        .chain(raw.lines.iter().map(|l| l.0))
        .chain(raw.points.iter().map(|p| p.0))
        .collect();
    all_tags.sort_unstable();
    if let Some(w) = all_tags.windows(2).find(|w| w[0] == w[1]) {
        return Err(MeshError::DuplicateElement(w[0]));
    }
    raw.bulk.sort_by_key(|b| b.0);
    raw.lines.sort_by_key(|l| l.0);
    raw.points.sort_by_key(|p| p.0);
    Ok(())
}

/// The in-plane positions [m] and the tags of the nodes, once every node is checked to lie on
/// z = 0 within [`Z_TOLERANCE`] of the in-plane size of the mesh.
fn planar_positions(raw_nodes: &[RawNode]) -> Result<(Vec<Vector2<f64>>, Vec<u64>), MeshError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (_, x) in raw_nodes {
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
    Ok((positions, node_tags))
}

/// The bulk elements turned counter-clockwise where the file gave them clockwise, and how many
/// were turned; each must pass [`oriented_element`]'s shape check.
fn oriented_elements(
    bulk: &[RawBulk],
    positions: &[Vector2<f64>],
) -> Result<(Vec<BulkElement>, usize), MeshError> {
    let mut reoriented = 0;
    let mut out_elements = Vec::with_capacity(bulk.len());
    for (tag, kind, ids, _) in bulk.iter().cloned() {
        let (element, turned) = oriented_element(tag, kind, ids, positions)?;
        if turned {
            reoriented += 1;
        }
        out_elements.push(element);
    }
    Ok((out_elements, reoriented))
}

/// Bulk element `tag` of nodes `ids`, counter-clockwise (and whether it had to be turned). Its
/// area and its smallest corner area (half the cross product of the two edges at a corner) must
/// both exceed [`AREA_TOLERANCE`] × (longest edge)² [m²], else it is degenerate.
fn oriented_element(
    tag: u64,
    kind: ElementKind,
    mut ids: Vec<usize>,
    positions: &[Vector2<f64>],
) -> Result<(BulkElement, bool), MeshError> {
    let turned = signed_area(&ids, positions) < 0.0;
    if turned {
        ids[1..].reverse();
    }
    let n = ids.len();
    let area = signed_area(&ids, positions);
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
    Ok((
        BulkElement {
            tag,
            kind,
            nodes: ids,
        },
        turned,
    ))
}

/// Per (dim, physical tag): indices of elements or nodes.
type Members = BTreeMap<(usize, i32), Vec<usize>>;

/// Per (dim, physical tag): the indices of its bulk (dim 2) or line (dim 1) elements, and the
/// nodes of its point elements (dim 0, in element order, possibly repeated).
fn group_members(raw: &RawElements, entity_groups: &EntityGroups) -> (Members, Members) {
    let mut members: Members = BTreeMap::new();
    let mut point_nodes: Members = BTreeMap::new();
    let groups_of = |entity: &(usize, i32)| entity_groups.get(entity).cloned().unwrap_or_default();
    for (i, b) in raw.bulk.iter().enumerate() {
        for g in groups_of(&b.3) {
            members.entry((2, g)).or_default().push(i);
        }
    }
    for (i, l) in raw.lines.iter().enumerate() {
        for g in groups_of(&l.2) {
            members.entry((1, g)).or_default().push(i);
        }
    }
    for p in &raw.points {
        for g in groups_of(&p.2) {
            point_nodes.entry((0, g)).or_default().push(p.1);
        }
    }
    (members, point_nodes)
}

/// The physical groups by name (their node lists still to be filled for dims 1 and 2) and the
/// warnings of the reader: a group without a name is left out with a warning, a name given to
/// two groups is an error.
fn physical_groups(
    raw: &RawElements,
    entity_groups: &EntityGroups,
    names: &HashMap<(usize, i32), String>,
) -> Result<(BTreeMap<String, PhysicalGroup>, Vec<String>), MeshError> {
    let mut warnings = Vec::new();
    let (members, point_nodes) = group_members(raw, entity_groups);
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
    Ok((groups, warnings))
}

/// Conformity: at most two elements per edge, on opposite sides; the edges are checked in
/// ascending order of their node pair, so the error is the same on every run.
fn check_conformity(mesh: &UnstructuredMesh) -> Result<(), MeshError> {
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
        if faces.len() == 2 && edge_start(mesh, faces[0]) == edge_start(mesh, faces[1]) {
            return Err(MeshError::Overlap {
                a: tags[0],
                b: tags[1],
            });
        }
    }
    Ok(())
}

/// The warning on the nodes used by no bulk element (the first ten tags shown), if any.
fn unused_nodes_warning(mesh: &UnstructuredMesh) -> Option<String> {
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
    if unused.is_empty() {
        return None;
    }
    let shown: Vec<String> = unused.iter().take(10).map(u64::to_string).collect();
    Some(format!(
        "{} node(s) used by no bulk element (tags {}{})",
        unused.len(),
        shown.join(", "),
        if unused.len() > 10 { ", ..." } else { "" }
    ))
}
