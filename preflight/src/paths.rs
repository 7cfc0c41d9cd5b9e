//! Output folders: a scene's name becomes a folder name only once it cannot leave `out/`, an
//! explicit folder may not be empty, a folder is claimed (created, written to, marked with the
//! model that writes it) before the first time step, and two models never share one.

use std::path::Path;

/// Marker file naming the model whose output a folder holds.
pub const MARKER: &str = ".written-by";

/// `name` as a single folder name: characters other than ASCII letters, digits, `-`, `_` and `.`
/// become `_`, leading dots are dropped (no `..`, no hidden folder), and an empty result becomes
/// `unnamed`. When that changed the name, a short hash of the original is appended, so that two
/// names that clean up alike (`a b` and `a:b`) never share a folder: `"../../x"` gives
/// `_.._x-<8 hex digits>`, `"center-crack"` stays `center-crack`.
pub fn folder_name(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let trimmed = cleaned.trim_start_matches('.');
    let safe = if trimmed.is_empty() { "unnamed" } else { trimmed };
    if safe == name {
        safe.to_string()
    } else {
        format!("{safe}-{:08x}", fnv1a(name.as_bytes()) as u32)
    }
}

/// FNV-1a, 64 bits: a fixed, portable hash (the same folder name on every machine and Rust
/// version, unlike std's `DefaultHasher`).
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// An explicit output folder (`--out`): refused when empty, since it would write into the
/// working directory.
pub fn explicit(dir: &Path) -> Result<&Path, String> {
    if dir.as_os_str().is_empty() {
        Err("--out \"\": give a folder (an empty one would write into the working directory)".to_string())
    } else {
        Ok(dir)
    }
}

/// Lock file of a folder's run: while a run holds it (an exclusive `flock`, which the system
/// releases when the process ends, however it ends), it names that run's process and command
/// line; a run that ends empties it.
pub const LOCK: &str = ".run.lock";

/// A claimed output folder, held until dropped: no other run (of any command, in any process)
/// writes into it meanwhile. Keep it for the whole run, writing included.
#[derive(Debug)]
#[must_use = "the folder is released when the claim is dropped"]
pub struct Claim {
    file: std::fs::File,
    taken_over: Option<String>,
}

impl Claim {
    /// The note to print when the folder's lock named a process that ended without releasing it
    /// (killed, or the machine went down): its run's output there is incomplete and is replaced.
    pub fn taken_over(&self) -> Option<&str> {
        self.taken_over.as_deref()
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        // empty: the next run finds no owner to report; the lock itself goes with the handle
        let _ = self.file.set_len(0);
    }
}

/// `pid <id>: <command line>` of this process, as a lock names it.
fn this_run() -> String {
    let args: Vec<String> = std::env::args().collect();
    format!("process {}: {}", std::process::id(), args.join(" "))
}

/// Takes the lock of `dir` ([`LOCK`]), or says which run holds it.
fn lock(dir: &Path) -> Result<Claim, String> {
    let path = dir.join(LOCK);
    if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
        return Err(format!(
            "output folder {}: {LOCK} is a symbolic link; remove it (a run never follows links in its folder)",
            dir.display()
        ));
    }
    let cannot = |e: std::io::Error| format!("output folder {}: cannot write to it: {e}", dir.display());
    let mut file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(cannot)?;
    let mut holder = String::new();
    match file.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => {
            let _ = std::io::Read::read_to_string(&mut file, &mut holder);
            let holder = holder.trim();
            let holder = if holder.is_empty() {
                "another process"
            } else {
                holder
            };
            return Err(format!(
                "output folder {} is in use by another run ({holder}); two runs in one folder \
                 would mix or lose their files: wait for it to end, or give another folder (--out)",
                dir.display()
            ));
        }
        Err(std::fs::TryLockError::Error(e)) => return Err(cannot(e)),
    }
    std::io::Read::read_to_string(&mut file, &mut holder).map_err(cannot)?;
    let holder = holder.trim();
    let taken_over = (!holder.is_empty()).then(|| {
        format!(
            "output folder {}: the run that held it ({holder}) ended without releasing it; its \
             output there is incomplete and is replaced by this run's",
            dir.display()
        )
    });
    file.set_len(0).map_err(cannot)?;
    std::io::Write::write_all(&mut &file, format!("{}\n", this_run()).as_bytes()).map_err(cannot)?;
    Ok(Claim { file, taken_over })
}

/// Creates `dir`, checks it and marks it as written by `model`, before any work, and locks it
/// for this run: a folder that cannot be created or written to, that another run holds (named
/// by its process and command line), that holds another model's output, or that holds files
/// without a marker (the user's own: a run removes and overwrites the files it writes) is
/// refused now rather than after the run. The folder stays locked until the [`Claim`] is
/// dropped.
pub fn claim(dir: &Path, model: &str) -> Result<Claim, String> {
    std::fs::create_dir_all(dir)
        .map_err(|e| format!("output folder {}: cannot create it: {e}", dir.display()))?;
    let marker = dir.join(MARKER);
    match std::fs::read_to_string(&marker) {
        Ok(owner) => {
            let owner = owner.trim();
            if owner != model {
                return Err(format!(
                    "output folder {} holds the output of the {owner} model; give the {model} \
                     model another folder (--out)",
                    dir.display()
                ));
            }
        }
        Err(_) => {
            let entries = std::fs::read_dir(dir)
                .map_err(|e| format!("output folder {}: cannot list it: {e}", dir.display()))?;
            let theirs = entries
                .map(|e| e.map_or_else(|_| "?".into(), |e| e.file_name().to_string_lossy().into_owned()))
                .find(|name| name != LOCK);
            if let Some(name) = theirs {
                return Err(format!(
                    "output folder {} already holds files (e.g. {name}) that this program did not \
                     write (it has no {MARKER}); a run would overwrite or remove some of them: give \
                     a new or empty folder (--out)",
                    dir.display()
                ));
            }
        }
    }
    let claim = lock(dir)?;
    std::fs::write(&marker, format!("{model}\n"))
        .map_err(|e| format!("output folder {}: cannot write to it: {e}", dir.display()))?;
    Ok(claim)
}

