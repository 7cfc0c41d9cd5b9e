//! The `[fem]` section: discretisation, model options, boundary conditions.

use super::boundary::{BoundaryKind, BoundarySpec, GRID_SIDES, boundary, kinds_fit_parts, mesh_boundary};
use super::checks::{Problems, check, inconsistent, keep, option};
use super::damping::{Damping, damping};
use super::diagnostics::{Diagnostics, diagnostics};
use super::interface_spec::{
    ContactSurface, InterfaceZone, sine_polyline, zones_and_surface, zones_hold_facets,
};
use super::mesh::{MeshSpec, mesh};
use super::paraview::{ParaviewSpec, paraview};
use super::problem::Crack;
use super::raw::RawFem;
use super::rough::{Rough, rough, rough_polyline};
use crate::error::SceneError;
use crate::mesh::interfaces::FacetKind;

/// Largest allowed safety factor α of the stable step (docs/fem-model.md §2, §10.10).
///
/// # Deviation
/// The paper gives no α, and a margin of α ≤ 0.9 is the usual choice. The measured limit of the
/// structured Q4 lumped-mass grid is 0.98 h/c_d and the penalty factor f(β_p) of eq. (12) is
/// conservative, so α = 0.95 is still stable; it is allowed because users test the model near its
/// stability limit (`fem_extremes` runs at 0.95). Above 0.95 a step is refused.
pub(crate) const MAX_SAFETY: f64 = 0.95;

/// Which cohesive-contact model runs (paper Section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// Hybrid: node-to-segment contact + cohesive law without compression (paper §2).
    Hybrid,
    /// Standard: contact through the cohesive law's compression penalty (paper eq. 4), no node-to-segment contact.
    Standard,
}

/// Insertion criterion over the two facet Gauss points (docs/fem-model.md §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InsertionRule {
    /// Insert when max_q σ_eff,q ≥ σ_c (paper App. A; default).
    Max,
    /// Insert when mean_q σ_eff,q > σ_c (Akantu's default).
    Mean,
}

/// Validated `[fem]` section.
#[derive(Debug, Clone, PartialEq)]
pub struct FemSpec {
    /// Domain x range [m].
    pub x_range: [f64; 2],
    /// Domain y range [m] (y = 0 is the crack/interface row).
    pub y_range: [f64; 2],
    /// Element edge h [m].
    pub element_size: f64,
    /// Hybrid or standard model.
    pub model: ModelKind,
    /// Safety factor α of the stable step [-] (≤ 0.95).
    pub time_step_safety: f64,
    /// Requested time step [s]; refused above the stable limit.
    pub requested_time_step: Option<f64>,
    /// Normal penalty ε_n [Pa/m].
    pub eps_n: f64,
    /// Tangential penalty ε_t [Pa/m].
    pub eps_t: f64,
    /// Prakash regularisation time t* [s] of the friction pressure (paper eq. 14; `fem.t_star`,
    /// default 0: plain Coulomb).
    pub t_star: f64,
    /// Add u_x += −ν (x − x_c) σ_yy/(2G) to the Westergaard field (docs/cases.md).
    pub lateral_contraction: bool,
    /// Add the mode-II part of u_y, [(1 − 2ν) Im ψ − y Re ψ']/(2G), that (C.9) drops (default
    /// false, as docs/cases.md): the shear part of the boundary field is then an exact elastic field.
    pub mode_ii_uy: bool,
    /// Sampling interval of the records [s].
    pub output_interval: f64,
    /// Insertion criterion.
    pub insertion_rule: InsertionRule,
    /// Which nodes are damped, and how strongly.
    pub damping: Damping,
    /// Contact detection distance d_max [m] (default h).
    pub max_gap: f64,
    /// Contact projection tolerance ε_ext [-].
    pub projection_tolerance: f64,
    /// Horizontal shift of the upper block's nodes [element sizes] (full-width pre-crack only).
    pub upper_offset: f64,
    /// The interface node row follows this polyline y(x) [m] (linear between points, y = 0
    /// outside); rows in between are interpolated (paper Section 4 meshes). `None`: flat.
    pub interface_polyline: Option<Vec<[f64; 2]>>,
    /// Stretches of the interface row with their own cohesive law (outside them: `[interface]`).
    pub interface_zones: Vec<InterfaceZone>,
    /// Which faces form the contact detection surface.
    pub contact_surface: ContactSurface,
    /// Section 4 diagnostics the scene asks for (none by default).
    pub diagnostics: Diagnostics,
    /// Probe points (reference positions [m]); the nearest node is recorded.
    pub probes: Vec<[f64; 2]>,
    /// Side-wise boundary conditions; `None`: Westergaard displacements on the whole boundary.
    pub boundary: Option<BoundarySpec>,
    /// ParaView field snapshots (`[fem.paraview]`); `None`: none are taken.
    pub paraview: Option<ParaviewSpec>,
    /// The Gmsh mesh of `[fem.mesh]`; `None`: the built-in grid. With a mesh, `x_range` and
    /// `y_range` are its bounding box and `element_size` the mean facet length of its interface.
    pub mesh: Option<MeshSpec>,
}

