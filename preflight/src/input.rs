//! User files read through a size cap, so that a wrong path (a device, a huge file) is refused
//! with its size before it fills the memory: scene files up to [`SCENE_CAP`], meshes up to
//! [`MESH_CAP`], each raised or lowered by an environment variable ([`SCENE_CAP_VAR`],
//! [`MESH_CAP_VAR`], a number of bytes; docs/scenes.md). The size the metadata gives is checked
//! before reading; a file without one (`/dev/zero`, a pipe) is read at most one byte past the cap.

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// Largest scene file read by default [bytes]: 16 MiB, far above any scene's few kilobytes.
pub const SCENE_CAP: u64 = 16 << 20;
/// Largest mesh file read by default [bytes]: 2 GiB, about 40 million nodes in ASCII.
pub const MESH_CAP: u64 = 2 << 30;
/// Environment variable that overrides [`SCENE_CAP`] (bytes).
pub const SCENE_CAP_VAR: &str = "COHESIVE_MAX_SCENE_BYTES";
/// Environment variable that overrides [`MESH_CAP`] (bytes).
pub const MESH_CAP_VAR: &str = "COHESIVE_MAX_MESH_BYTES";

/// A kind of user file, with its cap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cap {
    /// What the file is, for messages ("scene", "mesh").
    pub what: &'static str,
    /// Largest size read [bytes].
    pub bytes: u64,
    /// The variable that set or can set it.
    pub var: &'static str,
}

impl Cap {
    /// The cap of scene files: [`SCENE_CAP`], or [`SCENE_CAP_VAR`] when set.
    pub fn scene() -> Result<Cap, Error> {
        Cap::from_env("scene", SCENE_CAP, SCENE_CAP_VAR)
    }

    /// The cap of mesh files: [`MESH_CAP`], or [`MESH_CAP_VAR`] when set.
    pub fn mesh() -> Result<Cap, Error> {
        Cap::from_env("mesh", MESH_CAP, MESH_CAP_VAR)
    }

    /// `default` bytes, or the value of `var` when set; a value that is not a whole number of
    /// bytes is an error naming the variable.
    fn from_env(what: &'static str, default: u64, var: &'static str) -> Result<Cap, Error> {
        let bytes = match std::env::var(var) {
            Ok(v) => v.trim().parse().map_err(|_| {
                Error::new(
                    ErrorKind::InvalidInput,
                    format!("{var} = \"{v}\" is not a number of bytes"),
                )
            })?,
            Err(_) => default,
        };
        Ok(Cap { what, bytes, var })
    }

    /// The error for a file of `size` bytes ("more than" when only a read found it).
    fn too_large(&self, path: &Path, size: Option<u64>) -> Error {
        let size = match size {
            Some(s) => format!("is {s} bytes"),
            None => format!("holds more than {} bytes", self.bytes),
        };
        Error::new(
            ErrorKind::FileTooLarge,
            format!(
                "{} file {} {size}, above the cap of {} bytes for a {} file (set {} to change it)",
                self.what,
                path.display(),
                self.bytes,
                self.what,
                self.var
            ),
        )
    }
}

/// The bytes of the file at `path`, refused when it holds more than `cap`: before reading when
/// its metadata gives its size, else after reading `cap + 1` bytes at most.
pub fn read_capped(path: &Path, cap: Cap) -> Result<Vec<u8>, Error> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_file() && meta.len() > cap.bytes {
        return Err(cap.too_large(path, Some(meta.len())));
    }
    let mut bytes = Vec::new();
    file.take(cap.bytes.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap.bytes {
        return Err(cap.too_large(path, None));
    }
    Ok(bytes)
}

/// As [`read_capped`], as UTF-8 text.
pub fn read_text_capped(path: &Path, cap: Cap) -> Result<String, Error> {
    String::from_utf8(read_capped(path, cap)?)
        .map_err(|e| Error::new(ErrorKind::InvalidData, format!("not UTF-8 text: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: Cap = Cap {
        what: "scene",
        bytes: 1000,
        var: SCENE_CAP_VAR,
    };

    #[test]
    fn dev_zero_is_refused_after_the_cap() {
        let e = read_capped(Path::new("/dev/zero"), SMALL).unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains("/dev/zero") && m.contains("more than 1000 bytes") && m.contains(SCENE_CAP_VAR),
            "{m}"
        );
    }

    #[test]
    fn a_file_above_the_cap_is_refused_by_its_size() {
        let path = std::env::temp_dir().join(format!("preflight-cap-{}.toml", std::process::id()));
        std::fs::write(&path, vec![b'#'; 1001]).unwrap();
        let m = read_capped(&path, SMALL).unwrap_err().to_string();
        std::fs::write(&path, vec![b'#'; 1000]).unwrap();
        let fits = read_capped(&path, SMALL).map(|b| b.len());
        std::fs::remove_file(&path).unwrap();
        assert!(m.contains("is 1001 bytes, above the cap of 1000 bytes"), "{m}");
        assert_eq!(fits.unwrap(), 1000);
    }

    #[test]
    fn the_default_caps_are_16_mib_and_2_gib() {
        assert_eq!(SCENE_CAP, 16 * 1024 * 1024);
        assert_eq!(MESH_CAP, 2 * 1024 * 1024 * 1024);
    }
}
