//! Output folders: a scene's name becomes a folder name only once it cannot leave `out/`, an
//! explicit folder may not be empty, a folder is claimed (created, written to, marked with the
//! model that writes it) before the first time step, and two models never share one.

use std::path::Path;

/// Marker file naming the model whose output a folder holds.
pub const MARKER: &str = ".written-by";

/// `name` as a single folder name: characters other than ASCII letters, digits, `-`, `_` and `.`
/// become `_`, leading dots are dropped (no `..`, no hidden folder), and an empty result becomes
/// `unnamed`. `"../../x"` gives `_.._x`, `"/abs/path"` gives `_abs_path`.
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
    if trimmed.is_empty() {
        "unnamed".to_string()
    } else {
        trimmed.to_string()
    }
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

/// Creates `dir` and marks it as written by `model`, before any work: a folder that cannot be
/// created or written to, that holds another model's output, or that holds files without a marker
/// (the user's own: a run removes and overwrites the files it writes) is refused now rather than
/// after the run.
pub fn claim(dir: &Path, model: &str) -> Result<(), String> {
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
            let mut entries = std::fs::read_dir(dir)
                .map_err(|e| format!("output folder {}: cannot list it: {e}", dir.display()))?;
            if let Some(entry) = entries.next() {
                let name =
                    entry.map_or_else(|_| "?".into(), |e| e.file_name().to_string_lossy().into_owned());
                return Err(format!(
                    "output folder {} already holds files (e.g. {name}) that this program did not \
                     write (it has no {MARKER}); a run would overwrite or remove some of them: give \
                     a new or empty folder (--out)",
                    dir.display()
                ));
            }
        }
    }
    std::fs::write(&marker, format!("{model}\n"))
        .map_err(|e| format!("output folder {}: cannot write to it: {e}", dir.display()))
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
        assert_eq!(folder_name("../../x"), "_.._x");
        assert_eq!(folder_name("/etc/passwd"), "_etc_passwd");
        assert_eq!(folder_name(".."), "unnamed");
        assert_eq!(folder_name(""), "unnamed");
        assert_eq!(folder_name("a b\\c"), "a_b_c");
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
        claim(&dir, "fem").unwrap();
        claim(&dir, "fem").unwrap();
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
        claim(&dir, "fem").unwrap();
        std::fs::remove_file(dir.join(MARKER)).unwrap();
        std::fs::write(dir.join("run.csv"), "mine").unwrap();
        let e = claim(&dir, "fem").unwrap_err();
        assert!(e.contains("run.csv") && e.contains("did not write"), "{e}");
        assert_eq!(std::fs::read_to_string(dir.join("run.csv")).unwrap(), "mine");
        assert!(!dir.join(MARKER).exists(), "refused, yet claimed");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
