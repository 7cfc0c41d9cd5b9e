//! `[fem.mesh]`: the scene's body is a Gmsh mesh (MSH 4.1) instead of the built-in grid. The file
//! is read, its groups given their roles and its interface split here, during validation, so that
//! a missing group or a bad mesh is reported before any work (docs/scenes.md, "[fem.mesh]").

use super::checks::{cohesive_law, inconsistent, material};
use super::problem::Crack;
use super::raw::{RawFem, RawMesh};
use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;
use crate::law::elastic::PlaneStrain;
use crate::mesh::gmsh::first_surface;
use crate::mesh::prepared::{MeshRoles, PreparedMesh, prepare};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A validated `[fem.mesh]`.
#[derive(Debug, Clone)]
pub struct MeshSpec {
    /// The mesh file as resolved (relative paths from the scene file's folder).
    pub file: PathBuf,
    /// The roles of its physical groups.
    pub roles: MeshRoles,
    /// Length of one unit of the file's coordinates [m] (1 unless `unit` says otherwise).
    pub unit: f64,
    /// The mesh read, checked and split along its interface (shared by every variant of the scene).
    pub prepared: Arc<PreparedMesh>,
    /// Per interface curve (in the order of `roles.interface`): its own cohesive law, or `None`
    /// for the `[interface]` law.
    pub laws: Vec<Option<LinearCohesive>>,
    /// The materials of `[fem.mesh.materials]`, in the order of their surfaces in `roles.bulk`;
    /// empty without it (every element of `[material]`).
    pub materials: Vec<PlaneStrain>,
    /// Per element of the prepared mesh: 0 for `[material]`, k for `materials[k − 1]` (empty
    /// without `[fem.mesh.materials]`).
    pub element_material: Vec<u8>,
    /// Per material index (0: `[material]`, k: `materials[k − 1]`): the smallest length h_e of
    /// its elements ([`crate::mesh::lengths::element_length`]) [m] (∞: no element).
    pub min_length: Vec<f64>,
}

impl PartialEq for MeshSpec {
    fn eq(&self, other: &Self) -> bool {
        self.file == other.file
            && self.roles == other.roles
            && self.unit == other.unit
            && self.laws == other.laws
            && self.materials == other.materials
    }
}

/// The `[fem]` keys that describe a built-in grid, refused with a mesh (the file is the geometry).
const GRID_KEYS: [&str; 7] = [
    "x_range",
    "y_range",
    "element_size",
    "upper_offset",
    "interface_polyline",
    "interface_sine",
    "interface_rough",
];

/// Validates `[fem.mesh]` (`None`: the scene uses the built-in grid) and returns it with the
/// `[fem]` form completed from the mesh: x_range and y_range its bounding box, element_size the
/// mean facet length of its interface (or its smallest element length without one), so that
/// every check of the other keys applies unchanged.
pub(crate) fn mesh(
    f: &RawFem,
    crack: Option<&Crack>,
    cohesive: bool,
    base_dir: Option<&Path>,
) -> Result<Option<(MeshSpec, RawFem)>, SceneError> {
    let Some(m) = &f.mesh else {
        check_grid_given(f)?;
        return Ok(None);
    };
    refuse_grid_keys(f)?;
    let (file, roles) = roles(m, base_dir)?;
    let laws = curve_laws(f, m, &roles)?;
    let surface_materials = surface_materials(m, &roles)?;
    check_crack_roles(&roles, crack, cohesive)?;
    let unit = mesh_unit(m)?;
    let prepared = read_prepared(&file, &roles, unit)?;
    // the interface's shortest and mean facet (the smallest element without an interface)
    let (shortest, mean) = prepared
        .facet_lengths()
        .unwrap_or((prepared.h_min, prepared.h_min));
    check_crack_extent(crack, &prepared, mean)?;
    let (materials, element_material) = element_materials(&prepared, &roles, &surface_materials)?;
    let min_length = min_lengths(&prepared, &element_material, materials.len());
    let effective = effective_form(f, &prepared, shortest, mean);
    Ok(Some((
        MeshSpec {
            file,
            roles,
            unit,
            prepared: Arc::new(prepared),
            laws,
            materials,
            element_material,
            min_length,
        },
        effective,
    )))
}

