//! The structure of an MSH 4.1 file checked before `mshio` parses it, so that a bad file is
//! refused naming its section, its line and the node, and never quoted beyond one line: every
//! section closed by its `$End…`; in ASCII files the counts of `$PhysicalNames`, `$Entities`,
//! `$Nodes` and `$Elements` (header and per block) against the lines that follow, and every
//! coordinate finite; in both encodings every node tag in the header's range, non-zero and
//! defined once. The node tags are returned in file order: `mshio` drops them when the header's
//! range is dense, and the reader numbers the nodes with these instead (docs/meshes.md).

use super::MeshError;
use super::located::{Tag, quote};
use super::scan_binary::binary_node_tags;

/// The node tags of the file in file order, once its structure is checked.
pub(super) fn node_tags(bytes: &[u8]) -> Result<Vec<u64>, MeshError> {
    let lines = Lines::new(bytes);
    let binary = check_format(&lines)?;
    let tags = if binary {
        if let Some(start) = lines.find_header("PhysicalNames", 0) {
            check_physical_names(&lines, start)?;
        }
        binary_node_tags(
            bytes,
            lines.find_header("Nodes", 0).map(|l| lines.start_of(l + 1)),
        )?
    } else {
        check_ascii_sections(&lines)?
    };
    check_tags(&tags.0, tags.1, binary)?;
    Ok(tags.0.into_iter().map(|(t, _)| t).collect())
}

/// The file split into lines (without their `\n` and `\r`), numbered from 1.
struct Lines<'a> {
    /// The whole file.
    bytes: &'a [u8],
    /// Byte offset of the start of each line.
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        let mut starts = vec![0];
        starts.extend(
            bytes
                .iter()
                .enumerate()
                .filter(|(_, b)| **b == b'\n')
                .map(|(i, _)| i + 1),
        );
        if starts.last() == Some(&bytes.len()) && starts.len() > 1 {
            starts.pop();
        }
        Lines { bytes, starts }
    }

    /// Number of lines.
    fn len(&self) -> usize {
        self.starts.len()
    }

    /// Byte offset where line `i` (0-based) starts.
    fn start_of(&self, i: usize) -> usize {
        self.starts.get(i).copied().unwrap_or(self.bytes.len())
    }

    /// Line `i` (0-based), trimmed of its line end.
    fn get(&self, i: usize) -> &'a [u8] {
        let end = self.starts.get(i + 1).map_or(self.bytes.len(), |e| e - 1);
        let line = &self.bytes[self.starts[i]..end.max(self.starts[i])];
        let line = line.strip_suffix(b"\n").unwrap_or(line);
        line.strip_suffix(b"\r").unwrap_or(line)
    }

    /// The whitespace-separated fields of line `i`.
    fn fields(&self, i: usize) -> Vec<&'a [u8]> {
        self.get(i)
            .split(|b| b.is_ascii_whitespace())
            .filter(|f| !f.is_empty())
            .collect()
    }

    /// First line at or after `from` that is exactly `$name`.
    fn find_header(&self, name: &str, from: usize) -> Option<usize> {
        (from..self.len()).find(|&i| self.get(i).strip_prefix(b"$") == Some(name.as_bytes()))
    }

    /// The line of `$End<name>` closing the section opened on line `start`.
    fn end_of(&self, name: &str, start: usize) -> Result<usize, MeshError> {
        let end = format!("End{name}");
        self.find_header(&end, start + 1)
            .ok_or_else(|| MeshError::Unclosed {
                section: format!("${name}"),
                line: start + 1,
            })
    }

    /// An error on line `i` (0-based) of `section`, quoting the line.
    fn malformed(&self, section: &str, i: usize, expected: &str) -> MeshError {
        MeshError::Malformed {
            section: section.to_string(),
            at: format!("line {}", i + 1),
            expected: expected.to_string(),
            found: quote(self.get(i.min(self.len() - 1))),
        }
    }

    /// The numbers of line `i`, which must hold exactly `n` of type `T`.
    fn numbers<T: std::str::FromStr>(
        &self,
        section: &str,
        i: usize,
        n: usize,
        expected: &str,
    ) -> Result<Vec<T>, MeshError> {
        let fields = self.fields(i);
        let parsed: Option<Vec<T>> = fields
            .iter()
            .map(|f| std::str::from_utf8(f).ok()?.parse().ok())
            .collect();
        match parsed {
            Some(v) if v.len() == n => Ok(v),
            _ => Err(self.malformed(section, i, expected)),
        }
    }
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

