//! The `$Elements` section of an ASCII MSH 4.1 file: the counts of its header and of each block
//! against its lines, each element line a tag and its nodes; the element tags are returned with
//! their lines for the tag rules of `located`.

use super::MeshError;
use super::lines::{Lines, counted, mismatch};
use super::located::{Tag, Tags, nodes_per_element};

/// `$Elements` (ASCII) between lines `start` and `end`: block and element counts, each element
/// line a tag and its nodes. Returns the element tags with their lines (those before a block of
/// a type the reader does not take, which `mshio` and the reader name) and the header's range.
pub(super) fn check_elements(lines: &Lines, start: usize, end: usize) -> Result<Tags, MeshError> {
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
    let range = (header[2], header[3]);
    let mut tags: Vec<Tag> = Vec::new();
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
            return Ok((tags, range));
        };
        let block_line = i;
        i += 1;
        for k in 0..n {
            if i >= end || lines.fields(i).len() != width + 1 {
                return Err(mismatch("$Elements block", block_line, "elements", n, k));
            }
            let element = lines.numbers::<u64>(section, i, width + 1, "an element: tag and node tags")?;
            tags.push((element[0], i + 1));
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
    counted(section, start + 1, "elements", header[1], elements)?;
    Ok((tags, range))
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
