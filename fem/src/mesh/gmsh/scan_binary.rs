//! The `$Nodes` and `$Elements` sections of a binary MSH 4.1 file (little-endian, 8-byte
//! `size_t`) walked for their tags, each with its byte offset. A section is a header of four
//! `size_t` (blocks, total, smallest and largest tag) then blocks, each of three `int` and a
//! `size_t` count followed by its records, up to its `$End…` line. The blocks are walked by their
//! counts to that line and the header's totals checked against them; a block whose count does not
//! lead to the next block is refused with the count that does, when one does.

use super::MeshError;
use super::located::{Tag, Tags, nodes_per_element, quote};

/// How far from a block's declared count the search for the count that fits looks, each way.
const SEARCH: u64 = 1 << 16;

/// Most blocks the search reads (every try reads at least one), so that a section whose counts
/// are far off costs no more than this.
const BUDGET: u64 = 1 << 22;

/// Bytes of a block's header: entityDim, entityTag, a third `int`, the count.
const BLOCK_HEADER: usize = 20;

/// What a block's header says of its records.
enum Record {
    /// Bytes per node or element.
    Bytes(usize),
    /// A valid block the reader does not take (an element type refused later, by type).
    Unsupported,
    /// Not a block header.
    Invalid,
}

/// A block as walked: the byte offset of its header, its record size, its count.
#[derive(Clone, Copy)]
struct Block {
    at: usize,
    record: usize,
    n: u64,
}

/// One binary section.
struct Section<'a> {
    /// The whole file.
    bytes: &'a [u8],
    /// `Nodes` or `Elements`.
    name: &'static str,
    /// What its blocks hold, and the same when only a bound is known.
    what: [&'static str; 2],
    /// Byte offset of its header (just after the `$Name` line).
    start: usize,
    /// Byte offset of the `\n` before its `$End…` line, where its last block ends.
    end: usize,
    /// The record of a block from its entityDim and its third `int`.
    record: fn(i32, i32) -> Record,
    /// The header's counts: blocks, and nodes or elements in all.
    declared: (u64, u64),
}

/// The node tags with their byte offsets and the header's tag range, from the `$Nodes` section
/// whose header starts at byte `start` (none without the section).
pub(super) fn binary_node_tags(bytes: &[u8], start: Option<usize>) -> Result<Tags, MeshError> {
    let record = |dim: i32, parametric: i32| match (dim, parametric) {
        (0..=3, 0..=1) => Record::Bytes(8 * (1 + 3 + (dim * parametric) as usize)),
        _ => Record::Invalid,
    };
    let what = ["nodes", "nodes (at most, by the bytes left)"];
    // A node block lists its tags, then their coordinates.
    section(bytes, start, "Nodes", what, record, |b, i| {
        b.at + BLOCK_HEADER + 8 * i
    })
}

/// The element tags with their byte offsets and the header's tag range, from the `$Elements`
/// section whose header starts at byte `start` (none without the section, or before a block of a
/// type the reader does not take).
pub(super) fn binary_element_tags(bytes: &[u8], start: Option<usize>) -> Result<Tags, MeshError> {
    let record = |dim: i32, element_type: i32| match nodes_per_element(element_type.max(0) as u64) {
        Some(_) if !(0..=3).contains(&dim) => Record::Invalid,
        Some(width) => Record::Bytes(8 * (1 + width)),
        None if element_type > 0 && (0..=3).contains(&dim) => Record::Unsupported,
        None => Record::Invalid,
    };
    let what = ["elements", "elements (at most, by the bytes left)"];
    // An element is its tag then its node tags.
    section(bytes, start, "Elements", what, record, |b, i| {
        b.at + BLOCK_HEADER + b.record * i
    })
}