fn is_multiple(length: f64, h: f64) -> bool {
    let n = length / h;
    (n - n.round()).abs() < 1e-6 && n.round() >= 1.0
}

fn geometry(f: &RawFem, crack: Option<&Crack>) -> Result<(), SceneError> {
    let mut p = Problems::default();
    let h = p.check("fem.element_size", f.element_size, f.element_size > 0.0, "> 0 m");
    let [x0, x1] = f.x_range;
    let [y0, y1] = f.y_range;
    p.check("fem.x_range", x1 - x0, x1 > x0, "x_range[1] > x_range[0]");
    p.check(
        "fem.y_range",
        y0,
        y0 < 0.0 && y1 > 0.0,
        "y_range[0] < 0 < y_range[1] (y = 0 is the interface row)",
    );
    // the fit of the grid to the domain and the crack needs a valid h and domain
    p.done()?;
    for (name, len) in [
        ("width", x1 - x0),
        ("height below y = 0", -y0),
        ("height above y = 0", y1),
    ] {
        if !is_multiple(len, h) {
            return Err(inconsistent(
                "fem.element_size",
                format!("{name} {len} m is not a multiple of fem.element_size = {h} m"),
            ));
        }
    }
    if let Some(c) = crack {
        for tip in [c.center_x - c.half_length, c.center_x + c.half_length] {
            let inside = tip > x0 && tip < x1;
            if inside && !is_multiple(tip - x0, h) {
                return Err(inconsistent(
                    "crack.half_length",
                    format!("crack tip x = {tip} m is not on a node (fem.element_size = {h} m)"),
                ));
            }
        }
        if c.center_x + c.half_length <= x0 || c.center_x - c.half_length >= x1 {
            return Err(inconsistent(
                "crack.center_x",
                "the pre-crack lies outside fem.x_range",
            ));
        }
    }
    Ok(())
}

/// What the checks of `[fem]` that need neither the pre-crack nor the mesh give (each `None`
/// when refused, its problem added to the errors).
struct Standalone {
    options: Option<(ModelKind, InsertionRule)>,
    damping: Option<Damping>,
    steps: Option<(f64, f64, f64)>,
    distances: Option<(f64, f64)>,
    t_star: f64,
    diagnostics: Option<Diagnostics>,
    probes: Option<Vec<[f64; 2]>>,
    paraview: Option<Option<ParaviewSpec>>,
}

/// The checks of `[fem]` that need neither the pre-crack nor the mesh, over the form `f` (with
/// a mesh, the form completed from it).
fn standalone(f: &RawFem, duration: f64, errors: &mut Vec<SceneError>) -> Standalone {
    let t_star = f.t_star.unwrap_or(0.0);
    keep(errors, check("fem.t_star", t_star, t_star >= 0.0, ">= 0 s"));
    Standalone {
        options: keep(errors, options(f)),
        damping: keep(errors, damping(f)),
        steps: keep(errors, step_and_penalties(f, duration)),
        distances: keep(errors, contact_distances(f)),
        t_star,
        diagnostics: keep(errors, diagnostics(f, duration)),
        probes: keep(errors, probes(f)),
        paraview: keep(errors, paraview(f, duration)),
    }
}

