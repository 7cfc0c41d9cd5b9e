//! The CSV files of a run's records ([`crate::records`], docs/solver-api.md), and the ParaView
//! field files ([`paraview`]); the only module that writes files.

pub mod paraview;

use crate::records::RunOutput;
use serde::Serialize;
use std::io;
use std::path::{Path, PathBuf};

fn write<T: Serialize>(dir: &Path, name: &str, rows: &[T], out: &mut Vec<PathBuf>) -> io::Result<()> {
    debug_assert!(
        CSV_FILES.contains(&name),
        "{name} missing from CSV_FILES (clear_previous)"
    );
    let path = dir.join(name);
    // whole or not at all, the error naming the file (docs/outputs.md)
    preflight::save::atomically(&path, |file| {
        let mut w = csv::Writer::from_writer(file);
        for r in rows {
            w.serialize(r).map_err(io::Error::other)?;
        }
        w.flush()
    })?;
    out.push(path);
    Ok(())
}

/// A row of boundary.csv: a [`BoundaryRecord`] with its part by name.
#[derive(Serialize)]
struct BoundaryRow<'a> {
    t: f64,
    part: &'a str,
    ux: f64,
    uy: f64,
    fx: f64,
    fy: f64,
}

fn boundary_rows(output: &RunOutput) -> Vec<BoundaryRow<'_>> {
    output
        .boundary
        .iter()
        .map(|r| BoundaryRow {
            t: r.t,
            part: &output.boundary_parts[r.part as usize],
            ux: r.ux,
            uy: r.uy,
            fx: r.fx,
            fy: r.fy,
        })
        .collect()
}

/// Every CSV file [`write_csv`] may write: a run writes a subset, depending on the scene.
pub const CSV_FILES: [&str; 16] = [
    "run.csv",
    "tips.csv",
    "cracks.csv",
    "crack_tips.csv",
    "interface.csv",
    "faces.csv",
    "contact.csv",
    "energy.csv",
    "arrivals.csv",
    "probes.csv",
    "boundary.csv",
    "friction.csv",
    "residual_stress.csv",
    "kkt.csv",
    "field.csv",
    "profile.csv",
];

/// Removes from `dir` the files an earlier run of the model left there ([`CSV_FILES`], `fields.pvd` and
/// the snapshots in `fields/`), so that the folder holds one run's output only: a scene that no
/// longer writes a file (no pre-crack, no friction, another snapshot interval) would otherwise
/// leave the old one beside the new ones. Returns the number of files removed. Only for a
/// folder claimed by this model (`preflight::paths::claim`): nothing else is touched, and a
/// `fields/` that is a symbolic link is refused, not followed.
pub fn clear_previous(dir: &Path) -> io::Result<usize> {
    let fields = dir.join(paraview::FIELDS_DIR);
    // a linked fields/ would have the run remove files outside its folder
    preflight::save::not_a_link(&fields)?;
    let mut snapshots: Vec<PathBuf> = std::fs::read_dir(&fields)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| paraview::is_snapshot_file(p))
                .collect()
        })
        .unwrap_or_default();
    snapshots.sort();
    let files = CSV_FILES
        .iter()
        .chain([&paraview::COLLECTION])
        .map(|name| dir.join(name));
    preflight::paths::remove_files(files.chain(snapshots))
}

