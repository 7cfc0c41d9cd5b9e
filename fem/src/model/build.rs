//! Scene -> (Model, State, Workspace): the only place that allocates.

use crate::contact::{ContactParams, ContactState, ContactWorkspace, DetectionSurface};
use crate::error::BuildError;
use crate::law::cohesive::{ClosingTreatment, CohesiveState, LinearCohesive};
use crate::law::elastic::PlaneStrain;
use crate::mesh::interfaces::{FacetKind, InterfaceRow, NO_JUNCTION, column_tied, tie_junction};
use crate::mesh::nearest_node;
use crate::mesh::structured::{Grid, GridSpec};
use crate::model::bulk::{self, Stiffness};
use crate::model::face_stress::FaceStress;
use crate::model::loading;
use crate::model::mapped::{MappedStiffness, Trapezoid};
use crate::model::state::{
    Boundary, BoundaryDof, Bulk, BulkMesh, ContactPart, Damping, Dashpot, ElementNodes, EnergyTotals, Facets,
    GmshBulk, Interface, Model, Observed, State, Workspace,
};
use crate::model::unstructured::{BulkMaterial, UnstructuredBulk};
use crate::scene::MeshSpec;
use crate::scene::{ContactSurface, ModelKind, Scene, zone_of};
use nalgebra::Vector2;

/// Builds the model, its initial state and the workspace from a validated scene.
pub fn build(scene: &Scene) -> Result<(Model, State, Workspace), BuildError> {
    if let Some(m) = &scene.fem.mesh {
        return build_on_mesh(scene, m);
    }
    match scene.fem.interface_polyline {
        Some(_) => build_with_row_map(scene, Some(&|x| scene.fem.interface_y(x))),
        None => build_with_row_map(scene, None),
    }
}

/// The mesh-dependent parts of a model, before the scene's options are added.
pub(crate) struct MeshParts {
    pub x0: Vec<Vector2<f64>>,
    pub mesh: BulkMesh,
    pub mass: Vec<f64>,
    pub iface: Option<InterfaceRow>,
    pub boundary: loading::BoundaryData,
    /// Material index of each bulk element into `Scene::materials` (empty: all of material 0).
    pub element_material: Vec<u8>,
}

/// As [`build`], with the interface row (y = 0) mapped onto y = f(x) [m] (paper Section 4 meshes).
pub fn build_with_row_map(
    scene: &Scene,
    row_map: Option<&dyn Fn(f64) -> f64>,
) -> Result<(Model, State, Workspace), BuildError> {
    let grid = grid(scene, row_map);
    let element_material = grid_element_material(scene, &grid);
    let (stiffness, mass) = if element_material.is_empty() {
        let d = scene.material.d_matrix();
        (
            stiffness(&grid, &d)?,
            lumped_masses(&grid, scene.material.density),
        )
    } else {
        split_bulk(scene, &grid, &element_material)?
    };
    let crack = scene.crack.map(|c| (c.center_x, c.half_length));
    let iface = InterfaceRow::new(&grid, crack, scene.interface.is_some());
    let boundary = loading::boundary(scene, &grid);
    assemble(
        scene,
        MeshParts {
            x0: grid.x0.clone(),
            mesh: BulkMesh::Grid { grid, stiffness },
            mass,
            iface,
            boundary,
            element_material,
        },
    )
}

/// The model on the scene's Gmsh mesh, split along its interface at validation.
fn build_on_mesh(scene: &Scene, spec: &MeshSpec) -> Result<(Model, State, Workspace), BuildError> {
    let p = &spec.prepared;
    let materials: Vec<BulkMaterial> = scene
        .materials()
        .iter()
        .map(|m| BulkMaterial {
            d: m.d_matrix(),
            density: m.density,
        })
        .collect();
    let kernel = UnstructuredBulk::with_materials(&p.mesh, &materials, &spec.element_material)?;
    let elements = p
        .mesh
        .elements
        .iter()
        .map(|e| ElementNodes::from_slice(&e.nodes))
        .collect();
    assemble(
        scene,
        MeshParts {
            x0: p.mesh.positions.clone(),
            mass: kernel.masses().to_vec(),
            mesh: BulkMesh::Gmsh(Box::new(GmshBulk { kernel, elements })),
            iface: p.row.clone(),
            boundary: loading::boundary_on_mesh(scene, p),
            element_material: spec.element_material.clone(),
        },
    )
}

