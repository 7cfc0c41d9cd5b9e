//! What the scans of an MSH file (`scan`, `scan_elements` for its text, `scan_binary` for binary
//! sections) share: a tag with where it stands, the tag rules of a section, the node count of the
//! element types read, and a line quoted short.

use super::MeshError;

/// At most this many bytes of a line are quoted in an error.
const QUOTE_BYTES: usize = 64;

/// A node or element tag as read, with the line (ASCII) or byte offset (binary) where it stands.
pub(super) type Tag = (u64, usize);

/// The tags of a section as read, with the range of its header.
pub(super) type Tags = (Vec<Tag>, (u64, u64));

/// At most [`QUOTE_BYTES`] of `text`, cut on a character boundary, with "…" when cut.
pub(super) fn quote(text: &[u8]) -> String {
    let s = String::from_utf8_lossy(&text[..text.len().min(QUOTE_BYTES)]).into_owned();
    if text.len() > QUOTE_BYTES {
        format!("{}…", s.trim_end_matches('\u{FFFD}'))
    } else {
        s
    }
}

/// Nodes per element of the Gmsh types the reader takes (others are refused later, by type).
pub(super) fn nodes_per_element(element_type: u64) -> Option<usize> {
    match element_type {
        1 => Some(2),
        2 => Some(3),
        3 => Some(4),
        15 => Some(1),
        _ => None,
    }
}

/// Whose tags are checked.
#[derive(Clone, Copy)]
pub(super) enum Owner {
    /// The nodes of `$Nodes`.
    Node,
    /// The elements of `$Elements`.
    Element,
}

/// Every tag in the header's `range`, non-zero, defined once; `binary` says whether the places
/// are byte offsets rather than lines.
pub(super) fn check_tags(owner: Owner, (tags, range): &Tags, binary: bool) -> Result<(), MeshError> {
    let place = |at: usize| {
        if binary {
            format!("byte {at}")
        } else {
            format!("line {at}")
        }
    };
    let bad = |tag, at, reason| match owner {
        Owner::Node => MeshError::BadNodeTag { tag, at, reason },
        Owner::Element => MeshError::BadElementTag { tag, at, reason },
    };
    let section = match owner {
        Owner::Node => "$Nodes",
        Owner::Element => "$Elements",
    };
    for &(tag, at) in tags {
        if tag == 0 || tag < range.0 || tag > range.1 {
            let reason = format!(
                "outside the range {}..={} of the {section} header (and 0 is reserved)",
                range.0, range.1
            );
            return Err(bad(tag, place(at), reason));
        }
    }
    let mut sorted = tags.to_vec();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0].0 == w[1].0) {
        let reason = format!("defined twice (first at {})", place(w[0].1));
        return Err(bad(w[1].0, place(w[1].1), reason));
    }
    Ok(())
}
