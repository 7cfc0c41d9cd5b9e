//! Writing into an output folder: every file whole or not at all, never through a symbolic link.
//!
//! A file is written to a temporary file beside it (`.<name>.<pid>.tmp`), flushed to the disk,
//! then renamed over its name, so a crash, a kill or a full disk leaves the previous file (or
//! none), never a truncated one that looks whole. A rename replaces a symbolic link of that name
//! rather than writing through it, and [`subfolder`] refuses a subfolder that is a link, so that
//! no write or removal lands outside the folder the user chose.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// `e` with `path` in front, of the same kind: every error of a write names its file.
fn naming(path: &Path, e: io::Error) -> io::Error {
    io::Error::new(e.kind(), format!("{}: {e}", path.display()))
}

/// Writes the file `path` with `write`, atomically (see the module): the error names `path`, and
/// on any error the temporary file is removed and `path` is left as it was.
pub fn atomically<T>(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<File>) -> io::Result<T>,
) -> io::Result<T> {
    let name = path.file_name().ok_or_else(|| {
        naming(
            path,
            io::Error::new(io::ErrorKind::InvalidInput, "not a file name"),
        )
    })?;
    // a device, a socket or a pipe of that name is not a result file to replace
    if let Ok(m) = std::fs::symlink_metadata(path)
        && !(m.is_file() || m.is_symlink())
    {
        return Err(naming(
            path,
            io::Error::new(io::ErrorKind::InvalidInput, "not a regular file; not replaced"),
        ));
    }
    let tmp = path.with_file_name(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    // a temporary file left by a killed run of the same process id: it is ours to replace (an
    // error here, e.g. a folder that is a file, is the target's: it names the file asked for)
    match std::fs::remove_file(&tmp) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(naming(path, e)),
        _ => {}
    }
    let result = (|| {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        let mut w = BufWriter::new(file);
        let value = write(&mut w)?;
        let file = w.into_inner().map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)?;
        Ok(value)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        naming(path, e)
    })
}

/// Writes `bytes` as the file `path` ([`atomically`]).
pub fn bytes(path: &Path, bytes: &[u8]) -> io::Result<()> {
    atomically(path, |w| w.write_all(bytes))
}

/// Refuses `path` if it is a symbolic link: the error names it and says what to do.
pub fn not_a_link(path: &Path) -> io::Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!(
                "{} is a symbolic link; a run never writes or removes files through a link in its \
                 output folder: remove the link, or give another folder (--out)",
                path.display()
            ),
        )),
        _ => Ok(()),
    }
}

/// The subfolder `dir/name`, created if missing; refused if it is a symbolic link
/// ([`not_a_link`]) or not a folder.
pub fn subfolder(dir: &Path, name: &str) -> io::Result<PathBuf> {
    let sub = dir.join(name);
    not_a_link(&sub)?;
    std::fs::create_dir_all(&sub).map_err(|e| naming(&sub, e))?;
    Ok(sub)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("preflight-save-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A write that fails half-way (a full disk) leaves the previous file whole and no temporary
    /// file, and says which file.
    #[test]
    fn a_failed_write_keeps_the_previous_file_and_names_it() {
        let dir = scratch("fails");
        let path = dir.join("tips.csv");
        bytes(&path, b"whole\n").unwrap();
        let e = atomically(&path, |w| {
            w.write_all(b"half")?;
            Err::<(), _>(io::Error::new(
                io::ErrorKind::StorageFull,
                "no space left on device",
            ))
        })
        .unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        assert!(e.to_string().starts_with(&path.display().to_string()), "{e}");
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "whole\n");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "a temporary file left"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A file that is a link is replaced by the file, its target untouched; a linked subfolder
    /// is refused, named.
    #[test]
    fn links_are_replaced_or_refused_never_followed() {
        let dir = scratch("links");
        let target = dir.join("theirs.txt");
        std::fs::write(&target, "theirs").unwrap();
        std::os::unix::fs::symlink(&target, dir.join("run.csv")).unwrap();
        bytes(&dir.join("run.csv"), b"ours").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "theirs");
        assert!(
            !std::fs::symlink_metadata(dir.join("run.csv"))
                .unwrap()
                .is_symlink()
        );
        std::os::unix::fs::symlink(&dir, dir.join("fields")).unwrap();
        let e = subfolder(&dir, "fields").unwrap_err().to_string();
        assert!(e.contains("fields is a symbolic link"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A file in a folder that is not a folder is refused naming the file asked for, not the
    /// temporary file beside it.
    #[test]
    fn an_impossible_write_names_the_file_asked_for() {
        let dir = scratch("not-a-folder");
        let file = dir.join("plain");
        std::fs::write(&file, "x").unwrap();
        let path = file.join("run.csv");
        let e = bytes(&path, b"y").unwrap_err().to_string();
        assert!(e.starts_with(&format!("{}: ", path.display())), "{e}");
        assert!(!e.contains(".tmp"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A special file of that name (here a socket; a device such as /dev/full alike) is not
    /// replaced by a regular one.
    #[test]
    fn a_special_file_is_not_replaced() {
        let dir = scratch("special");
        let path = dir.join("run.csv");
        let _socket = std::os::unix::net::UnixListener::bind(&path).unwrap();
        let e = bytes(&path, b"x").unwrap_err().to_string();
        assert!(e.contains("run.csv") && e.contains("not a regular file"), "{e}");
        assert!(!std::fs::symlink_metadata(&path).unwrap().is_file());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