/// Writes run.csv, tips.csv (with a pre-crack), cracks.csv and crack_tips.csv (with an
/// interface), interface.csv, faces.csv, contact.csv, energy.csv, arrivals.csv, probes.csv,
/// boundary.csv (with `[fem.boundary]`), friction.csv (with friction) and, when declared,
/// residual_stress.csv, kkt.csv, field.csv, profile.csv into `dir`.
pub fn write_csv(output: &RunOutput, dir: &Path) -> io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir)?;
    // interface.csv, the largest file, on one thread while the others are written on another:
    // the files do not depend on each other, and each is written by one writer in row order.
    let (interface, rest) = rayon::join(
        || {
            let mut out = Vec::new();
            write(dir, "interface.csv", &output.interface, &mut out).map(|_| out)
        },
        || {
            let mut out = Vec::new();
            write(dir, "run.csv", &[output.record()], &mut out)?;
            // tips exist only from a pre-crack; the per-chain extents on any interface
            if !output.tips.is_empty() {
                write(dir, "tips.csv", &output.tips, &mut out)?;
            }
            if !output.cracks.is_empty() {
                write(dir, "cracks.csv", &output.cracks, &mut out)?;
                write(dir, "crack_tips.csv", &output.crack_tips, &mut out)?;
            }
            write(dir, "faces.csv", &output.faces, &mut out)?;
            write(dir, "contact.csv", &output.contact, &mut out)?;
            write(dir, "energy.csv", &output.energy, &mut out)?;
            write(dir, "arrivals.csv", &output.arrivals, &mut out)?;
            write(dir, "probes.csv", &output.probes, &mut out)?;
            if !output.boundary.is_empty() {
                write(dir, "boundary.csv", &boundary_rows(output), &mut out)?;
            }
            if !output.friction.is_empty() {
                write(dir, "friction.csv", &output.friction, &mut out)?;
            }
            // the Section 4 diagnostics exist only when the scene declares them
            if !output.residual_stress.is_empty() {
                write(dir, "residual_stress.csv", &output.residual_stress, &mut out)?;
            }
            if !output.kkt.is_empty() {
                write(dir, "kkt.csv", &output.kkt, &mut out)?;
            }
            if !output.fields.is_empty() {
                write(dir, "field.csv", &output.fields, &mut out)?;
                write(dir, "profile.csv", &output.profiles, &mut out)?;
            }
            Ok::<_, io::Error>(out)
        },
    );
    let mut out = rest?;
    out.insert(2, interface?.remove(0));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clearing_removes_the_model_files_and_nothing_else() {
        let dir = std::env::temp_dir().join(format!("fem-clear-previous-{}", std::process::id()));
        let fields = dir.join(paraview::FIELDS_DIR);
        std::fs::create_dir_all(&fields).unwrap();
        let ours = [
            "tips.csv",
            "friction.csv",
            "fields.pvd",
            "fields/bulk_000000.vtu",
            "fields/crack_0001234.vtu",
        ];
        let theirs = [
            "notes.txt",
            "tips.csv.bak",
            "fields/bulk_final.vtu",
            "fields/mine.vtu",
            ".written-by",
        ];
        for f in ours.iter().chain(&theirs) {
            std::fs::write(dir.join(f), "x").unwrap();
        }
        assert_eq!(clear_previous(&dir).unwrap(), ours.len());
        for f in ours {
            assert!(!dir.join(f).exists(), "{f} kept");
        }
        for f in theirs {
            assert!(dir.join(f).exists(), "{f} removed");
        }
        // a second call finds nothing; a folder without fields/ is fine
        assert_eq!(clear_previous(&dir).unwrap(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(clear_previous(&dir).unwrap(), 0);
    }

    /// A `fields/` that is a symbolic link is not followed: the snapshots it points at, outside
    /// the output folder, are not the run's to remove.
    #[test]
    fn a_linked_fields_folder_is_refused_and_its_target_untouched() {
        let root = std::env::temp_dir().join(format!("fem-linked-fields-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let (dir, elsewhere) = (root.join("out"), root.join("elsewhere"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::create_dir_all(&elsewhere).unwrap();
        std::fs::write(elsewhere.join("bulk_000000.vtu"), "theirs").unwrap();
        std::os::unix::fs::symlink(&elsewhere, dir.join(paraview::FIELDS_DIR)).unwrap();
        let e = clear_previous(&dir).unwrap_err().to_string();
        assert!(e.contains("symbolic link") && e.contains("fields"), "{e}");
        assert!(
            elsewhere.join("bulk_000000.vtu").exists(),
            "removed through the link"
        );
        let e = paraview::ParaviewWriter::new(&dir, 10).unwrap_err().to_string();
        assert!(e.contains("symbolic link") && e.contains("fields"), "{e}");
        std::fs::remove_dir_all(&root).unwrap();
    }

    /// A file that cannot be written is named in the error, and the file it would have replaced
    /// is left whole.
    #[test]
    fn a_failed_write_names_the_file_and_keeps_the_previous_one() {
        let dir = std::env::temp_dir().join(format!("fem-write-fails-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("run.csv")).unwrap();
        std::fs::write(dir.join("energy.csv"), "an earlier run's whole file").unwrap();
        let e = write_csv(&RunOutput::default(), &dir).unwrap_err().to_string();
        assert!(e.contains(&dir.join("run.csv").display().to_string()), "{e}");
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().all(|n| !n.contains(".tmp")), "{names:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A run without fracture has no damping share: run.csv leaves the field empty instead of
    /// writing NaN, which reads as a failed computation.
    #[test]
    fn a_run_without_fracture_writes_no_damping_share() {
        let dir = std::env::temp_dir().join(format!("fem-run-csv-{}", std::process::id()));
        write_csv(&RunOutput::default(), &dir).unwrap();
        let text = std::fs::read_to_string(dir.join("run.csv")).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        let at = header.iter().position(|c| *c == "damping_share").unwrap();
        assert_eq!(row[at], "", "{text}");
        assert!(!text.contains("NaN"), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