/// The prescribed DOFs whose node has a twin free in that component, with that twin (see
/// `Model::held_twins`). Empty on the built-in grids, whose sides hold both copies.
fn held_twins(
    prescribed: &[BoundaryDof],
    fixed_dof: &[[bool; 2]],
    iface: Option<&InterfaceRow>,
) -> Vec<(u32, u32)> {
    let Some(row) = iface else { return Vec::new() };
    let mut twin = vec![u32::MAX; fixed_dof.len()];
    for (i, (&m, &p)) in row.minus.iter().zip(&row.plus).enumerate() {
        if m != p && row.col_junction[i] == NO_JUNCTION {
            twin[m as usize] = p;
            twin[p as usize] = m;
        }
    }
    prescribed
        .iter()
        .enumerate()
        .filter_map(|(k, b)| {
            let t = twin[b.node as usize];
            (t != u32::MAX && !fixed_dof[t as usize][b.dof as usize]).then_some((k as u32, t))
        })
        .collect()
}

/// The dashpots with, for each node of the interface row among them, its twin (a dashpot of
/// zero, if the absorbing part does not hold it): while the pair is tied, the pair moves as one
/// node under the sum of both dashpots. An absorbing part through a junction is refused.
fn with_twins(
    mut dashpots: Vec<Dashpot>,
    iface: Option<&InterfaceRow>,
    x0: &[Vector2<f64>],
) -> Result<Vec<Dashpot>, BuildError> {
    let Some(row) = iface else { return Ok(dashpots) };
    if dashpots.is_empty() {
        return Ok(dashpots);
    }
    let has = |d: &[Dashpot], n: u32| d.binary_search_by_key(&n, |d| d.node).is_ok();
    for i in 0..row.minus.len() {
        let (m, p) = (row.minus[i], row.plus[i]);
        if m == p || !(has(&dashpots, m) || has(&dashpots, p)) {
            continue;
        }
        if row.col_junction[i] != NO_JUNCTION {
            let x = x0[m as usize];
            return Err(BuildError::AbsorbingJunction { x: x.x, y: x.y });
        }
        let (part, relative) = dashpots
            .iter()
            .find(|d| d.node == m || d.node == p)
            .map_or((0, false), |d| (d.part, d.relative));
        for n in [m, p] {
            if let Err(k) = dashpots.binary_search_by_key(&n, |d| d.node) {
                dashpots.insert(
                    k,
                    Dashpot {
                        node: n,
                        c: [0.0; 3],
                        part,
                        relative,
                    },
                );
            }
        }
    }
    Ok(dashpots)
}

/// A support on a copy of a junction is refused: its tie group would not follow the support
/// (a held twin pair is supported by [`held_twins`]; a group of k ≥ 2 copies is not).
fn held_junction(
    row: &InterfaceRow,
    prescribed: &[BoundaryDof],
    x0: &[Vector2<f64>],
) -> Result<(), BuildError> {
    for cols in &row.junctions {
        let copies = cols
            .iter()
            .flat_map(|&i| [row.minus[i as usize], row.plus[i as usize]]);
        for n in copies {
            if prescribed.iter().any(|p| p.node == n) {
                let x = x0[n as usize];
                return Err(BuildError::HeldJunction { x: x.x, y: x.y });
            }
        }
    }
    Ok(())
}

