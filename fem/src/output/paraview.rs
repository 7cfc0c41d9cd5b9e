//! ParaView field output: each snapshot as VTK UnstructuredGrid XML files (`.vtu`, written and
//! read with `vtkio`), the series as a ParaView collection (`fields.pvd`: time → files).
//! docs/outputs.md lists the files, the arrays and their units.
//!
//! The pieces are generic unstructured meshes (points, cells of VTK type line 3, triangle 5 or
//! quad 9, point and cell arrays), so other meshes can reuse the writer. Arrays are written in
//! VTK's inline binary form (base64 of little-endian f64): a value read back is the value written,
//! to the bit, and the files are identical byte for byte between runs of the same scene.

use crate::records::fields::{CellShape, FieldArray, FieldPiece, FieldSink, FieldSnapshot, FieldValues};
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, ElementType, IOBuffer, Piece,
    UnstructuredGridPiece, Version, VertexNumbers, Vtk,
};

/// VTK's cell type of a shape.
fn vtk_cell(shape: CellShape) -> CellType {
    match shape {
        CellShape::Line => CellType::Line,
        CellShape::Triangle => CellType::Triangle,
        CellShape::Quad => CellType::Quad,
    }
}

/// Folder of the snapshot files inside the run's output folder.
pub const FIELDS_DIR: &str = "fields";

/// The collection file, beside [`FIELDS_DIR`].
pub const COLLECTION: &str = "fields.pvd";

/// Whether `path` is a snapshot file as [`ParaviewWriter`] names them: `bulk_<digits>.vtu` or
/// `crack_<digits>.vtu`.
pub fn is_snapshot_file(path: &Path) -> bool {
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return false;
    };
    let Some(stem) = name.strip_suffix(".vtu") else {
        return false;
    };
    let digits = stem.strip_prefix("bulk_").or_else(|| stem.strip_prefix("crack_"));
    digits.is_some_and(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
}

/// Writes each snapshot as `fields/bulk_<step>.vtu` (+ `fields/crack_<step>.vtu`) at once, and the
/// collection `fields.pvd` listing them in [`ParaviewWriter::finish`].
#[derive(Debug)]
pub struct ParaviewWriter {
    dir: PathBuf,
    digits: usize,
    /// (time [s], files relative to `dir`) per snapshot, in the order taken.
    written: Vec<(f64, Vec<String>)>,
}

impl ParaviewWriter {
    /// A writer into `dir` for a run of `steps` steps (the step numbers in the file names are
    /// zero-padded to its width, at least 6 digits, so that the files sort in time order).
    /// Creates `dir/fields`: a folder that cannot be created, or a `fields` that is a symbolic
    /// link (the snapshots would land outside the output folder), is refused before the run.
    pub fn new(dir: &Path, steps: u64) -> io::Result<ParaviewWriter> {
        preflight::save::subfolder(dir, FIELDS_DIR)?;
        Ok(ParaviewWriter {
            dir: dir.to_path_buf(),
            digits: steps.to_string().len().max(6),
            written: Vec::new(),
        })
    }

    /// Snapshots written so far.
    pub fn snapshots(&self) -> usize {
        self.written.len()
    }

    /// Writes `fields.pvd`: every snapshot written, in time order, the bulk as part 0 and the
    /// crack as part 1 (ParaView shows them as two blocks). Returns its path.
    pub fn finish(&self) -> io::Result<PathBuf> {
        let mut text = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, files) in &self.written {
            for (part, file) in files.iter().enumerate() {
                let name = if part == 0 { "bulk" } else { "crack" };
                writeln!(
                    text,
                    "    <DataSet timestep=\"{t:e}\" group=\"\" part=\"{part}\" name=\"{name}\" file=\"{file}\"/>"
                )
                .expect("invariant: writing to a String cannot fail");
            }
        }
        text.push_str("  </Collection>\n</VTKFile>\n");
        let path = self.dir.join(COLLECTION);
        preflight::save::bytes(&path, text.as_bytes())?;
        Ok(path)
    }
}

impl FieldSink for ParaviewWriter {
    fn snapshot(&mut self, snapshot: FieldSnapshot) -> io::Result<()> {
        let digits = self.digits;
        let step = snapshot.step;
        let mut files = Vec::new();
        for (name, piece) in [("bulk", Some(snapshot.bulk)), ("crack", snapshot.crack)] {
            let Some(piece) = piece else { continue };
            let file = format!("{FIELDS_DIR}/{name}_{step:0digits$}.vtu");
            write_vtu(&self.dir.join(&file), piece)?;
            files.push(file);
        }
        self.written.push((snapshot.t, files));
        Ok(())
    }

