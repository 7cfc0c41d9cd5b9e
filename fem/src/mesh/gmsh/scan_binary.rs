//! The `$Nodes` section of a binary MSH 4.1 file (little-endian, 8-byte `size_t`) walked for its
//! node tags, each with its byte offset: the counts must fit in the section, which must end with
//! `$EndNodes`.

use super::MeshError;
use super::located::{Tag, quote};

/// A cursor on the bytes of the file.
struct Cursor<'a> {
    /// The whole file.
    bytes: &'a [u8],
    /// Current byte offset.
    at: usize,
}

impl Cursor<'_> {
    /// The next `n` bytes, or an error naming what was being read.
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], MeshError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let Some(end) = end else {
            return Err(MeshError::Malformed {
                section: "$Nodes".into(),
                at: format!("byte {}", self.at),
                expected: what.to_string(),
                found: "the end of the file".into(),
            });
        };
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }

    fn u64(&mut self, what: &str) -> Result<u64, MeshError> {
        let b = self.take(8, what)?;
        Ok(u64::from_le_bytes(
            b.try_into().expect("invariant: 8 bytes taken"),
        ))
    }

    fn i32(&mut self, what: &str) -> Result<i32, MeshError> {
        let b = self.take(4, what)?;
        Ok(i32::from_le_bytes(
            b.try_into().expect("invariant: 4 bytes taken"),
        ))
    }
}

/// The node tags with their byte offsets and the header's tag range, from the `$Nodes` section
/// whose body starts at byte `start` (none without the section).
pub(super) fn binary_node_tags(
    bytes: &[u8],
    start: Option<usize>,
) -> Result<(Vec<Tag>, (u64, u64)), MeshError> {
    let Some(start) = start else {
        return Ok((Vec::new(), (0, 0)));
    };
    let mut c = Cursor { bytes, at: start };
    let blocks = c.u64("numEntityBlocks")?;
    let num_nodes = c.u64("numNodes")?;
    let range = (c.u64("minNodeTag")?, c.u64("maxNodeTag")?);
    let mut tags: Vec<Tag> = Vec::new();
    for _ in 0..blocks {
        let block_at = c.at;
        let dim = c.i32("entityDim")?;
        c.i32("entityTag")?;
        let parametric = c.i32("parametric")?;
        let n = c.u64("numNodesInBlock")?;
        if !(0..=3).contains(&dim) || !(0..=1).contains(&parametric) {
            return Err(MeshError::Malformed {
                section: "$Nodes".into(),
                at: format!("byte {block_at}"),
                expected: "a block: entityDim 0..3, parametric 0 or 1".into(),
                found: format!("entityDim {dim}, parametric {parametric}"),
            });
        }
        let width = 3 + if parametric == 1 { dim as usize } else { 0 };
        let room = (bytes.len() - c.at) as u64 / (8 + 8 * width as u64);
        if n > room {
            return Err(MeshError::CountMismatch {
                section: "$Nodes block".into(),
                at: format!("byte {block_at}"),
                what: "nodes (at most, by the bytes left)",
                expected: n,
                found: room,
            });
        }
        for _ in 0..n {
            let at = c.at;
            tags.push((c.u64("a node tag")?, at));
        }
        c.take(8 * width * n as usize, "node coordinates")?;
    }
    if tags.len() as u64 != num_nodes {
        return Err(MeshError::CountMismatch {
            section: "$Nodes".into(),
            at: format!("byte {start}"),
            what: "nodes",
            expected: num_nodes,
            found: tags.len() as u64,
        });
    }
    let rest = &bytes[c.at..];
    let rest = rest.strip_prefix(b"\r").unwrap_or(rest);
    if !rest.strip_prefix(b"\n").unwrap_or(rest).starts_with(b"$EndNodes") {
        return Err(MeshError::Malformed {
            section: "$Nodes".into(),
            at: format!("byte {}", c.at),
            expected: "$EndNodes".into(),
            found: quote(&rest[..rest.len().min(16)]),
        });
    }
    Ok((tags, range))
}