/// The model from its mesh parts and the scene's options, with its initial state and workspace.
pub(crate) fn assemble(scene: &Scene, parts: MeshParts) -> Result<(Model, State, Workspace), BuildError> {
    let f = &scene.fem;
    let MeshParts {
        x0,
        mesh,
        mass,
        iface,
        boundary: bd,
        element_material,
    } = parts;
    let mut fixed_dof = vec![[false; 2]; x0.len()];
    for p in &bd.prescribed {
        fixed_dof[p.node as usize][p.dof as usize] = true;
    }
    if let Some(row) = &iface {
        held_junction(row, &bd.prescribed, &x0)?;
    }
    let held_twins = held_twins(&bd.prescribed, &fixed_dof, iface.as_ref());
    let dashpots = with_twins(bd.dashpots, iface.as_ref(), &x0)?;
    let mut dashpot_of = Vec::new();
    if !dashpots.is_empty() {
        dashpot_of = vec![u32::MAX; x0.len()];
        for (k, d) in dashpots.iter().enumerate() {
            dashpot_of[d.node as usize] = k as u32;
        }
    }
    // the layers the grid's one-pass sweep leaves to the corrector (a Gmsh mesh has no sweep)
    let deferred = match &mesh {
        BulkMesh::Grid { grid, .. } => {
            // a dashpot's force, like a load, is added before the corrector
            let neumann_nodes: Vec<u32> = bd
                .neumann
                .iter()
                .map(|p| p.node)
                .chain(dashpots.iter().map(|d| d.node))
                .collect();
            crate::model::layers::deferred_layers(grid, &fixed_dof, &neumann_nodes)
        }
        BulkMesh::Gmsh(_) => Vec::new(),
    };
    let probes = f
        .probes
        .iter()
        .map(|p| nearest_node(&x0, Vector2::new(p[0], p[1])) as u32)
        .collect();
    let chunk = match &mesh {
        BulkMesh::Grid { grid, .. } => grid.nx + 1,
        BulkMesh::Gmsh(_) => crate::model::layers::CHUNK,
    };
    let mut model = Model {
        bulk: Bulk {
            mesh,
            d: scene.materials().iter().map(|m| m.d_matrix()).collect(),
            element_material,
            mass,
            deferred,
            chunk,
            apart: Vec::new(),
            x0,
        },
        interface: interface(scene, iface),
        boundary: Boundary {
            ramps: bd.ramps,
            prescribed: bd.prescribed,
            neumann: bd.neumann,
            parts: bd.parts,
            fixed_dof,
            held_twins,
            lateral_contraction: f.lateral_contraction,
            dashpots,
            dashpot_of,
            far_field: bd.far_field,
        },
        damping: Damping {
            set: f.damping.set,
            factor: f.damping.factor(scene.time_step()),
        },
        observed: Observed {
            probes,
            crack: scene.crack.map(|c| (c.center_x, c.half_length)),
            diagnostics: f.diagnostics.clone(),
        },
        dt: scene.time_step(),
        // the guard against a blow-up: no node outruns 10 times the fastest material's c_d
        cd: scene
            .materials()
            .iter()
            .map(|m| m.wave_speeds().cd)
            .fold(0.0, f64::max),
    };
    model.interface.facet_faces = facet_faces(&model);
    model.bulk.apart =
        crate::model::layers::apart_chunks(model.num_nodes(), model.bulk.chunk, model.interface.row.as_ref());
    let state = initial_state(&model);
    let ws = workspace(&model);
    Ok((model, state, ws))
}

/// The interface room: the row, its laws per facet, how closed elements resist, the insertion
/// rule and the contact parameters (its facets' stress sampling is added once the bulk is built).
fn interface(scene: &Scene, row: Option<InterfaceRow>) -> Interface {
    let f = &scene.fem;
    let (laws, facet_law) = facet_laws(scene, &row);
    Interface {
        facet_detect: facet_law
            .iter()
            .map(|&k| match f.contact_surface {
                ContactSurface::All => true,
                ContactSurface::Zones => k > 0,
            })
            .collect(),
        laws,
        facet_law,
        closing: match f.model {
            ModelKind::Hybrid => ClosingTreatment::Hybrid,
            ModelKind::Standard => ClosingTreatment::Standard { eps_n: f.eps_n },
        },
        insertion_rule: f.insertion_rule,
        contact: scene.has_contact().then_some(ContactParams {
            eps_n: f.eps_n,
            eps_t: f.eps_t,
            friction_coeff: scene.friction_coeff,
            max_gap: f.max_gap,
            projection_tolerance: f.projection_tolerance,
            prakash_ratio: (f.t_star > 0.0).then(|| scene.time_step() / f.t_star),
        }),
        friction_failed_only: scene.contact_friction == crate::scene::ContactFriction::FailedOnly,
        row,
        facet_faces: Vec::new(),
    }
}

