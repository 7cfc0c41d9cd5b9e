//! Side-wise boundary conditions of `[fem.boundary]`: per side, curve or point and component, an
//! imposed displacement [m], traction [Pa] (sides and curves) or force [N/m] (points), and on a
//! side or curve a pressure [Pa] along the outward normal, each through the ramp of eq. (B.1); and,
//! on a Gmsh mesh, the checks that each condition names a part of the right kind.

use super::checks::{inconsistent, option, ramp};
use super::mesh::MeshSpec;
use super::problem::Crack;
use super::problem::Ramp;
use super::raw::{RawBoundary, RawBoundaryComponent, RawFem, RawRamp, RawSide};
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
    /// Viscous dashpots on the part's nodes (Lysmer–Kuhlemeyer): a force −C v with ρc_d on the
    /// normal and ρc_s on the tangential velocity, lumped over each node's tributary length,
    /// on the components no displacement holds. Waves that reach the part leave the body (all of
    /// a plane wave at normal incidence); a traction or pressure on the same part keeps loading it.
    pub absorbing: bool,
    /// The part carries the traction σ∞ n of the uniform far-field stress of `[loading]` (σ_xx = 0,
    /// σ_yy = `normal`, σ_xy = `shear`, the far field of the spectral model), as consistent nodal
    /// forces; with `absorbing`, its dashpots act on the velocity relative to that field's motion,
    /// so that they let the scattered waves out and leave the load alone.
    pub far_field: bool,
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
    let (absorbing, far_field) = (s.absorbing == Some(true), s.far_field == Some(true));
    if s.x.is_none() && s.y.is_none() && s.pressure.is_none() && !absorbing && !far_field {
        return Err(inconsistent(
            format!("fem.boundary.{name}"),
            "gives no x, y, pressure, absorbing = true or far_field = true: a part not listed is free \
             already (remove the table, or give its condition)",
        ));
    }
    let key = |c: &str| format!("fem.boundary.{name}.{c}");
    if far_field
        && let Some(other) = [
            ("x", s.x.is_some()),
            ("y", s.y.is_some()),
            ("pressure", s.pressure.is_some()),
        ]
        .into_iter()
        .find(|(_, given)| *given)
    {
        return Err(inconsistent(
            key("far_field"),
            format!(
                "the far field gives the part's whole traction, and {} gives another: keep one",
                key(other.0)
            ),
        ));
    }
    if absorbing
        && let Some(held) = [("x", &s.x), ("y", &s.y)]
            .into_iter()
            .find(|(_, c)| c.as_ref().is_some_and(|c| c.kind == "displacement"))
    {
        return Err(inconsistent(
            key("absorbing"),
            format!(
                "a part whose {} displacement is imposed cannot let waves out through it; absorb on a \
                 part that is free or loaded by a traction or pressure",
                held.0
            ),
        ));
    }
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
        absorbing,
        far_field,
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

/// With a mesh: the Westergaard field needs a straight pre-crack on y = 0, and each side of
/// `[fem.boundary]` applies to the physical curve or point of the same name, a pressure to a curve
/// of the outer boundary only ([`kinds_fit_parts`] checks the components' kinds).
pub(super) fn mesh_boundary(f: &RawFem, crack: Option<&Crack>, m: &MeshSpec) -> Result<(), SceneError> {
    let p = &m.prepared;
    match &f.boundary {
        None if !m.materials.is_empty() => {
            return Err(inconsistent(
                "fem.boundary",
                "missing: the Westergaard boundary field is the field of one material everywhere, and \
                 fem.mesh.materials gives several; give [fem.boundary]",
            ));
        }
        None => {
            let a = crack.map_or(0.0, |c| c.half_length);
            // 1e-9 a: a straight crack drawn on y = 0 is exactly there; anything else is not the
            // crack of the analytic field
            if p.pre_crack_max_abs_y() > 1e-9 * a {
                return Err(inconsistent(
                    "fem.boundary",
                    format!(
                        "missing: the Westergaard boundary field needs a straight pre-crack on y = 0, and the \
                         mesh's pre-crack reaches |y| = {:.3e} m; give [fem.boundary]",
                        p.pre_crack_max_abs_y()
                    ),
                ));
            }
        }
        Some(b) => {
            for (name, side) in b {
                let roles = &m.roles;
                if let Some(role) = [("interface", &roles.interface), ("pre_crack", &roles.pre_crack)]
                    .into_iter()
                    .find_map(|(role, names)| names.contains(name).then_some(role))
                {
                    return Err(inconsistent(
                        format!("fem.boundary.{name}"),
                        format!(
                            "\"{name}\" is a crack curve (fem.mesh.{role}): its nodes are split in two, and a \
                             condition would hold one face only; put it on a curve of the outer boundary"
                        ),
                    ));
                }
                let part = p
                    .boundary_nodes(name)
                    .map_err(|e| inconsistent(format!("fem.boundary.{name}"), e.to_string()))?;
                for (given, what, key) in [
                    (side.pressure.is_some(), "a pressure acts", "pressure"),
                    (side.absorbing == Some(true), "dashpots absorb", "absorbing"),
                    (
                        side.far_field == Some(true),
                        "a far-field traction acts",
                        "far_field",
                    ),
                ] {
                    if given && key == "far_field" && !m.materials.is_empty() {
                        return Err(inconsistent(
                            format!("fem.boundary.{name}.far_field"),
                            "the far field of [loading] is the uniform stress of one material, and \
                             fem.mesh.materials gives several; load the part by its own traction",
                        ));
                    }
                    if !given {
                        continue;
                    }
                    if part.point {
                        return Err(inconsistent(
                            format!("fem.boundary.{name}.{key}"),
                            format!("\"{name}\" is a physical point; {what} along a curve"),
                        ));
                    }
                    p.mesh
                        .pressure_weights(name)
                        .map_err(|e| inconsistent(format!("fem.boundary.{name}.{key}"), e.to_string()))?;
                }
            }
        }
    }
    Ok(())
}

/// On a mesh, each condition fits its kind of part: a traction along a curve, a force on a point
/// (a pressure on a point is refused by [`mesh_boundary`], which also checks that the parts exist).
pub(super) fn kinds_fit_parts(b: &BoundarySpec, m: &MeshSpec) -> Result<(), SceneError> {
    for c in &b.curves {
        let point = m.prepared.boundary_nodes(&c.name).is_ok_and(|part| part.point);
        for (k, comp) in ["x", "y"].iter().zip(&c.components) {
            let why = match (point, comp.map(|comp| comp.kind)) {
                (true, Some(BoundaryKind::Traction)) => {
                    "a traction [Pa] acts along a curve; on a physical point give \"force\" [N/m]"
                }
                (false, Some(BoundaryKind::Force)) => {
                    "a force [N/m] acts on a physical point; along a curve give \"traction\" [Pa]"
                }
                _ => continue,
            };
            return Err(inconsistent(format!("fem.boundary.{}.{k}.kind", c.name), why));
        }
    }
    Ok(())
}