/// Without `[fem.mesh]`: the built-in grid needs `fem.x_range`, `fem.y_range` and
/// `fem.element_size`; the first missing one is reported.
fn check_grid_given(f: &RawFem) -> Result<(), SceneError> {
    for (key, missing) in [
        ("fem.x_range", f.x_range[0].is_nan()),
        ("fem.y_range", f.y_range[0].is_nan()),
        ("fem.element_size", f.element_size.is_nan()),
    ] {
        if missing {
            return Err(inconsistent(
                key,
                "missing: the built-in grid needs fem.x_range, fem.y_range and fem.element_size (or give [fem.mesh])",
            ));
        }
    }
    Ok(())
}

/// With `[fem.mesh]`: the first of [`GRID_KEYS`] given is refused (the mesh file is the geometry).
fn refuse_grid_keys(f: &RawFem) -> Result<(), SceneError> {
    let given = [
        !f.x_range[0].is_nan(),
        !f.y_range[0].is_nan(),
        !f.element_size.is_nan(),
        f.upper_offset.is_some(),
        f.interface_polyline.is_some(),
        f.interface_sine.is_some(),
        f.interface_rough.is_some(),
    ];
    if let Some(k) = given.iter().position(|&g| g) {
        return Err(inconsistent(
            format!("fem.{}", GRID_KEYS[k]),
            "describes the built-in grid; with [fem.mesh] the mesh file is the geometry",
        ));
    }
    Ok(())
}

/// The interface curves need an `[interface]` section (their cohesive law), and the mesh's
/// pre-crack curves go with a `[crack]` section.
fn check_crack_roles(roles: &MeshRoles, crack: Option<&Crack>, cohesive: bool) -> Result<(), SceneError> {
    if !roles.interface.is_empty() && !cohesive {
        return Err(inconsistent(
            "fem.mesh.interface",
            "needs an [interface] section (the cohesive law of its facets)",
        ));
    }
    if crack.is_some() == roles.pre_crack.is_empty() {
        return Err(inconsistent(
            "fem.mesh.pre_crack",
            "[crack] and fem.mesh.pre_crack go together: the mesh's pre-crack curve and the crack the \
             other parts of the scene (boundary field, spectral model) read",
        ));
    }
    Ok(())
}

/// `fem.mesh.unit`: the length of one unit of the file's coordinates [m] (1 if not given), finite
/// and > 0.
fn mesh_unit(m: &RawMesh) -> Result<f64, SceneError> {
    let unit = m.unit.unwrap_or(1.0);
    if !(unit.is_finite() && unit > 0.0) {
        return Err(inconsistent(
            "fem.mesh.unit",
            format!(
                "{unit}: give the length of one unit of the file's coordinates in metres, > 0 \
                 (1e-3 for a mesh drawn in millimetres)"
            ),
        ));
    }
    Ok(unit)
}

/// The mesh `file` read, scaled by `unit` [m] and prepared for its `roles`. A unit that overflows
/// the coordinates, or shrinks the elements until their areas underflow, is the unit's fault, not
/// the mesh's (nor the contact distances' derived from h).
fn read_prepared(file: &Path, roles: &MeshRoles, unit: f64) -> Result<PreparedMesh, SceneError> {
    use crate::mesh::gmsh::MeshError;
    let mut mesh = crate::mesh::gmsh::UnstructuredMesh::read(file).map_err(|e| {
        let message = match e {
            MeshError::Io { .. } => e.to_string(),
            _ => format!("{}: {e}", file.display()),
        };
        inconsistent("fem.mesh.file", message)
    })?;
    mesh.scale(unit);
    if mesh
        .positions
        .iter()
        .any(|p| !(p.x.is_finite() && p.y.is_finite()))
    {
        return Err(unit_error(unit, "makes the coordinates overflow".into()));
    }
    let prepared = prepare(mesh, roles)
        .map_err(|e| inconsistent(format!("fem.mesh.{}", e.role), e.error.to_string()))?;
    if !(prepared.h_min * prepared.h_min).is_normal() {
        return Err(unit_error(
            unit,
            format!(
                "puts the element areas beyond floating point (the smallest element length comes out as {} m)",
                crate::error::number(prepared.h_min)
            ),
        ));
    }
    Ok(prepared)
}

/// The error on `fem.mesh.unit` when the unit (`unit` [m] per unit of the file) `what` (e.g.
/// "makes the coordinates overflow").
fn unit_error(unit: f64, what: String) -> SceneError {
    inconsistent(
        "fem.mesh.unit",
        format!(
            "{} m per unit {what}: give the length of one unit of the file's coordinates in metres",
            crate::error::number(unit)
        ),
    )
}