/// Walks the sections of an ASCII file, checks each, and returns its node tags with their lines
/// and the header's tag range.
fn check_ascii_sections(lines: &Lines) -> Result<(Vec<Tag>, (u64, u64)), MeshError> {
    let mut nodes = None;
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
            "Elements" => check_elements(lines, i, end)?,
            _ => {}
        }
        i = end + 1;
    }
    Ok(nodes.unwrap_or_default())
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

/// A count `expected` declared on line `line + 1` against the `found` one.
fn counted(
    section: &str,
    line: usize,
    what: &'static str,
    expected: u64,
    found: u64,
) -> Result<(), MeshError> {
    if expected == found {
        return Ok(());
    }
    Err(mismatch(section, line, what, expected, found))
}

/// The error for a count `expected` on line `line + 1` against the `found` one.
fn mismatch(section: &str, line: usize, what: &'static str, expected: u64, found: u64) -> MeshError {
    MeshError::CountMismatch {
        section: section.to_string(),
        at: format!("line {}", line + 1),
        what,
        expected,
        found,
    }
}

/// `$Nodes` (ASCII) between lines `start` and `end`: block and node counts, one tag per line,
/// finite coordinates. Returns the tags with their lines and the header's range.
fn check_nodes(lines: &Lines, start: usize, end: usize) -> Result<(Vec<Tag>, (u64, u64)), MeshError> {
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

/// Nodes per element of the Gmsh types the reader takes (others are refused later, by type).
fn nodes_per_element(element_type: u64) -> Option<usize> {
    match element_type {
        1 => Some(2),
        2 => Some(3),
        3 => Some(4),
        15 => Some(1),
        _ => None,
    }
}

/// `$Elements` (ASCII) between lines `start` and `end`: block and element counts, each element
/// line a tag and its nodes.
fn check_elements(lines: &Lines, start: usize, end: usize) -> Result<(), MeshError> {
    let section = "$Elements";
    let header = lines.numbers::<u64>(
        section,
        start + 1,
        4,
        "numEntityBlocks numElements minElementTag maxElementTag",
    )?;
    if header[1] == 0 {
        return Err(MeshError::NoElements { line: start + 2 });
    }
    let (mut blocks, mut elements, mut i) = (0u64, 0u64, start + 2);
    while i < end {
        let block = lines.numbers::<u64>(
            section,
            i,
            4,
            "a block: entityDim entityTag elementType numElementsInBlock",
        )?;
        let (element_type, n) = (block[2], block[3]);
        let Some(width) = nodes_per_element(element_type) else {
            // An unsupported type: `mshio` and the reader name it with its first element.
            return Ok(());
        };
        let block_line = i;
        i += 1;
        for k in 0..n {
            if i >= end || lines.fields(i).len() != width + 1 {
                return Err(mismatch("$Elements block", block_line, "elements", n, k));
            }
            lines.numbers::<u64>(section, i, width + 1, "an element: tag and node tags")?;
            i += 1;
        }
        let extra = (i..end).take_while(|&j| is_element_line(lines, j, width)).count() as u64;
        if extra > 0 {
            return Err(mismatch("$Elements block", block_line, "elements", n, n + extra));
        }
        blocks += 1;
        elements += n;
    }
    counted(section, start + 1, "entity blocks", header[0], blocks)?;
    counted(section, start + 1, "elements", header[1], elements)
}

/// Whether line `i` is one more element of `width` nodes rather than the next block's header: a
/// triangle's line has a header's four fields, but its first (the element tag) would be an
/// entity dimension above 3 — for elements 1 to 3 it is taken as a header, and the totals decide.
fn is_element_line(lines: &Lines, i: usize, width: usize) -> bool {
    let fields = lines.fields(i);
    fields.len() == width + 1
        && (fields.len() != 4
            || std::str::from_utf8(fields[0])
                .ok()
                .and_then(|f| f.parse::<u64>().ok())
                > Some(3))
}

/// Every tag in the header's `range`, non-zero, defined once; `binary` says whether the places
/// are byte offsets rather than lines.
fn check_tags(tags: &[Tag], range: (u64, u64), binary: bool) -> Result<(), MeshError> {
    let place = |at: usize| {
        if binary {
            format!("byte {at}")
        } else {
            format!("line {at}")
        }
    };
    for &(tag, at) in tags {
        if tag == 0 || tag < range.0 || tag > range.1 {
            return Err(MeshError::BadNodeTag {
                tag,
                at: place(at),
                reason: format!(
                    "outside the range {}..={} of the $Nodes header (and 0 is reserved)",
                    range.0, range.1
                ),
            });
        }
    }
    let mut sorted = tags.to_vec();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(MeshError::BadNodeTag {
            tag: w[1].0,
            at: place(w[1].1),
            reason: format!("defined twice (first at {})", place(w[0].1)),
        });
    }
    Ok(())
}