    fn taken(&self) -> Vec<(f64, Vec<String>)> {
        self.written.clone()
    }

    fn resume(&mut self, taken: Vec<(f64, Vec<String>)>) -> io::Result<()> {
        let listed: std::collections::HashSet<&str> =
            taken.iter().flat_map(|(_, f)| f).map(String::as_str).collect();
        let fields = self.dir.join(FIELDS_DIR);
        let mut after = Vec::new();
        for entry in std::fs::read_dir(&fields)? {
            let path = entry?.path();
            let name = format!(
                "{FIELDS_DIR}/{}",
                path.file_name().unwrap_or_default().to_string_lossy()
            );
            if is_snapshot_file(&path) && !listed.contains(name.as_str()) {
                after.push(path);
            }
        }
        preflight::paths::remove_files(after)?;
        self.written = taken;
        Ok(())
    }
}

fn vtk_array(a: FieldArray) -> Attribute {
    let (elem, data) = match a.values {
        FieldValues::Scalars(v) => (scalars(), IOBuffer::F64(v)),
        FieldValues::Vectors(v) => (
            ElementType::Vectors,
            IOBuffer::F64(v.iter().flat_map(|p| [p[0], p[1], 0.0]).collect()),
        ),
        FieldValues::Integers(v) => (scalars(), IOBuffer::I32(v)),
    };
    Attribute::DataArray(DataArray {
        name: a.name,
        elem,
        data,
    })
}

fn scalars() -> ElementType {
    ElementType::Scalars {
        num_comp: 1,
        lookup_table: None,
    }
}

/// Writes `piece` as a VTK UnstructuredGrid XML file at `path`.
pub fn write_vtu(path: &Path, piece: FieldPiece) -> io::Result<()> {
    let vtk = Vtk {
        version: Version::new_xml(1, 0),
        title: String::new(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: IOBuffer::F64(piece.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect()),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity: piece.connectivity,
                    offsets: piece.offsets,
                },
                types: piece.shapes.iter().map(|&s| vtk_cell(s)).collect(),
            },
            data: Attributes {
                point: piece.point_data.into_iter().map(vtk_array).collect(),
                cell: piece.cell_data.into_iter().map(vtk_array).collect(),
            },
        }),
    };
    // whole or not at all, the error naming the file
    preflight::save::atomically(path, |w| vtk.write_xml(w).map_err(io::Error::other))
}

fn bad(path: &Path, what: impl std::fmt::Display) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, format!("{}: {what}", path.display()))
}

