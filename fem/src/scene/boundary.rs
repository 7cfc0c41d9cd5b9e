//! Side-wise boundary conditions of `[fem.boundary]`: per side and component, an imposed
//! displacement [m] or traction [Pa] through the ramp of eq. (B.1).

use super::checks::{check, option};
use super::problem::Ramp;
use super::raw::{RawBoundaryComponent, RawSide};
use crate::error::SceneError;

/// Kind of a boundary condition component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundaryKind {
    /// Imposed displacement [m], uniform along the side.
    Displacement,
    /// Imposed traction [Pa] (Neumann, consistent nodal forces), uniform along the side.
    Traction,
}

/// One component (x or y) of a side's boundary condition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryComponent {
    /// Displacement or traction.
    pub kind: BoundaryKind,
    /// History of the value ([m] or [Pa]) through the ramp of eq. (B.1).
    pub ramp: Ramp,
}

/// Side-wise boundary conditions replacing the Westergaard field; sides or components not given are free.
/// Index order: [bottom, right, top, left], each [x, y].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BoundarySpec {
    /// Per side, per component.
    pub sides: [[Option<BoundaryComponent>; 2]; 4],
}

fn component(field: &'static str, c: &RawBoundaryComponent) -> Result<BoundaryComponent, SceneError> {
    let kind = option(
        field,
        Some(&c.kind),
        BoundaryKind::Displacement,
        &[
            ("displacement", BoundaryKind::Displacement),
            ("traction", BoundaryKind::Traction),
        ],
        "\"displacement\" [m] or \"traction\" [Pa]",
    )?;
    check(field, c.initial, true, "a finite number")?;
    check(field, c.final_, true, "a finite number")?;
    check(field, c.ramp_start, c.ramp_start >= 0.0, "ramp_start >= 0 s")?;
    check(
        field,
        c.ramp_end,
        c.ramp_end >= c.ramp_start,
        "ramp_end >= ramp_start",
    )?;
    let ramp = Ramp {
        initial: c.initial,
        final_value: c.final_,
        ramp_start: c.ramp_start,
        ramp_end: c.ramp_end,
    };
    Ok(BoundaryComponent { kind, ramp })
}

pub(crate) fn side(
    names: [&'static str; 2],
    s: &Option<RawSide>,
) -> Result<[Option<BoundaryComponent>; 2], SceneError> {
    let Some(s) = s else { return Ok([None, None]) };
    let x = s.x.as_ref().map(|c| component(names[0], c)).transpose()?;
    let y = s.y.as_ref().map(|c| component(names[1], c)).transpose()?;
    Ok([x, y])
}
