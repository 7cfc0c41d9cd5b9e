//! What the two scans of an MSH file (`scan` for its text, `scan_binary` for a binary `$Nodes`)
//! report with: a node tag with where it stands, and a line quoted short.

/// At most this many bytes of a line are quoted in an error.
const QUOTE_BYTES: usize = 64;

/// A node tag as read, with the line (ASCII) or byte offset (binary) where it stands.
pub(super) type Tag = (u64, usize);

/// At most [`QUOTE_BYTES`] of `text`, cut on a character boundary, with "…" when cut.
pub(super) fn quote(text: &[u8]) -> String {
    let s = String::from_utf8_lossy(&text[..text.len().min(QUOTE_BYTES)]).into_owned();
    if text.len() > QUOTE_BYTES {
        format!("{}…", s.trim_end_matches('\u{FFFD}'))
    } else {
        s
    }
}