/// The checks of `[fem]` run when `[crack]` is refused, so that the problems of `[fem]` are
/// reported with those of the shared tables instead of after they are fixed: the grid's own and
/// [`standalone`]. (With `[fem.mesh]` the form is completed from the mesh first, which needs a
/// valid crack; such a scene waits for its crack.)
pub(crate) fn check_fem_alone(f: &RawFem, duration: f64, errors: &mut Vec<SceneError>) {
    if f.mesh.is_none() {
        keep(errors, geometry(f, None));
        standalone(f, duration, errors);
    }
}

/// Validates `[fem]` against the pre-crack and the duration T [s], adding every problem found to
/// `errors` (`None` if there was any).
pub(crate) fn validate_fem(
    f: &RawFem,
    crack: Option<&Crack>,
    cohesive: bool,
    base_dir: Option<&std::path::Path>,
    duration: f64,
    errors: &mut Vec<SceneError>,
) -> Option<FemSpec> {
    let before = errors.len();
    // with a mesh, the form is completed from it (domain, element size) and the grid's own
    // checks are skipped; a mesh that cannot be used stops here (the other checks would only
    // repeat its absence)
    let (mesh, effective) = match keep(errors, mesh(f, crack, cohesive, base_dir))? {
        Some((spec, effective)) => (Some(spec), Some(effective)),
        None => (None, None),
    };
    let f = effective.as_ref().unwrap_or(f);
    let geometry_ok = match &mesh {
        None => keep(errors, geometry(f, crack)).is_some(),
        Some(m) => keep(errors, mesh_boundary(f, crack, m)).is_some(),
    };
    let Standalone {
        options,
        damping,
        steps,
        distances,
        t_star,
        diagnostics,
        probes,
        paraview,
    } = standalone(f, duration, errors);
    let blocks = keep(errors, blocks_and_boundary(f, crack, duration));
    if let (Some(m), Some((_, Some(b))), true) = (&mesh, &blocks, geometry_ok) {
        keep(errors, kinds_fit_parts(b, m));
    }
    let zones = keep(errors, zones_and_surface(f));
    if let (Some((z, _)), true) = (&zones, geometry_ok)
        && !z.is_empty()
    {
        keep(
            errors,
            zones_hold_facets(z, &cohesive_centres(f, crack, mesh.as_ref())),
        );
    }
    if let (Some(m), Some(p), true) = (&mesh, &probes, geometry_ok) {
        keep(errors, probes_in_body(p, m));
    }
    let rough = rough(f, errors);
    let polyline = match (geometry_ok, &blocks, &mesh, rough) {
        (true, Some((upper_offset, _)), None, Some(rough)) => {
            keep(errors, interface_row(f, crack, *upper_offset, rough.as_ref()))
        }
        (true, Some(_), Some(_), _) => Some(None),
        _ => None,
    };
    if errors.len() > before {
        return None;
    }
    let ((model, insertion_rule), (time_step_safety, eps_n, eps_t)) = (options?, steps?);
    let ((max_gap, projection_tolerance), (upper_offset, boundary)) = (distances?, blocks?);
    let (interface_zones, contact_surface) = zones?;
    Some(FemSpec {
        x_range: f.x_range,
        y_range: f.y_range,
        element_size: f.element_size,
        model,
        time_step_safety,
        requested_time_step: f.time_step,
        eps_n,
        eps_t,
        t_star,
        lateral_contraction: f.lateral_contraction.unwrap_or(true),
        mode_ii_uy: f.mode_ii_uy.unwrap_or(false),
        output_interval: f.output_interval,
        insertion_rule,
        damping: damping?,
        max_gap,
        projection_tolerance,
        upper_offset,
        interface_polyline: polyline?,
        interface_zones,
        contact_surface,
        diagnostics: diagnostics?,
        probes: probes?,
        boundary,
        paraview: paraview?,
        mesh,
    })
}