/// The mesh's pre-crack must span the `[crack]`'s extent along the interface, to within a
/// millionth of the `mean` facet length [m].
fn check_crack_extent(crack: Option<&Crack>, prepared: &PreparedMesh, mean: f64) -> Result<(), SceneError> {
    if let (Some(c), Some([s0, s1])) = (crack, prepared.pre_crack_extent()) {
        // the mesh's coordinates are printed to 16 digits: a crack that is meant to match does
        // to far better than a millionth of a facet
        let tol = 1e-6 * mean;
        let (a, b) = (c.center_x - c.half_length, c.center_x + c.half_length);
        if (s0 - a).abs() > tol || (s1 - b).abs() > tol {
            return Err(inconsistent(
                "crack.half_length",
                format!(
                    "the mesh's pre-crack spans [{s0}, {s1}] m along the interface; [crack] says [{a}, {b}] m"
                ),
            ));
        }
    }
    Ok(())
}

/// Per material index (0: `[material]`, k: the k-th of the `materials` given), the smallest
/// length h_e [m] of its elements ([`crate::mesh::lengths::element_length`]); ∞ for a
/// material without elements.
fn min_lengths(prepared: &PreparedMesh, element_material: &[u8], materials: usize) -> Vec<f64> {
    let mut min_length = vec![f64::INFINITY; materials + 1];
    for e in 0..prepared.mesh.elements.len() {
        let k = element_material.get(e).copied().unwrap_or(0) as usize;
        let h = crate::mesh::lengths::element_length(&prepared.mesh, e);
        min_length[k] = min_length[k].min(h);
    }
    min_length
}

/// The `[fem]` form completed from the mesh: x_range and y_range its bounding box [m],
/// element_size the `mean` facet length [m], max_gap (if not given) the `shortest` one [m].
fn effective_form(f: &RawFem, prepared: &PreparedMesh, shortest: f64, mean: f64) -> RawFem {
    let mut effective = f.clone();
    let b = prepared.bbox;
    effective.x_range = b[0];
    effective.y_range = b[1];
    effective.element_size = mean;
    // the paper's detection distance: the smallest element size along the interface
    effective.max_gap = effective.max_gap.or(Some(shortest));
    effective
}

/// The file (resolved) and the roles. A group listed twice, in one role or in both crack roles,
/// is refused: each group has one role (a curve cannot be a pre-crack and a cohesive interface).
fn roles(m: &RawMesh, base_dir: Option<&Path>) -> Result<(PathBuf, MeshRoles), SceneError> {
    let Some(file) = &m.file else {
        return Err(inconsistent(
            "fem.mesh.file",
            "missing: give the Gmsh mesh file (MSH 4.1, relative to the scene file)",
        ));
    };
    let path = Path::new(file);
    let file = match base_dir {
        Some(d) if path.is_relative() => d.join(path),
        _ => path.to_path_buf(),
    };
    let list = |v: &Option<Vec<String>>| v.clone().unwrap_or_default();
    let roles = MeshRoles {
        bulk: list(&m.bulk),
        pre_crack: list(&m.pre_crack),
        interface: list(&m.interface),
    };
    for (role, names) in [
        ("bulk", &roles.bulk),
        ("pre_crack", &roles.pre_crack),
        ("interface", &roles.interface),
    ] {
        if let Some(name) = names
            .iter()
            .enumerate()
            .find_map(|(i, n)| names[..i].contains(n).then_some(n))
        {
            return Err(inconsistent(
                format!("fem.mesh.{role}"),
                format!("lists \"{name}\" twice"),
            ));
        }
    }
    if let Some(name) = roles.interface.iter().find(|n| roles.pre_crack.contains(n)) {
        return Err(inconsistent(
            "fem.mesh.interface",
            format!(
                "lists \"{name}\", which fem.mesh.pre_crack lists too: a curve is a pre-crack or a cohesive interface"
            ),
        ));
    }
    Ok((file, roles))
}