/// How each interface facet samples the stress of its (+, −) elements (insertion).
fn facet_faces(model: &Model) -> Vec<[FaceStress; 2]> {
    let Some(row) = &model.interface.row else {
        return Vec::new();
    };
    (0..row.num_facets())
        .map(|c| {
            let [ep, em] = row.face_edges[c];
            [(row.elem_plus[c], ep), (row.elem_minus[c], em)].map(|(e, edge)| {
                crate::model::face_stress::face_of(
                    &model.bulk.x0,
                    model.element_nodes(e as usize).as_slice(),
                    edge as usize,
                )
            })
        })
        .collect()
}

/// The cohesive laws (0: `[interface]`, then `[[fem.interface_zones]]`, then the curves of
/// `[fem.mesh.laws]`; none without an interface) and the law of each facet of the interface row:
/// its curve's on a mesh with curve laws, else the zone holding its midpoint's coordinate.
fn facet_laws(scene: &Scene, iface: &Option<InterfaceRow>) -> (Vec<LinearCohesive>, Vec<u8>) {
    let f = &scene.fem;
    let Some(base) = scene.interface else {
        return (Vec::new(), vec![0; iface.as_ref().map_or(0, |r| r.num_facets())]);
    };
    let mut laws: Vec<LinearCohesive> = std::iter::once(base)
        .chain(f.interface_zones.iter().map(|z| z.law))
        .collect();
    let curve_laws = f.mesh.as_ref().filter(|m| m.laws.iter().any(Option::is_some));
    let facet_law = match (curve_laws, iface) {
        (Some(m), Some(_)) => {
            let index: Vec<u8> = m
                .laws
                .iter()
                .map(|l| {
                    l.map_or(0, |l| {
                        laws.push(l);
                        (laws.len() - 1) as u8
                    })
                })
                .collect();
            m.prepared
                .facet_curve
                .iter()
                .map(|&k| index.get(k as usize).copied().unwrap_or(0))
                .collect()
        }
        _ => facet_centres(iface)
            .map(|x| zone_of(&f.interface_zones, x) as u8)
            .collect(),
    };
    (laws, facet_law)
}

/// Interface coordinate [m] of each facet midpoint of the interface row (none without a row):
/// x on the built-in grids, the arc length along the interface on a Gmsh mesh.
fn facet_centres(iface: &Option<InterfaceRow>) -> impl Iterator<Item = f64> + '_ {
    iface.iter().flat_map(move |row| {
        (0..row.num_facets()).map(move |c| {
            let [sa, sb] = row.facet_span(c);
            0.5 * (sa + sb)
        })
    })
}

/// Whether the grid's y = 0 row is twinned: a pre-crack or an interface exists.
fn twinned(scene: &Scene) -> bool {
    scene.crack.is_some() || scene.interface.is_some()
}

/// Whether a grid of a split `[material]` keeps one K_e a material and with it the stencils and
/// the one-pass sweep ([`split_bulk`]), read from the scene alone, before anything is built: its
/// elements are translates of one another (a grid not mapped onto an interface path) and no layer
/// of nodes touches element rows of both materials (its y = 0 row, where the materials meet, is
/// twinned). Otherwise it keeps one K_e an element and takes the separate passes. The estimate of a
/// run prices the two apart (`solver::estimate`).
pub(crate) fn split_grid_keeps_stencils(scene: &Scene) -> bool {
    scene.fem.mesh.is_none() && scene.fem.interface_polyline.is_none() && twinned(scene)
}