/// The interface row's path: the sine of `interface_sine` or the self-affine profile of
/// `interface_rough` (its fields checked already) sampled at the node columns, or the user's
/// `interface_polyline`, or flat.
fn interface_row(
    f: &RawFem,
    crack: Option<&Crack>,
    upper_offset: f64,
    rough: Option<&Rough>,
) -> Result<Option<Vec<[f64; 2]>>, SceneError> {
    let center = crack.map_or(0.0, |c| c.center_x);
    let (path, key) = match (&f.interface_sine, rough) {
        (Some(s), _) => (sine_polyline(f, s, center)?, "fem.interface_sine.amplitude"),
        (None, Some(r)) => (rough_polyline(f, r, center)?, "fem.interface_rough.rms_slope"),
        (None, None) => return polyline(f, upper_offset, "fem.interface_polyline"),
    };
    let mut g = RawFem::clone(f);
    g.interface_polyline = Some(path);
    polyline(&g, upper_offset, key)
}

/// The string options: model and insertion rule.
fn options(f: &RawFem) -> Result<(ModelKind, InsertionRule), SceneError> {
    let mut p = Problems::default();
    let model = p.keep(option(
        "fem.model",
        f.model.as_ref(),
        ModelKind::Hybrid,
        &[("hybrid", ModelKind::Hybrid), ("standard", ModelKind::Standard)],
        "\"hybrid\" or \"standard\"",
    ));
    let insertion_rule = p.keep(option(
        "fem.insertion_rule",
        f.insertion_rule.as_ref(),
        InsertionRule::Max,
        &[("max", InsertionRule::Max), ("mean", InsertionRule::Mean)],
        "\"max\" or \"mean\"",
    ));
    p.done()?;
    let (Some(model), Some(insertion_rule)) = (model, insertion_rule) else {
        unreachable!("invariant: both options passed, done() found no problem");
    };
    Ok((model, insertion_rule))
}

/// Safety factor α, requested step, output interval and penalties (α, ε_n, ε_t).
fn step_and_penalties(f: &RawFem, duration: f64) -> Result<(f64, f64, f64), SceneError> {
    let mut p = Problems::default();
    let alpha = f.time_step_safety.unwrap_or(0.5);
    p.check(
        "fem.time_step_safety",
        alpha,
        alpha > 0.0 && alpha <= MAX_SAFETY,
        "(0, 0.95]",
    );
    if let Some(dt) = f.time_step {
        p.check("fem.time_step", dt, dt > 0.0, "> 0 s");
        if f.time_step_safety.is_some() {
            p.push(inconsistent(
                "fem.time_step",
                "give fem.time_step [s] or fem.time_step_safety [-], not both",
            ));
        }
    }
    let dt_out = f.output_interval;
    p.check(
        "fem.output_interval",
        dt_out,
        dt_out > 0.0 && dt_out <= duration,
        "(0, loading.duration] s",
    );
    let eps_n = f.eps_n.unwrap_or(0.0);
    let eps_t = f.eps_t.unwrap_or(eps_n);
    p.check("fem.eps_n", eps_n, eps_n >= 0.0, ">= 0 Pa/m");
    p.check("fem.eps_t", eps_t, eps_t >= 0.0, ">= 0 Pa/m");
    p.done()?;
    Ok((alpha, eps_n, eps_t))
}

/// Detection distance d_max [m] and projection tolerance.
fn contact_distances(f: &RawFem) -> Result<(f64, f64), SceneError> {
    let mut p = Problems::default();
    let max_gap = f.max_gap.unwrap_or(f.element_size);
    p.check("fem.max_gap", max_gap, max_gap > 0.0, "> 0 m");
    let tol = f.projection_tolerance.unwrap_or(1e-3);
    p.check(
        "fem.projection_tolerance",
        tol,
        (0.0..0.5).contains(&tol),
        "[0, 0.5)",
    );
    p.done()?;
    Ok((max_gap, tol))
}

