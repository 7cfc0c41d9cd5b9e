//! The fields of one time step as a run hands them over ([`FieldSnapshot`]: unstructured pieces
//! of points, cells and named arrays), and the [`FieldSink`] that takes them. Plain data: the
//! ParaView writer (`output::paraview`) is one sink, and a caller may bring its own.

use std::io;

/// Shape of a cell (its VTK cell type number in brackets).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellShape {
    /// Two-node segment (VTK_LINE = 3).
    Line,
    /// Three-node triangle, counter-clockwise (VTK_TRIANGLE = 5).
    Triangle,
    /// Four-node quadrilateral, counter-clockwise (VTK_QUAD = 9).
    Quad,
}

impl CellShape {
    /// Number of nodes of the shape.
    pub fn nodes(self) -> usize {
        match self {
            CellShape::Line => 2,
            CellShape::Triangle => 3,
            CellShape::Quad => 4,
        }
    }
}

/// Values of one data array, one entry per point or per cell.
#[derive(Debug, Clone, PartialEq)]
pub enum FieldValues {
    /// One number per entry.
    Scalars(Vec<f64>),
    /// An in-plane vector per entry, written with a zero z component (3 components) so that
    /// ParaView's Warp By Vector and glyph filters apply to it directly.
    Vectors(Vec<[f64; 2]>),
    /// A small integer per entry (states, flags).
    Integers(Vec<i32>),
}

impl FieldValues {
    /// Number of entries.
    pub fn len(&self) -> usize {
        match self {
            FieldValues::Scalars(v) => v.len(),
            FieldValues::Vectors(v) => v.len(),
            FieldValues::Integers(v) => v.len(),
        }
    }

    /// Whether there are no entries.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One named data array (the names and units are listed in docs/outputs.md).
#[derive(Debug, Clone, PartialEq)]
pub struct FieldArray {
    /// Array name as ParaView shows it.
    pub name: String,
    /// The values.
    pub values: FieldValues,
}

impl FieldArray {
    /// A named array.
    pub fn new(name: &str, values: FieldValues) -> FieldArray {
        FieldArray {
            name: name.to_string(),
            values,
        }
    }
}

/// One unstructured mesh with its data: what one `.vtu` file holds.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FieldPiece {
    /// Reference positions X of the points [m] (written with z = 0).
    pub points: Vec<[f64; 2]>,
    /// Point indices of every cell, cell after cell.
    pub connectivity: Vec<u64>,
    /// End of each cell in `connectivity` (VTK's offsets: the first cell is `0..offsets[0]`).
    pub offsets: Vec<u64>,
    /// Shape of each cell.
    pub shapes: Vec<CellShape>,
    /// Arrays with one entry per point.
    pub point_data: Vec<FieldArray>,
    /// Arrays with one entry per cell.
    pub cell_data: Vec<FieldArray>,
}

impl FieldPiece {
    /// Appends a cell of `shape` through the points `nodes` (counter-clockwise for a face).
    pub fn push_cell(&mut self, shape: CellShape, nodes: &[u32]) {
        debug_assert_eq!(nodes.len(), shape.nodes());
        self.connectivity.extend(nodes.iter().map(|&n| u64::from(n)));
        self.offsets.push(self.connectivity.len() as u64);
        self.shapes.push(shape);
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.shapes.len()
    }

    /// The point array called `name`, if any.
    pub fn point_array(&self, name: &str) -> Option<&FieldValues> {
        self.point_data.iter().find(|a| a.name == name).map(|a| &a.values)
    }

    /// The cell array called `name`, if any.
    pub fn cell_array(&self, name: &str) -> Option<&FieldValues> {
        self.cell_data.iter().find(|a| a.name == name).map(|a| &a.values)
    }
}

/// The fields of one time step.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldSnapshot {
    /// Step index [-].
    pub step: u64,
    /// Time [s].
    pub t: f64,
    /// The bulk elements and every node.
    pub bulk: FieldPiece,
    /// The interface row as line cells (`None` without a pre-crack or an interface).
    pub crack: Option<FieldPiece>,
}

/// Receives the snapshots of a run as they are taken (`run_with_fields`); `Send` because the
/// time steps run on a rayon pool thread.
pub trait FieldSink: Send {
    /// Takes one snapshot; an error stops the run (`RunError::FieldOutput`).
    fn snapshot(&mut self, snapshot: FieldSnapshot) -> io::Result<()>;

    /// The snapshots taken so far as a checkpoint keeps them: (time [s], files written) each,
    /// in the order taken (empty for a sink that keeps no list).
    fn taken(&self) -> Vec<(f64, Vec<String>)> {
        Vec::new()
    }

    /// Takes back the list [`FieldSink::taken`] gave, when a run resumes from a checkpoint; a
    /// sink that writes files removes those of the stopped run that are not in it (taken after
    /// the checkpoint: the resumed run writes them again, or not at all).
    fn resume(&mut self, _taken: Vec<(f64, Vec<String>)>) -> io::Result<()> {
        Ok(())
    }
}