/// The structured grid of the scene; the y = 0 row is twinned when a pre-crack or an interface exists.
fn grid(scene: &Scene, row_map: Option<&dyn Fn(f64) -> f64>) -> Grid {
    let f = &scene.fem;
    let h = f.element_size;
    let jc = scene.interface_row();
    let twinned = twinned(scene);
    Grid::new(&GridSpec {
        x_range: f.x_range,
        y_range: f.y_range,
        nx: ((f.x_range[1] - f.x_range[0]) / h).round() as usize,
        ny: ((f.y_range[1] - f.y_range[0]) / h).round() as usize,
        twinned_row: twinned.then_some(jc),
        upper_shift: f.upper_offset * h,
        row_map: row_map.map(|m| (jc, m)),
    })
}

/// With a split `[material]`, the material of each grid element: 0 (`[material.top]`) for the
/// element rows above the interface row, whose centroids lie above it, 1 (`[material.bottom]`)
/// below; empty with one material.
fn grid_element_material(scene: &Scene, grid: &Grid) -> Vec<u8> {
    if scene.bottom_material.is_none() {
        return Vec::new();
    }
    let jc = scene.interface_row();
    (0..grid.num_elements())
        .map(|e| if e / grid.nx >= jc { 0 } else { 1 })
        .collect()
}