/// The tags of section `$name` (header at byte `start`), the tag `i` of block `b` standing at
/// byte `tag_at(b, i)`.
fn section(
    bytes: &[u8],
    start: Option<usize>,
    name: &'static str,
    what: [&'static str; 2],
    record: fn(i32, i32) -> Record,
    tag_at: fn(&Block, usize) -> usize,
) -> Result<Tags, MeshError> {
    let Some(start) = start else {
        return Ok((Vec::new(), (0, 0)));
    };
    let close = format!("$End{name}");
    let Some(p) = bytes[start..]
        .windows(close.len())
        .position(|w| w == close.as_bytes())
    else {
        return Err(malformed(name, start, &close, "the end of the file".into()));
    };
    let end = start + p - usize::from(p > 0 && bytes[start + p - 1] == b'\n');
    let mut s = Section {
        bytes,
        name,
        what,
        start,
        end,
        record,
        declared: (0, 0),
    };
    let header: Vec<u64> = (0..4).map_while(|k| s.word(start + 8 * k)).collect();
    let [blocks, total, min, max] = header[..] else {
        let expected = "numEntityBlocks, the total, the smallest and the largest tag (4 size_t)";
        return Err(malformed(name, start, expected, format!("the end of ${name}")));
    };
    s.declared = (blocks, total);
    let Some(walked) = s.walk()? else {
        return Ok((Vec::new(), (min, max)));
    };
    s.counted("entity blocks", blocks, walked.len() as u64)?;
    s.counted(what[0], total, walked.iter().map(|b| b.n).sum())?;
    let mut tags: Vec<Tag> = Vec::new();
    for b in &walked {
        for i in 0..b.n as usize {
            let at = tag_at(b, i);
            tags.push((
                s.word(at)
                    .expect("invariant: the walk kept every block in the section"),
                at,
            ));
        }
    }
    Ok((tags, (min, max)))
}

/// An error at byte `at` of section `$name`.
fn malformed(name: &str, at: usize, expected: &str, found: String) -> MeshError {
    MeshError::Malformed {
        section: format!("${name}"),
        at: format!("byte {at}"),
        expected: expected.to_string(),
        found,
    }
}

impl Section<'_> {
    /// The `size_t` at byte `at`, if it ends before the section does.
    fn word(&self, at: usize) -> Option<u64> {
        let b = self
            .bytes
            .get(at..at.checked_add(8).filter(|&e| e <= self.end)?)?;
        Some(u64::from_le_bytes(b.try_into().ok()?))
    }

    /// The `int` at byte `at`, if it ends before the section does.
    fn int(&self, at: usize) -> Option<i32> {
        let b = self
            .bytes
            .get(at..at.checked_add(4).filter(|&e| e <= self.end)?)?;
        Some(i32::from_le_bytes(b.try_into().ok()?))
    }

    /// Whether byte `at` is the end of the last block (a `\r` may stand before the `\n`).
    fn landed(&self, at: usize) -> bool {
        at == self.end || (at + 1 == self.end && self.bytes[at] == b'\r')
    }

    /// The block whose header is at byte `at`, or what its header says instead.
    fn block(&self, at: usize) -> Result<Block, Record> {
        let (Some(dim), Some(third), Some(n)) = (self.int(at), self.int(at + 8), self.word(at + 12)) else {
            return Err(Record::Invalid);
        };
        match (self.record)(dim, third) {
            Record::Bytes(record) => Ok(Block { at, record, n }),
            other => Err(other),
        }
    }

    /// Where the block `b` ends, if it ends in the section.
    fn after(&self, b: &Block) -> Option<usize> {
        let size =
            b.n.checked_mul(b.record as u64)?
                .checked_add(BLOCK_HEADER as u64)?;
        let next = (b.at as u64).checked_add(size)?;
        (next <= self.end as u64).then_some(next as usize)
    }

    /// The number of blocks from byte `at` and their records in all, walked by their counts, if
    /// they end where the section does; each block read takes one from `budget`, and none left
    /// is a no.
    fn rest(&self, mut at: usize, budget: &mut u64) -> Option<(u64, u64)> {
        let (mut blocks, mut total) = (0u64, 0u64);
        while !self.landed(at) {
            *budget = budget.checked_sub(1)?;
            let b = self.block(at).ok()?;
            at = self.after(&b)?;
            blocks += 1;
            total = total.checked_add(b.n)?;
        }
        Some((blocks, total))
    }

    /// The blocks of the section, walked by their counts (none before a block the reader does not
    /// take).
    fn walk(&self) -> Result<Option<Vec<Block>>, MeshError> {
        let (mut blocks, mut at) = (Vec::new(), self.start + 32);
        while !self.landed(at) {
            match self.block(at) {
                Ok(b) => match self.after(&b) {
                    Some(next) => {
                        blocks.push(b);
                        at = next;
                    }
                    None => return Err(self.miscounted(&blocks, Some(b), at)),
                },
                // A type the reader refuses later, by type, unless the walk ran off the blocks.
                Err(Record::Unsupported) => return self.recount(&blocks, None).map_or(Ok(None), Err),
                Err(_) => return Err(self.miscounted(&blocks, None, at)),
            }
        }
        Ok(Some(blocks))
    }

    /// The error when the walk stops at byte `at`, after the blocks `walked`, on block `failing`
    /// (that runs past the end of the section) or on a header that is none: a wrong count, when
    /// [`Section::recount`] finds one, else what stands at `at`.
    fn miscounted(&self, walked: &[Block], failing: Option<Block>, at: usize) -> MeshError {
        if let Some(e) = self.recount(walked, failing) {
            return e;
        }
        if let Some(b) = failing {
            let room = (self.end - b.at - BLOCK_HEADER) as u64 / b.record as u64;
            return self.mismatch(b.at, self.what[1], b.n, room);
        }
        let third = if self.name == "Nodes" {
            "parametric"
        } else {
            "elementType"
        };
        let found = match (self.int(at), self.int(at + 8)) {
            (Some(dim), Some(t)) => format!("entityDim {dim}, {third} {t}"),
            _ => quote(&self.bytes[at..self.end.min(at + 16)]),
        };
        let expected = format!(
            "a block (entityDim 0..3, a {third} the reader takes) or $End{}",
            self.name
        );
        malformed(self.name, at, &expected, found)
    }

    /// The count of a block of `walked` and `failing` with which the blocks end where the section
    /// does, as many as the header says with as many records, if one does. One wrong count sends
    /// the walk off into the records, where it may read a few blocks before it stops, so every
    /// block walked is a suspect: the count closest to the declared one wins, on the earliest
    /// block.
    fn recount(&self, walked: &[Block], failing: Option<Block>) -> Option<MeshError> {
        let mut suspects = Vec::new();
        let (mut blocks, mut total) = (0u64, 0u64);
        for b in walked.iter().copied().chain(failing) {
            suspects.push((b, blocks, total));
            blocks += 1;
            total = total.saturating_add(b.n);
        }
        let mut budget = BUDGET;
        for d in 1..=SEARCH {
            let mut tried = false;
            for &(b, blocks, total) in &suspects {
                let first = b.at + BLOCK_HEADER;
                let room = (self.end - first) as u64 / b.record as u64;
                for m in [b.n.checked_sub(d), b.n.checked_add(d)].into_iter().flatten() {
                    if m > room || budget == 0 {
                        continue;
                    }
                    tried = true;
                    let rest = self.rest(first + m as usize * b.record, &mut budget);
                    if rest.is_some_and(|(k, n)| (blocks + 1 + k, total + m + n) == self.declared) {
                        return Some(self.mismatch(b.at, self.what[0], b.n, m));
                    }
                }
            }
            if !tried {
                break;
            }
        }
        None
    }

    /// A declared count against the one found, in the header (`at` its start) or a block's.
    fn mismatch(&self, at: usize, what: &'static str, expected: u64, found: u64) -> MeshError {
        let block = if at == self.start { "" } else { " block" };
        MeshError::CountMismatch {
            section: format!("${}{block}", self.name),
            at: format!("byte {at}"),
            what,
            expected,
            found,
        }
    }

    /// A count of the header against the one walked.
    fn counted(&self, what: &'static str, expected: u64, found: u64) -> Result<(), MeshError> {
        if expected == found {
            return Ok(());
        }
        Err(self.mismatch(self.start, what, expected, found))
    }
}