/// Upper-block offset (full-width pre-crack only) and side-wise boundary conditions (required
/// unless a centre pre-crack lets the Westergaard field apply).
fn blocks_and_boundary(
    f: &RawFem,
    crack: Option<&Crack>,
    duration: f64,
) -> Result<(f64, Option<BoundarySpec>), SceneError> {
    let upper_offset = f.upper_offset.unwrap_or(0.0);
    check(
        "fem.upper_offset",
        upper_offset,
        (0.0..1.0).contains(&upper_offset),
        "[0, 1) element sizes",
    )?;
    let full_width = crack.is_some_and(|c| {
        c.center_x - c.half_length <= f.x_range[0] && c.center_x + c.half_length >= f.x_range[1]
    });
    if upper_offset > 0.0 && !full_width {
        return Err(inconsistent(
            "fem.upper_offset",
            "needs a full-width pre-crack (two separate blocks)",
        ));
    }
    let boundary = f.boundary.as_ref().map(|b| boundary(b, duration)).transpose()?;
    if let (Some(b), None) = (&boundary, &f.mesh) {
        // the built-in grid has its four sides; other names are curves of a mesh file
        if let Some(c) = b.curves.iter().find(|c| !GRID_SIDES.contains(&c.name.as_str())) {
            return Err(inconsistent(
                format!("fem.boundary.{}", c.name),
                "the built-in grid's sides are bottom, right, top and left (other names are physical \
                 curves or points of a [fem.mesh] file)",
            ));
        }
        for c in &b.curves {
            for (k, comp) in ["x", "y"].iter().zip(&c.components) {
                if comp.is_some_and(|comp| comp.kind == BoundaryKind::Force) {
                    return Err(inconsistent(
                        format!("fem.boundary.{}.{k}.kind", c.name),
                        "a force [N/m] acts on a physical point of a [fem.mesh] file; a side of the \
                         built-in grid takes \"traction\" [Pa]",
                    ));
                }
            }
        }
    }
    if boundary.is_none() && (crack.is_none() || full_width) {
        return Err(inconsistent(
            "fem.boundary",
            "missing: the Westergaard boundary field needs a centre pre-crack inside the domain; give [fem.boundary] instead",
        ));
    }
    Ok((upper_offset, boundary))
}

fn probes(f: &RawFem) -> Result<Vec<[f64; 2]>, SceneError> {
    let probes = f.probes.clone().unwrap_or_default();
    let mut problems = Problems::default();
    for p in &probes {
        problems.check(
            "fem.probes",
            p[0],
            p[0] >= f.x_range[0] && p[0] <= f.x_range[1],
            "inside fem.x_range",
        );
        problems.check(
            "fem.probes",
            p[1],
            p[1] >= f.y_range[0] && p[1] <= f.y_range[1],
            "inside fem.y_range",
        );
    }
    problems.done()?;
    Ok(probes)
}

/// On a mesh, each probe lies in an element of the body (not in a notch or a hole inside the
/// bounding box, where the nearest node would be on the hole's edge).
fn probes_in_body(probes: &[[f64; 2]], m: &MeshSpec) -> Result<(), SceneError> {
    for (k, p) in probes.iter().enumerate() {
        if !m.prepared.contains(nalgebra::Vector2::new(p[0], p[1])) {
            return Err(inconsistent(
                format!("fem.probes[{k}]"),
                format!("({}, {}) m lies in no element of the body", p[0], p[1]),
            ));
        }
    }
    Ok(())
}

/// Centres of the cohesive facets in interface coordinates [m]: the grid's facets classified as
/// the build classifies them, or the mesh's interface facets.
fn cohesive_centres(f: &RawFem, crack: Option<&Crack>, mesh: Option<&MeshSpec>) -> Vec<f64> {
    if let Some(m) = mesh {
        let Some(row) = &m.prepared.row else {
            return Vec::new();
        };
        return (0..row.num_facets())
            .filter(|&c| row.kind[c] == FacetKind::Cohesive)
            .map(|c| {
                let [a, b] = row.facet_span(c);
                0.5 * (a + b)
            })
            .collect();
    }
    let h = f.element_size;
    let n = ((f.x_range[1] - f.x_range[0]) / h).round() as usize;
    let crack = crack.map(|c| (c.center_x, c.half_length));
    (0..n)
        .map(|i| f.x_range[0] + (i as f64 + 0.5) * h)
        .filter(|&x| FacetKind::of_grid_facet(x, crack, true) == FacetKind::Cohesive)
        .collect()
}