/// Stiffness and row-sum lumped masses [kg/m] (each element with its own density) of a grid of
/// several materials: one shared K_e a material when the elements are translates of one another
/// and no layer touches element rows of two materials (the split at the twinned row), so that
/// the grid keeps its stencils and the one-pass sweep; else one K_e per element, each with its own
/// material's D.
fn split_bulk(
    scene: &Scene,
    grid: &Grid,
    element_material: &[u8],
) -> Result<(Stiffness, Vec<f64>), BuildError> {
    let materials = scene.materials();
    let d: Vec<_> = materials.iter().map(|m| m.d_matrix()).collect();
    let mass = split_masses(grid, element_material, &materials);
    let nx = grid.nx;
    let row_kind: Option<Vec<u8>> = (0..grid.ny)
        .map(|r| {
            let kind = element_material[r * nx];
            element_material[r * nx..(r + 1) * nx]
                .iter()
                .all(|&k| k == kind)
                .then_some(kind)
        })
        .collect();
    if let Some(row_kind) = row_kind.filter(|_| translates(grid)) {
        let kinds = d
            .iter()
            .map(|d| {
                bulk::stiffness(&grid.element_coords(0), d)
                    .map_err(|det_j| BuildError::InvertedElement { element: 0, det_j })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if let Some(k) = Stiffness::by_row(grid, &kinds, row_kind) {
            return Ok((k, mass));
        }
    }
    let ke = (0..grid.num_elements())
        .map(|e| {
            bulk::stiffness(&grid.element_coords(e), &d[element_material[e] as usize])
                .map_err(|det_j| BuildError::InvertedElement { element: e, det_j })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok((Stiffness::PerElement(ke), mass))
}

/// Row-sum lumped nodal masses [kg/m] of a grid whose element e has density
/// `materials[element_material[e]]`.
fn split_masses(grid: &Grid, element_material: &[u8], materials: &[PlaneStrain]) -> Vec<f64> {
    let mut mass = vec![0.0; grid.num_nodes()];
    for e in 0..grid.num_elements() {
        let m = bulk::lumped_mass(
            &grid.element_coords(e),
            materials[element_material[e] as usize].density,
        );
        for (k, n) in grid.element_nodes(e).iter().enumerate() {
            mass[*n as usize] += m[k];
        }
    }
    mass
}

/// Whether every element of the grid is a translate of element 0 (to 1e-9 of its diagonal).
fn translates(grid: &Grid) -> bool {
    let c0 = grid.element_coords(0);
    let tol = 1e-9 * (c0[2] - c0[0]).norm();
    (0..grid.num_elements()).all(|e| {
        let c = grid.element_coords(e);
        (0..4).all(|k| ((c[k] - c[0]) - (c0[k] - c0[0])).norm() <= tol)
    })
}

/// Row-sum lumped nodal masses [kg/m].
fn lumped_masses(grid: &Grid, density: f64) -> Vec<f64> {
    let mut mass = vec![0.0; grid.num_nodes()];
    for e in 0..grid.num_elements() {
        let m = bulk::lumped_mass(&grid.element_coords(e), density);
        for (k, n) in grid.element_nodes(e).iter().enumerate() {
            mass[*n as usize] += m[k];
        }
    }
    mass
}

/// The nodes whose u the insertion check reads (`model::insertion::check`), which hold those the
/// cohesive law reads: the nodes of the elements on both sides of every cohesive facet, sorted and
/// each once (none without cohesive laws).
fn checked_nodes(model: &Model) -> Vec<u32> {
    let Some(row) = model
        .interface
        .row
        .as_ref()
        .filter(|_| !model.interface.laws.is_empty())
    else {
        return Vec::new();
    };
    let mut nodes: Vec<u32> = (0..row.num_facets())
        .filter(|&c| row.kind[c] == FacetKind::Cohesive)
        .flat_map(|c| [row.elem_plus[c], row.elem_minus[c]])
        .flat_map(|e| model.element_nodes(e as usize).as_slice().to_vec())
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Every buffer of the step, sized once.
fn workspace(model: &Model) -> Workspace {
    let n = model.num_nodes();
    let with_contact = model.interface.contact.is_some();
    let check_nodes = if model.grid().is_some() {
        checked_nodes(model)
    } else {
        Vec::new()
    };
    Workspace {
        f: vec![Vector2::zeros(); n],
        x: if with_contact {
            model.bulk.x0.clone()
        } else {
            Vec::new()
        },
        f_con: if with_contact {
            vec![Vector2::zeros(); n]
        } else {
            Vec::new()
        },
        frictionless: if with_contact && model.interface.friction_failed_only {
            vec![false; n]
        } else {
            Vec::new()
        },
        row_u_old: vec![Vector2::zeros(); model.interface.row.as_ref().map_or(0, |r| 2 * r.minus.len())],
        ramp_values: vec![0.0; model.boundary.ramps.len()],
        strain_energy: 0.0,
        clock: Default::default(),
        predicted: false,
        sweep: match model.grid() {
            Some(grid) => crate::model::layers::SweepBuffers::new(grid),
            None => crate::model::layers::SweepBuffers::none(model.bulk.apart.len()),
        },
        reached: Vec::with_capacity(model.interface.row.as_ref().map_or(0, |r| r.num_facets())),
        cohesive_forces: Vec::with_capacity(model.interface.row.as_ref().map_or(0, |r| r.num_facets())),
        // zeroed by the allocator: the pages of nodes the check does not read stay untouched
        check_u: if check_nodes.is_empty() {
            Vec::new()
        } else {
            bytemuck::zeroed_vec(n)
        },
        check_nodes,
    }
}

/// One shared K_e when every element is a translate of element 0; on-the-fly forces when every
/// element has vertical sides and the same width (mapped meshes); else one K_e per element.
fn stiffness(grid: &Grid, d: &[[f64; 3]; 3]) -> Result<Stiffness, BuildError> {
    let c0 = grid.element_coords(0);
    let same = translates(grid);
    let k_of = |e: usize| {
        bulk::stiffness(&grid.element_coords(e), d)
            .map_err(|det_j| BuildError::InvertedElement { element: e, det_j })
    };
    if same {
        return Ok(Stiffness::shared(k_of(0)?));
    }
    let width = c0[1].x - c0[0].x;
    let shapes: Option<Vec<Trapezoid>> = (0..grid.num_elements())
        .map(|e| Trapezoid::of(&grid.element_coords(e), width))
        .collect();
    // an anisotropic D (shear coupled to the normal strains) takes one K_e per element
    let mapped = shapes
        .and_then(|shapes| MappedStiffness::new(0.5 * width, *d, grid.nx, &shapes).map(|k| (shapes, k)));
    if let Some((shapes, mapped)) = mapped {
        // det J = (h/2) y_η > 0 at every point iff both vertical sides have positive height
        if let Some(e) = shapes.iter().position(|s| s.v_left <= 0.0 || s.v_right <= 0.0) {
            let s = shapes[e];
            return Err(BuildError::InvertedElement {
                element: e,
                det_j: 0.5 * width * s.v_left.min(s.v_right),
            });
        }
        Ok(Stiffness::Mapped(Box::new(mapped)))
    } else {
        (0..grid.num_elements())
            .map(k_of)
            .collect::<Result<Vec<_>, _>>()
            .map(Stiffness::PerElement)
    }
}

fn initial_state(model: &Model) -> State {
    let n = model.num_nodes();
    let nf = model.interface.row.as_ref().map_or(0, |r| r.num_facets());
    let zero_state = CohesiveState {
        sigma_c_eff: 0.0,
        delta_c_eff: 1.0,
        delta_max: 0.0,
        damage: 0.0,
        t_ins: Vector2::zeros(),
    };
    let facets = Facets {
        inserted: vec![false; nf],
        sign: vec![1.0; nf],
        gauss: vec![[zero_state; 2]; nf],
        prev_opening: vec![[Vector2::zeros(); 2]; nf],
        prev_traction: vec![[Vector2::zeros(); 2]; nf],
        insert_time: vec![f64::NAN; nf],
        fail_time: vec![[f64::NAN; 2]; nf],
        work_density: vec![[0.0; 2]; nf],
        active: Vec::with_capacity(nf),
        column_insert_time: vec![f64::NAN; model.interface.row.as_ref().map_or(1, |r| r.minus.len())],
    };
    let mut tied_twin = vec![u32::MAX; n];
    let mut contact = None;
    if let Some(row) = &model.interface.row {
        for i in 0..row.minus.len() {
            // a crack tip inside the body is one node, not a pair; a junction's columns are tied
            // below, as a group
            if row.minus[i] != row.plus[i]
                && row.col_junction[i] == NO_JUNCTION
                && column_tied(row, &facets.inserted, i)
            {
                tied_twin[row.minus[i] as usize] = row.plus[i];
                tied_twin[row.plus[i] as usize] = row.minus[i];
            }
        }
        for j in 0..row.junctions.len() {
            tie_junction(row, &facets.inserted, j, &mut tied_twin);
        }
        if model.interface.contact.is_some() {
            let cap = 2 * row.num_interface_facets();
            let mut surface = DetectionSurface::with_capacity(n, cap);
            for c in 0..row.num_facets() {
                if row.kind[c] == FacetKind::PreCrack && model.interface.facet_detect[c] {
                    add_facet_faces(&mut surface, row, c);
                }
            }
            contact = Some(ContactPart {
                surface,
                state: ContactState::new(n, cap),
                ws: ContactWorkspace::new(n, cap),
                f_prev: vec![Vector2::zeros(); 2 * row.minus.len()],
                max_penetration: 0.0,
                dropped_step: 0,
                dropped_total: 0,
            });
        }
    }
    State {
        step: 0,
        t: 0.0,
        u: vec![Vector2::zeros(); n],
        v: vec![Vector2::zeros(); n],
        a: vec![Vector2::zeros(); n],
        tied_twin,
        facets,
        contact,
        energy: EnergyTotals::default(),
        presc_u: vec![0.0; model.boundary.prescribed.len()],
        presc_v: vec![0.0; model.boundary.prescribed.len()],
        presc_r: vec![0.0; model.boundary.prescribed.len()],
        neumann_f: vec![0.0; model.boundary.neumann.len()],
        dashpot_f: vec![Vector2::zeros(); model.boundary.dashpots.len()],
    }
}

/// Adds both faces of facet c to Γ_det, each in its owner's counter-clockwise order: the + face
/// is the bottom edge of the upper element (a⁺ → b⁺), the − face the top edge of the lower (b⁻ → a⁻).
pub(crate) fn add_facet_faces(surface: &mut DetectionSurface, row: &InterfaceRow, c: usize) {
    let [a, b] = row.facet_columns(c);
    surface.add_segment(row.plus[a], row.plus[b]);
    surface.add_segment(row.minus[b], row.minus[a]);
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;
    use crate::test_scenes::scene_text;

    #[test]
    fn bad_polyline_is_refused() {
        let text = scene_text("tiny-fem-center-crack").replace(
            "[fem]\n",
            "[fem]\ninterface_polyline = [[0.01, 0.0], [0.005, 1e-3]]\n",
        );
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("fem.interface_polyline"), "{e}");
    }

    /// A split `[material]` on the grid: every element whose centroid lies above the interface
    /// row y = 0 is of material 0 (`[material.top]`), every other of material 1; the nodal masses
    /// are the row sums of each side's own density (a node of the + copy of the row gets ρ_top
    /// h²/4 per element, of the − copy ρ_bottom h²/4), exact to round-off (1e-12 relative), and the
    /// per-element stiffness is each side's D.
    #[test]
    fn a_split_grid_gives_each_element_its_sides_material() {
        let scene = Scene::from_toml_str_in(
            &scene_text("tiny-fem-bimaterial-grid"),
            std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes")),
        )
        .unwrap();
        let (model, _, _) = super::build(&scene).unwrap();
        let grid = model.grid().unwrap();
        let (top, bottom) = (scene.material, scene.material_below());
        assert_ne!(top.density, bottom.density);
        let h = scene.fem.element_size;
        for e in 0..grid.num_elements() {
            let c = grid.element_coords(e);
            let yc = 0.25 * c.iter().map(|p| p.y).sum::<f64>();
            let k = model.bulk.element_material[e];
            assert_eq!(k, if yc > 0.0 { 0 } else { 1 }, "element {e} at y = {yc}");
            let want = if yc > 0.0 {
                top.d_matrix()
            } else {
                bottom.d_matrix()
            };
            assert_eq!(model.d_of(e), &want);
        }
        let row = model.interface.row.as_ref().unwrap();
        // an interior column: two elements on each side of the row
        let i = 2;
        let (mp, mm) = (
            model.bulk.mass[row.plus[i] as usize],
            model.bulk.mass[row.minus[i] as usize],
        );
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(rel(mp, 2.0 * top.density * h * h / 4.0) < 1e-12, "{mp}");
        assert!(rel(mm, 2.0 * bottom.density * h * h / 4.0) < 1e-12, "{mm}");
    }

    /// What the scene alone says of a split grid's stiffness (`split_grid_keeps_stencils`, which
    /// the run's estimate reads) is what the build does: one K_e a material where the y = 0 row
    /// is twinned on a grid of translates, one K_e an element without the twin (a layer then
    /// touches both materials) or on a grid mapped onto an interface path.
    #[test]
    fn the_scene_tells_whether_a_split_grid_keeps_its_stencils() {
        use crate::model::bulk::Stiffness;
        use crate::model::state::BulkMesh;
        let base = scene_text("tiny-fem-bimaterial-grid");
        let interface = &base[base.find("[interface]").unwrap()..base.find("[loading]").unwrap()];
        let cases = [
            ("twinned at its interface", base.clone(), true),
            ("no interface and no crack", base.replace(interface, ""), false),
            (
                "mapped onto a path",
                base.replace(
                    "[fem]\n",
                    "[fem]\ninterface_polyline = [[-0.03, 0.0], [0.0, 0.004], [0.03, 0.0]]\n",
                ),
                false,
            ),
        ];
        for (what, text, keeps) in cases {
            let dir = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes"));
            let scene = Scene::from_toml_str_in(&text, dir).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert!(scene.bottom_material.is_some(), "{what}");
            let (model, _, _) = super::build(&scene).unwrap();
            let by_row = matches!(
                model.bulk.mesh,
                BulkMesh::Grid {
                    stiffness: Stiffness::ByRow(_),
                    ..
                }
            );
            assert_eq!(by_row, keeps, "{what}: built");
            assert_eq!(
                super::split_grid_keeps_stencils(&scene),
                keeps,
                "{what}: from the scene"
            );
        }
    }
}