/// Removes the files `paths` that exist (a claimed folder's earlier output, so that it holds one
/// run's files only); a missing file is not an error. Returns how many were removed.
pub fn remove_files(paths: impl IntoIterator<Item = std::path::PathBuf>) -> std::io::Result<usize> {
    let mut removed = 0;
    for path in paths {
        match std::fs::remove_file(&path) {
            Ok(()) => removed += 1,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(e),
        }
    }
    Ok(removed)
}

/// The note for a run's first line after [`remove_files`]: empty when nothing was removed.
pub fn removed_note(removed: usize) -> String {
    if removed > 0 {
        format!(" (the previous run's {removed} files removed)")
    } else {
        String::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_cannot_leave_the_output_folder() {
        assert_eq!(folder_name("center-crack"), "center-crack");
        assert!(folder_name("../../x").starts_with("_.._x-"));
        assert!(folder_name("/etc/passwd").starts_with("_etc_passwd-"));
        assert!(folder_name("..").starts_with("unnamed-"));
        assert!(folder_name("").starts_with("unnamed-"));
        assert!(folder_name("a b\\c").starts_with("a_b_c-"));
        for n in ["../../x", "/abs", "..", "a/../../b"] {
            let f = folder_name(n);
            assert!(
                !f.contains('/') && !f.contains('\\') && !f.starts_with('.'),
                "{n} → {f}"
            );
        }
    }

    #[test]
    fn an_empty_out_is_refused() {
        assert!(explicit(Path::new("")).is_err());
        assert!(explicit(Path::new("out/x")).is_ok());
    }

    #[test]
    fn a_folder_belongs_to_one_model() {
        let dir = std::env::temp_dir().join(format!("preflight-claim-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        drop(claim(&dir, "fem").unwrap());
        drop(claim(&dir, "fem").unwrap());
        let e = claim(&dir, "spectral").unwrap_err();
        assert!(e.contains("fem model"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A folder of the user's own files is not a run's to clear: its run.csv would be removed.
    #[test]
    fn a_folder_of_other_files_is_refused_and_an_empty_one_claimed() {
        let dir = std::env::temp_dir().join(format!("preflight-claim-theirs-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        drop(claim(&dir, "fem").unwrap());
        std::fs::remove_file(dir.join(MARKER)).unwrap();
        std::fs::write(dir.join("run.csv"), "mine").unwrap();
        let e = claim(&dir, "fem").unwrap_err();
        assert!(e.contains("run.csv") && e.contains("did not write"), "{e}");
        assert_eq!(std::fs::read_to_string(dir.join("run.csv")).unwrap(), "mine");
        assert!(!dir.join(MARKER).exists(), "refused, yet claimed");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Two runs into one folder would remove and overwrite each other's files: the second is
    /// refused while the first holds the folder, and its message names the first's process.
    #[test]
    fn a_folder_takes_one_run_at_a_time() {
        let dir = std::env::temp_dir().join(format!("preflight-claim-busy-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let first = claim(&dir, "fem").unwrap();
        let e = claim(&dir, "fem").unwrap_err();
        assert!(
            e.contains("in use") && e.contains(&format!("process {}", std::process::id())),
            "{e}"
        );
        drop(first);
        let _again = claim(&dir, "fem").unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Scene files whose names differ only in characters a folder name cannot hold get
    /// different default folders; a name kept as it is stays as it is.
    #[test]
    fn names_that_sanitise_alike_stay_apart() {
        assert_ne!(folder_name("a b"), folder_name("a_b"));
        assert_ne!(folder_name("a b"), folder_name("a:b"));
        assert_ne!(folder_name(".x"), folder_name("x"));
        assert_eq!(folder_name("a_b"), "a_b");
        assert_eq!(folder_name("a b"), folder_name("a b"));
    }

    /// A lock left by a process that ended without releasing it (killed) is taken over, and the
    /// claim says whose it was.
    #[test]
    fn a_dead_run_s_lock_is_taken_over_and_named() {
        let dir = std::env::temp_dir().join(format!("preflight-claim-stale-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        drop(claim(&dir, "fem").unwrap());
        assert!(claim(&dir, "fem").unwrap().taken_over().is_none());
        std::fs::write(dir.join(LOCK), "process 4194304: fem scene.toml\n").unwrap();
        let c = claim(&dir, "fem").unwrap();
        let note = c.taken_over().unwrap();
        assert!(note.contains("process 4194304: fem scene.toml"), "{note}");
        drop(c);
        assert_eq!(std::fs::read_to_string(dir.join(LOCK)).unwrap(), "");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