/// Reads a `.vtu` file written by [`write_vtu`] back (tests, post-processing): 3-component float
/// arrays become [`FieldValues::Vectors`] (their z dropped), 1-component float arrays
/// [`FieldValues::Scalars`], 32-bit integer arrays [`FieldValues::Integers`].
pub fn read_vtu(path: &Path) -> io::Result<FieldPiece> {
    let vtk = Vtk::import(path).map_err(|e| bad(path, e))?;
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        return Err(bad(path, "not an UnstructuredGrid"));
    };
    let Some(Piece::Inline(p)) = pieces.into_iter().next() else {
        return Err(bad(path, "no inline piece"));
    };
    let xyz: Vec<f64> = p
        .points
        .cast_into()
        .ok_or_else(|| bad(path, "points are not numbers"))?;
    let (connectivity, offsets) = p.cells.cell_verts.into_xml();
    let shapes = p
        .cells
        .types
        .iter()
        .map(|t| match t {
            CellType::Line => Ok(CellShape::Line),
            CellType::Triangle => Ok(CellShape::Triangle),
            CellType::Quad => Ok(CellShape::Quad),
            other => Err(bad(path, format!("cell type {other:?}"))),
        })
        .collect::<io::Result<Vec<_>>>()?;
    let arrays = |attributes: Vec<Attribute>| -> io::Result<Vec<FieldArray>> {
        attributes
            .into_iter()
            .filter_map(|a| match a {
                Attribute::DataArray(a) => Some(a),
                Attribute::Field { .. } => None,
            })
            .map(|a| {
                let values = match (&a.data, a.elem.num_comp()) {
                    (IOBuffer::I32(v), 1) => FieldValues::Integers(v.clone()),
                    (IOBuffer::F64(v), 1) => FieldValues::Scalars(v.clone()),
                    (IOBuffer::F64(v), 3) => {
                        FieldValues::Vectors(v.chunks(3).map(|c| [c[0], c[1]]).collect())
                    }
                    (_, n) => return Err(bad(path, format!("array {}: {n} components", a.name))),
                };
                Ok(FieldArray { name: a.name, values })
            })
            .collect()
    };
    Ok(FieldPiece {
        points: xyz.chunks(3).map(|c| [c[0], c[1]]).collect(),
        connectivity,
        offsets,
        shapes,
        point_data: arrays(p.data.point)?,
        cell_data: arrays(p.data.cell)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_and_segment() -> FieldPiece {
        let mut p = FieldPiece {
            points: vec![[0.0, 0.0], [1e-3, 0.0], [1e-3, 1e-3], [0.0, 1e-3], [2e-3, 0.0]],
            ..FieldPiece::default()
        };
        p.push_cell(CellShape::Quad, &[0, 1, 2, 3]);
        p.push_cell(CellShape::Triangle, &[1, 4, 2]);
        p.push_cell(CellShape::Line, &[1, 4]);
        p.point_data.push(FieldArray::new(
            "displacement",
            FieldValues::Vectors(
                (0..5)
                    .map(|k| [1e-7 * k as f64, -3.3e-9 / (k + 1) as f64])
                    .collect(),
            ),
        ));
        p.cell_data.push(FieldArray::new(
            "sigma_xx",
            FieldValues::Scalars(vec![1.0 / 3.0, -2.5e6, f64::MIN_POSITIVE]),
        ));
        p.cell_data.push(FieldArray::new(
            "facet_state",
            FieldValues::Integers(vec![0, 2, 3]),
        ));
        p
    }

    #[test]
    fn a_piece_reads_back_to_the_bit_with_its_vtk_cell_types() {
        let dir = std::env::temp_dir().join(format!("fem-paraview-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("piece.vtu");
        write_vtu(&path, square_and_segment()).unwrap();
        // binary (base64) f64: the values come back exactly, so equality is the test
        assert_eq!(read_vtu(&path).unwrap(), square_and_segment());
        // (VTK itself reads the cell types as 9, 5, 3: tests/vtk/check_fields.py)
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("<VTKFile type=\"UnstructuredGrid\""), "{text}");
        // same piece, same bytes
        let second = dir.join("again.vtu");
        write_vtu(&second, square_and_segment()).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), std::fs::read(&second).unwrap());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_collection_lists_every_snapshot_with_its_parts() {
        let dir = std::env::temp_dir().join(format!("fem-paraview-pvd-{}", std::process::id()));
        let mut w = ParaviewWriter::new(&dir, 1234).unwrap();
        for (step, t) in [(0, 0.0), (10, 1.5e-5)] {
            w.snapshot(FieldSnapshot {
                step,
                t,
                bulk: square_and_segment(),
                crack: Some(square_and_segment()),
            })
            .unwrap();
        }
        let pvd = std::fs::read_to_string(w.finish().unwrap()).unwrap();
        assert!(
            pvd.contains(
                r#"timestep="1.5e-5" group="" part="1" name="crack" file="fields/crack_000010.vtu""#
            ),
            "{pvd}"
        );
        assert_eq!(pvd.matches("<DataSet").count(), 4, "{pvd}");
        assert!(dir.join("fields/bulk_000000.vtu").is_file());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_runs_snapshot_reads_back_to_the_bit() {
        // a snapshot of the tiny centre crack under a smooth displacement field: every array the
        // observer fills (stresses, displacements, the crack faces) goes through the file unchanged
        let text = crate::test_scenes::scene_text("tiny-fem-center-crack");
        let scene = crate::scene::Scene::from_toml_str(&text).unwrap();
        let (model, mut state, _) = crate::model::build::build(&scene).unwrap();
        for (u, x) in state.u.iter_mut().zip(&model.bulk.x0) {
            *u = nalgebra::Vector2::new(2e-4 * x.x + 3e-4 * x.y, -1e-4 * x.x - 5e-4 * x.y);
        }
        let snap = crate::diag::fields::snapshot(&model, &state);
        let dir = std::env::temp_dir().join(format!("fem-fields-uniform-{}", std::process::id()));
        let mut w = ParaviewWriter::new(&dir, 0).unwrap();
        w.snapshot(snap.clone()).unwrap();
        assert_eq!(read_vtu(&dir.join("fields/bulk_000000.vtu")).unwrap(), snap.bulk);
        assert_eq!(
            read_vtu(&dir.join("fields/crack_000000.vtu")).unwrap(),
            snap.crack.unwrap()
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