/// `[fem.mesh.laws]`: a cohesive law per interface curve, by the curve's name; the other curves
/// keep the `[interface]` law. Not with `[[fem.interface_zones]]` (two ways to say the same).
fn curve_laws(f: &RawFem, m: &RawMesh, roles: &MeshRoles) -> Result<Vec<Option<LinearCohesive>>, SceneError> {
    let mut out = vec![None; roles.interface.len()];
    let Some(laws) = &m.laws else {
        return Ok(out);
    };
    if !laws.is_empty() && f.interface_zones.as_ref().is_some_and(|z| !z.is_empty()) {
        return Err(inconsistent(
            "fem.mesh.laws",
            "give the interface curves their laws here or stretches of the interface in \
             [[fem.interface_zones]], not both",
        ));
    }
    // the model indexes its laws with a byte: [interface] and up to 254 others
    if laws.len() > 254 {
        return Err(inconsistent(
            "fem.mesh.laws",
            format!("{} laws given; at most 254", laws.len()),
        ));
    }
    for (name, raw) in laws {
        let Some(k) = roles.interface.iter().position(|c| c == name) else {
            return Err(inconsistent(
                format!("fem.mesh.laws.{name}"),
                format!(
                    "names no curve of fem.mesh.interface ({})",
                    roles.interface.join(", ")
                ),
            ));
        };
        out[k] = Some(cohesive_law(
            &format!("fem.mesh.laws.{name}"),
            [raw.sigma_c, raw.delta_c, raw.beta, raw.kappa],
        )?);
    }
    Ok(out)
}

/// `[fem.mesh.materials]`: per bulk surface (in the order of `roles.bulk`), its own material, or
/// `None` for `[material]`. Each key must name a surface of `fem.mesh.bulk`; the values are
/// checked as `[material]`'s.
fn surface_materials(m: &RawMesh, roles: &MeshRoles) -> Result<Vec<Option<PlaneStrain>>, SceneError> {
    let mut out = vec![None; roles.bulk.len()];
    let Some(materials) = &m.materials else {
        return Ok(out);
    };
    // the model indexes its materials with a byte: [material] and up to 255 others
    if materials.len() > 255 {
        return Err(inconsistent(
            "fem.mesh.materials",
            format!("{} materials given; at most 255", materials.len()),
        ));
    }
    for (name, raw) in materials {
        let Some(k) = roles.bulk.iter().position(|c| c == name) else {
            return Err(inconsistent(
                format!("fem.mesh.materials.{name}"),
                format!(
                    "names no surface of fem.mesh.bulk ({}); a material is given to a listed bulk surface",
                    if roles.bulk.is_empty() {
                        "none listed".to_string()
                    } else {
                        roles.bulk.join(", ")
                    }
                ),
            ));
        };
        out[k] = Some(material(&format!("fem.mesh.materials.{name}"), raw)?);
    }
    Ok(out)
}

/// The distinct materials given and each element's index (0: `[material]`, k: the k-th given),
/// both empty without `[fem.mesh.materials]`. An element in two listed surfaces must get the same
/// material from both (a surface without an entry gives `[material]`).
fn element_materials(
    p: &PreparedMesh,
    roles: &MeshRoles,
    given: &[Option<PlaneStrain>],
) -> Result<(Vec<PlaneStrain>, Vec<u8>), SceneError> {
    if given.iter().all(Option::is_none) {
        return Ok((Vec::new(), Vec::new()));
    }
    let materials: Vec<PlaneStrain> = given.iter().flatten().copied().collect();
    let mut index = Vec::with_capacity(given.len());
    let mut next = 0u8;
    for g in given {
        index.push(g.map_or(0, |_| {
            next += 1;
            next
        }));
    }
    let same = |a: u8, b: u8| {
        let of = |k: u8| (k > 0).then(|| materials[k as usize - 1]);
        a == b || (of(a).is_some() && of(a) == of(b))
    };
    // each element's material from the first surface that holds it
    let groups = roles.bulk.iter().map(|name| &p.mesh.groups[name].elements[..]);
    let from = first_surface(p.mesh.elements.len(), groups, |a, b| same(index[a], index[b])).map_err(
        |(e, first, s)| {
            let says = |s: usize| {
                if given[s].is_some() {
                    format!("fem.mesh.materials.{}", roles.bulk[s])
                } else {
                    "[material]".to_string()
                }
            };
            inconsistent(
                format!(
                    "fem.mesh.materials.{}",
                    roles.bulk[if given[s].is_some() { s } else { first }]
                ),
                format!(
                    "element {} lies in the surfaces \"{}\" ({}) and \"{}\" ({}), which give it \
                     different materials",
                    p.mesh.elements[e].tag,
                    roles.bulk[first],
                    says(first),
                    roles.bulk[s],
                    says(s)
                ),
            )
        },
    )?;
    let element_material = from.iter().map(|f| f.map_or(0, |s| index[s])).collect();
    Ok((materials, element_material))
}
