//! The structure of an MSH 4.1 file checked before `mshio` parses it, so that a bad file is
//! refused naming its section, its line (or byte) and the node or element, and never quoted
//! beyond one line: every section closed by its `$End…`; in ASCII files the counts of
//! `$PhysicalNames`, `$Entities`, `$Nodes` and `$Elements` (header and per block) against the
//! lines that follow, and every coordinate finite; in binary files the counts of `$Nodes` and
//! `$Elements` against their blocks (`scan_binary`); in both encodings every node and element tag
//! in its header's range, non-zero and given once. The node tags are returned in file order:
//! `mshio` drops them when the header's range is dense, and the reader numbers the nodes with
//! these instead (docs/meshes.md).

use super::MeshError;
use super::lines::{Lines, counted, mismatch};
use super::located::{Owner, Tag, Tags, check_tags};
use super::scan_binary::{binary_element_tags, binary_node_tags};
use super::scan_elements::check_elements;

/// The node tags of the file in file order, once its structure and its node and element tags are
/// checked.
pub(super) fn node_tags(bytes: &[u8]) -> Result<Vec<u64>, MeshError> {
    let lines = Lines::new(bytes);
    let binary = check_format(&lines)?;
    let (nodes, elements) = if binary {
        if let Some(start) = lines.find_header("PhysicalNames", 0) {
            check_physical_names(&lines, start)?;
        }
        let header = lines.find_header("Nodes", 0);
        let body = |l: usize| lines.start_of(l + 1);
        let nodes = binary_node_tags(bytes, header.map(body))?;
        let elements = lines.find_header("Elements", header.unwrap_or(0));
        (nodes, binary_element_tags(bytes, elements.map(body))?)
    } else {
        check_ascii_sections(&lines)?
    };
    check_tags(Owner::Node, &nodes, binary)?;
    check_tags(Owner::Element, &elements, binary)?;
    Ok(nodes.0.into_iter().map(|(t, _)| t).collect())
}

/// Checks `$MeshFormat` (first section, version 4.1) and tells whether the file is binary.
fn check_format(lines: &Lines) -> Result<bool, MeshError> {
    let first = (0..lines.len()).find(|&i| !lines.get(i).trim_ascii().is_empty());
    let Some(first) = first.filter(|&i| lines.get(i) == b"$MeshFormat") else {
        let i = first.unwrap_or(0);
        return Err(lines.malformed("file", i, "$MeshFormat first"));
    };
    let format = lines.fields(first + 1);
    let binary = match format.as_slice() {
        [b"4.1", b"0", _] => false,
        [b"4.1", b"1", b"8"] => true,
        _ => {
            return Err(lines.malformed(
                "$MeshFormat",
                first + 1,
                "\"4.1 0 8\" (ASCII) or \"4.1 1 8\" (binary, 8-byte sizes)",
            ));
        }
    };
    Ok(binary)
}

/// Walks the sections of an ASCII file, checks each, and returns its node and element tags with
/// their lines and the headers' tag ranges.
fn check_ascii_sections(lines: &Lines) -> Result<(Tags, Tags), MeshError> {
    let (mut nodes, mut elements) = (None, None);
    let mut i = 0;
    while i < lines.len() {
        let line = lines.get(i);
        if line.trim_ascii().is_empty() {
            i += 1;
            continue;
        }
        let Some(name) = line.strip_prefix(b"$").filter(|n| !n.starts_with(b"End")) else {
            return Err(lines.malformed("file", i, "a section header ($Name)"));
        };
        let name = String::from_utf8_lossy(name).into_owned();
        let end = lines.end_of(&name, i)?;
        match name.as_str() {
            "PhysicalNames" => check_physical_names(lines, i)?,
            "Entities" => check_entities(lines, i, end)?,
            "Nodes" => nodes = Some(check_nodes(lines, i, end)?),
            "Elements" => elements = Some(check_elements(lines, i, end)?),
            _ => {}
        }
        i = end + 1;
    }
    Ok((nodes.unwrap_or_default(), elements.unwrap_or_default()))
}