/// Validates the row's path; `key` names it in errors (`fem.interface_polyline`, or the sine's
/// amplitude when the path is the generated sine). The row is piecewise linear between node
/// columns, so a point of the path that falls between columns and off that line is a feature
/// finer than h the mesh cannot follow: refused, rather than lost unnoticed.
fn polyline(f: &RawFem, upper_offset: f64, key: &'static str) -> Result<Option<Vec<[f64; 2]>>, SceneError> {
    let Some(p) = &f.interface_polyline else {
        return Ok(None);
    };
    if p.len() < 2 || upper_offset > 0.0 {
        return Err(inconsistent(
            "fem.interface_polyline",
            "needs at least 2 points and no fem.upper_offset",
        ));
    }
    let limit = 0.5 * (-f.y_range[0]).min(f.y_range[1]);
    for (k, q) in p.iter().enumerate() {
        let increasing = k == 0 || q[0] > p[k - 1][0];
        check(
            "fem.interface_polyline",
            q[0],
            increasing,
            "points with strictly increasing x [m]",
        )?;
        check(
            key,
            q[1],
            q[1].abs() < limit,
            "a path with |y| < half the smaller of the heights below and above y = 0 [m]",
        )?;
    }
    let (h, x0) = (f.element_size, f.x_range[0]);
    let y_at = |x: f64| {
        if x <= p[0][0] || x >= p[p.len() - 1][0] {
            return 0.0;
        }
        let k = p.partition_point(|q| q[0] <= x).max(1);
        let (a, b) = (p[k - 1], p[k]);
        a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
    };
    for q in p {
        let i = ((q[0] - x0) / h).floor();
        let (xa, xb) = (x0 + i * h, x0 + (i + 1.0) * h);
        let on_row = y_at(xa) + (y_at(xb) - y_at(xa)) * (q[0] - xa) / h;
        if (q[1] - on_row).abs() > 0.1 * h {
            return Err(inconsistent(
                "fem.interface_polyline",
                format!(
                    "the point ({}, {}) m is {:.3e} m off the mesh row, whose nodes are fem.element_size = {h} m \
                     apart: features finer than h cannot be followed; refine the mesh or smooth the path",
                    q[0],
                    q[1],
                    (q[1] - on_row).abs()
                ),
            ));
        }
    }
    Ok(Some(p.clone()))
}

impl FemSpec {
    /// y [m] of the interface row at x [m]: the polyline, linear between points, 0 outside.
    pub fn interface_y(&self, x: f64) -> f64 {
        let Some(p) = &self.interface_polyline else {
            return 0.0;
        };
        if x <= p[0][0] || x >= p[p.len() - 1][0] {
            return 0.0;
        }
        let k = p.partition_point(|q| q[0] <= x).max(1);
        let (a, b) = (p[k - 1], p[k]);
        a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
    }

    /// Smallest element length h_min [m] of the stable step: h on a flat mesh; on a mapped mesh
    /// the smallest altitude of the elements next to the mapped row, min(v) / √(1 + s²) with v the
    /// row spacing of a column and s the slope of the row (the classical CFL length of a sheared
    /// quad; the element eigenvalue bound gives 0.60 h at the sinusoid's steepest slope s = π/2,
    /// the altitude 0.54 h, so the altitude is the safe side).
    pub fn min_edge(&self) -> f64 {
        if let Some(m) = &self.mesh {
            return m.prepared.h_min;
        }
        let h = self.element_size;
        if self.interface_polyline.is_none() {
            return h;
        }
        let [x0, x1] = self.x_range;
        let [y0, y1] = self.y_range;
        let (below, above) = ((-y0 / h).round(), (y1 / h).round());
        let n = ((x1 - x0) / h).round() as usize;
        let spacing = |y: f64| ((y - y0) / below).min((y1 - y) / above);
        (0..n)
            .map(|i| {
                let (ya, yb) = (
                    self.interface_y(x0 + i as f64 * h),
                    self.interface_y(x0 + (i + 1) as f64 * h),
                );
                let slope = (yb - ya) / h;
                spacing(ya).min(spacing(yb)) / (1.0 + slope * slope).sqrt()
            })
            .fold(h, f64::min)
    }
}
