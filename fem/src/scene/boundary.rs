//! Side-wise boundary conditions of `[fem.boundary]`: per side, curve or point and component, an
//! imposed displacement [m], traction [Pa] (sides and curves) or force [N/m] (points), and on a
//! side or curve a pressure [Pa] along the outward normal, each through the ramp of eq. (B.1).

use super::checks::{inconsistent, option, ramp};
use super::problem::Ramp;
use super::raw::{RawBoundary, RawBoundaryComponent, RawRamp, RawSide};
use crate::error::SceneError;

/// Kind of a boundary condition component.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundaryKind {
    /// Imposed displacement [m], uniform along the side.
    Displacement,
    /// Imposed traction [Pa] (Neumann, consistent nodal forces), uniform along the side.
    Traction,
    /// Imposed force [N/m] (per unit thickness) on each node of a physical point of a mesh.
    Force,
}

/// One component (x or y) of a side's boundary condition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryComponent {
    /// Displacement or traction.
    pub kind: BoundaryKind,
    /// History of the value ([m] or [Pa]) through the ramp of eq. (B.1).
    pub ramp: Ramp,
}

/// The sides of the built-in grid, in the order their conditions apply.
pub const GRID_SIDES: [&str; 4] = ["bottom", "right", "top", "left"];

/// At most this many sides or curves in `[fem.boundary]` (each is up to three ramps of the
/// loading, which a byte indexes).
pub const MAX_CURVES: usize = 80;

/// The conditions of one side of the grid, or of one physical curve or point of a mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryCurve {
    /// The side (`bottom`, `right`, `top`, `left`) or the mesh's physical curve or point.
    pub name: String,
    /// Per component [x, y]: its condition, or `None` (free).
    pub components: [Option<BoundaryComponent>; 2],
    /// A uniform pressure [Pa] along the outward normal (> 0 pushes into the body): consistent
    /// nodal forces p ∫ N_a (−n) ds, on the components no displacement holds.
    pub pressure: Option<Ramp>,
}

/// Boundary conditions replacing the Westergaard field; sides, curves or components not given
/// are free. They apply in this order, a later displacement replacing an earlier one at a shared
/// node: the grid's sides in the order [`GRID_SIDES`], then the other curves by name.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BoundarySpec {
    /// Per side or curve, in the order they apply.
    pub curves: Vec<BoundaryCurve>,
}

fn component(field: &str, c: &RawBoundaryComponent, duration: f64) -> Result<BoundaryComponent, SceneError> {
    let kind = option(
        format!("{field}.kind"),
        Some(&c.kind),
        BoundaryKind::Displacement,
        &[
            ("displacement", BoundaryKind::Displacement),
            ("traction", BoundaryKind::Traction),
            ("force", BoundaryKind::Force),
        ],
        "\"displacement\" [m], \"traction\" [Pa] (on a curve) or \"force\" [N/m] (on a physical point)",
    )?;
    let ramp = ramp(
        field,
        &RawRamp {
            initial: c.initial,
            final_: c.final_,
            ramp_start: c.ramp_start,
            ramp_end: c.ramp_end,
        },
        duration,
    )?;
    Ok(BoundaryComponent { kind, ramp })
}

fn side(name: &str, s: &RawSide, duration: f64) -> Result<BoundaryCurve, SceneError> {
    if s.x.is_none() && s.y.is_none() && s.pressure.is_none() {
        return Err(inconsistent(
            format!("fem.boundary.{name}"),
            "gives no x, y or pressure: a part not listed is free already (remove the table, or \
             give its condition)",
        ));
    }
    let key = |c: &str| format!("fem.boundary.{name}.{c}");
    let x =
        s.x.as_ref()
            .map(|c| component(&key("x"), c, duration))
            .transpose()?;
    let y =
        s.y.as_ref()
            .map(|c| component(&key("y"), c, duration))
            .transpose()?;
    let pressure = s
        .pressure
        .as_ref()
        .map(|p| ramp(&key("pressure"), p, duration))
        .transpose()?;
    Ok(BoundaryCurve {
        name: name.to_string(),
        components: [x, y],
        pressure,
    })
}

/// The conditions of `[fem.boundary]` in the order they apply: the grid's sides first, in the
/// order of [`GRID_SIDES`], then the other names in order. `duration` is the run's T [s]. An
/// empty `[fem.boundary]` is refused: it would replace the Westergaard field by nothing, leaving
/// the body unloaded and unheld.
pub(crate) fn boundary(b: &RawBoundary, duration: f64) -> Result<BoundarySpec, SceneError> {
    if b.is_empty() {
        return Err(inconsistent(
            "fem.boundary",
            "is empty: it replaces the Westergaard boundary field, so the body would be neither \
             loaded nor held; give a side, curve or point (e.g. [fem.boundary.top]) or remove it",
        ));
    }
    // each component given is one ramp of the loading, indexed by a byte
    if b.len() > MAX_CURVES {
        return Err(inconsistent(
            "fem.boundary",
            format!("{} sides or curves: at most {MAX_CURVES}", b.len()),
        ));
    }
    let rank = |name: &str| {
        GRID_SIDES
            .iter()
            .position(|&s| s == name)
            .unwrap_or(GRID_SIDES.len())
    };
    let mut names: Vec<&String> = b.keys().collect();
    names.sort_by_key(|n| rank(n)); // stable: the other names stay in the map's (name) order
    let curves = names
        .into_iter()
        .map(|n| side(n, &b[n], duration))
        .collect::<Result<_, _>>()?;
    Ok(BoundarySpec { curves })
}