/// `$PhysicalNames` opened on line `start`: its count against its lines.
fn check_physical_names(lines: &Lines, start: usize) -> Result<(), MeshError> {
    let end = lines.end_of("PhysicalNames", start)?;
    let section = "$PhysicalNames";
    let [count] = lines.numbers::<u64>(section, start + 1, 1, "the number of names")?[..] else {
        unreachable!("invariant: numbers returns exactly the count asked for")
    };
    let found = (start + 2..end)
        .filter(|&i| !lines.get(i).trim_ascii().is_empty())
        .count();
    counted(section, start + 1, "names", count, found as u64)
}

/// `$Entities` (ASCII) between lines `start` and `end`: its four counts against its lines.
fn check_entities(lines: &Lines, start: usize, end: usize) -> Result<(), MeshError> {
    let section = "$Entities";
    let counts = lines.numbers::<u64>(
        section,
        start + 1,
        4,
        "numPoints numCurves numSurfaces numVolumes",
    )?;
    let expected = counts.iter().try_fold(0u64, |a, &c| a.checked_add(c));
    let found = (start + 2..end)
        .filter(|&i| !lines.get(i).trim_ascii().is_empty())
        .count();
    counted(
        section,
        start + 1,
        "entities",
        expected.unwrap_or(u64::MAX),
        found as u64,
    )
}

/// `$Nodes` (ASCII) between lines `start` and `end`: block and node counts, one tag per line,
/// finite coordinates. Returns the tags with their lines and the header's range.
fn check_nodes(lines: &Lines, start: usize, end: usize) -> Result<Tags, MeshError> {
    let section = "$Nodes";
    let header = lines.numbers::<u64>(
        section,
        start + 1,
        4,
        "numEntityBlocks numNodes minNodeTag maxNodeTag",
    )?;
    let mut tags: Vec<Tag> = Vec::new();
    let (mut blocks, mut i) = (0u64, start + 2);
    while i < end {
        let block = lines.numbers::<u64>(
            section,
            i,
            4,
            "a block: entityDim entityTag parametric numNodesInBlock",
        )?;
        let (dim, parametric, n) = (block[0], block[2], block[3]);
        if dim > 3 || parametric > 1 {
            return Err(lines.malformed(section, i, "entityDim 0..3 and parametric 0 or 1"));
        }
        let width = 3 + if parametric == 1 { dim as usize } else { 0 };
        let block_line = i;
        i += 1;
        let first = tags.len();
        while (tags.len() - first) as u64 != n {
            match lines.fields(i).as_slice() {
                [t] if i < end => {
                    let tag = std::str::from_utf8(t).ok().and_then(|t| t.parse().ok());
                    let tag = tag.ok_or_else(|| lines.malformed(section, i, "a node tag"))?;
                    tags.push((tag, i + 1));
                    i += 1;
                }
                _ => {
                    let found = (tags.len() - first) as u64;
                    return Err(mismatch("$Nodes block", block_line, "nodes", n, found));
                }
            }
        }
        let extra = (i..end).take_while(|&j| lines.fields(j).len() == 1).count() as u64;
        if extra > 0 {
            return Err(mismatch("$Nodes block", block_line, "nodes", n, n + extra));
        }
        for (k, &(tag, _)) in tags[first..].iter().enumerate() {
            if i >= end {
                return Err(mismatch(
                    "$Nodes block",
                    block_line,
                    "coordinate lines",
                    n,
                    k as u64,
                ));
            }
            let x = lines.numbers::<f64>(section, i, width, "node coordinates x y z")?;
            if !x.iter().all(|c| c.is_finite()) {
                return Err(MeshError::NonFiniteNode {
                    node: tag,
                    at: format!("line {}", i + 1),
                });
            }
            i += 1;
        }
        blocks += 1;
    }
    counted(section, start + 1, "entity blocks", header[0], blocks)?;
    counted(section, start + 1, "nodes", header[1], tags.len() as u64)?;
    Ok((tags, (header[2], header[3])))
}
