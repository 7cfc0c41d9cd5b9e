//! An MSH file seen as lines, for the scans of its text: each line by number, its fields and
//! numbers, sections found by their `$Name` lines, and the errors that name a line.

use super::MeshError;
use super::located::quote;

/// The file split into lines (without their `\n` and `\r`), numbered from 1.
pub(super) struct Lines<'a> {
    /// The whole file.
    bytes: &'a [u8],
    /// Byte offset of the start of each line.
    starts: Vec<usize>,
}

impl<'a> Lines<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Self {
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
    pub(super) fn len(&self) -> usize {
        self.starts.len()
    }

    /// Byte offset where line `i` (0-based) starts.
    pub(super) fn start_of(&self, i: usize) -> usize {
        self.starts.get(i).copied().unwrap_or(self.bytes.len())
    }

    /// Line `i` (0-based), trimmed of its line end.
    pub(super) fn get(&self, i: usize) -> &'a [u8] {
        let end = self.starts.get(i + 1).map_or(self.bytes.len(), |e| e - 1);
        let line = &self.bytes[self.starts[i]..end.max(self.starts[i])];
        let line = line.strip_suffix(b"\n").unwrap_or(line);
        line.strip_suffix(b"\r").unwrap_or(line)
    }

    /// The whitespace-separated fields of line `i`.
    pub(super) fn fields(&self, i: usize) -> Vec<&'a [u8]> {
        self.get(i)
            .split(|b| b.is_ascii_whitespace())
            .filter(|f| !f.is_empty())
            .collect()
    }

    /// First line at or after `from` that is exactly `$name`.
    pub(super) fn find_header(&self, name: &str, from: usize) -> Option<usize> {
        (from..self.len()).find(|&i| self.get(i).strip_prefix(b"$") == Some(name.as_bytes()))
    }

    /// The line of `$End<name>` closing the section opened on line `start`.
    pub(super) fn end_of(&self, name: &str, start: usize) -> Result<usize, MeshError> {
        let end = format!("End{name}");
        self.find_header(&end, start + 1)
            .ok_or_else(|| MeshError::Unclosed {
                section: format!("${name}"),
                line: start + 1,
            })
    }

    /// An error on line `i` (0-based) of `section`, quoting the line.
    pub(super) fn malformed(&self, section: &str, i: usize, expected: &str) -> MeshError {
        MeshError::Malformed {
            section: section.to_string(),
            at: format!("line {}", i + 1),
            expected: expected.to_string(),
            found: quote(self.get(i.min(self.len() - 1))),
        }
    }

    /// The numbers of line `i`, which must hold exactly `n` of type `T`.
    pub(super) fn numbers<T: std::str::FromStr>(
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

/// A count `expected` declared on line `line + 1` against the `found` one.
pub(super) fn counted(
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
pub(super) fn mismatch(
    section: &str,
    line: usize,
    what: &'static str,
    expected: u64,
    found: u64,
) -> MeshError {
    MeshError::CountMismatch {
        section: section.to_string(),
        at: format!("line {}", line + 1),
        what,
        expected,
        found,
    }
}
