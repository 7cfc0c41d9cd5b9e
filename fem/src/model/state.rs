//! Model (immutable after build), State (struct of arrays, evolves) and Workspace (every buffer
//! the step needs, allocated once).

use crate::contact::{ContactParams, ContactState, ContactWorkspace, DetectionSurface};
use crate::law::cohesive::{ClosingTreatment, CohesiveState, LinearCohesive};
use crate::mesh::interfaces::InterfaceRow;
use crate::mesh::structured::Grid;
use crate::model::bulk::Stiffness;
use crate::model::face_stress::FaceStress;
use crate::model::unstructured::UnstructuredBulk;
use crate::scene::{DampingSet, Diagnostics, InsertionRule, Ramp};
use nalgebra::Vector2;

/// One boundary DOF whose value (displacement [m] or force [N/m]) is Σ_k coeff_k · ramp_k(t).
#[derive(Debug, Clone, Copy)]
pub(crate) struct BoundaryDof {
    /// Node id.
    pub node: u32,
    /// 0 = x, 1 = y.
    pub dof: u8,
    /// (index into `Model::ramps`, coefficient); coefficient 0 terms are unused.
    pub terms: [(u8, f64); 2],
}

impl BoundaryDof {
    /// Value given the ramp values at the current time.
    #[inline]
    pub fn value(&self, ramps: &[f64]) -> f64 {
        self.terms.iter().map(|&(k, c)| c * ramps[k as usize]).sum()
    }
}

/// The viscous dashpot of one node of an absorbing part: the force −C v [N/m] with C symmetric.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dashpot {
    /// Node id.
    pub node: u32,
    /// (C_xx, C_xy, C_yy) [N·s/m²]; zero for the free twin of an absorbing node, which shares
    /// its pair's dashpot while the pair is tied.
    pub c: [f64; 3],
    /// The absorbing part whose force `boundary.csv` books it under (the last that names the node).
    pub part: u16,
    /// The dashpot acts on the velocity relative to the far field's motion (`Boundary::far_field`).
    pub relative: bool,
}

/// The motion of the uniform far field of `[loading]` (σ_xx = 0, σ_yy, σ_xy), that the dashpots of
/// far-field parts take their velocity from: v∞ = ε̇∞ (x − x_c), with no rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct FarFieldMotion {
    /// σ_yy(t) [Pa].
    pub normal: Ramp,
    /// σ_xy(t) [Pa].
    pub shear: Ramp,
    /// ε_xx, ε_yy per unit σ_yy and γ_xy per unit σ_xy [1/Pa] (plane strain).
    pub compliance: [f64; 3],
    /// x_c [m]: the centroid of the dashpots that follow the far field, which it leaves at rest.
    pub center: Vector2<f64>,
}

impl FarFieldMotion {
    /// v∞ [m/s] at reference position `x` [m] and time `t` [s].
    #[inline]
    pub fn velocity(&self, x: Vector2<f64>, t: f64) -> Vector2<f64> {
        self.strain_field(x, self.normal.rate(t), self.shear.rate(t))
    }

    /// The far field's strain rate ε̇∞ [1/s] or its second derivative ε̈∞ [1/s²] at `t` [s]:
    /// (ε_xx, ε_yy, ½γ), whose product with x − x_c is v∞ or a∞.
    #[inline]
    pub fn acceleration_gradient(&self, t: f64) -> [f64; 3] {
        let (sn, ss) = (self.normal.acceleration(t), self.shear.acceleration(t));
        [
            self.compliance[0] * sn,
            self.compliance[1] * sn,
            0.5 * self.compliance[2] * ss,
        ]
    }

    /// The linear field ε (x − x_c) of the strain (rate) of stresses (rates) σ_yy, σ_xy.
    #[inline]
    fn strain_field(&self, x: Vector2<f64>, syy: f64, sxy: f64) -> Vector2<f64> {
        let (exx, eyy, half_g) = (
            self.compliance[0] * syy,
            self.compliance[1] * syy,
            0.5 * self.compliance[2] * sxy,
        );
        let d = x - self.center;
        Vector2::new(exx * d.x + half_g * d.y, half_g * d.x + eyy * d.y)
    }
}

/// The parts of `[fem.boundary]` as `boundary.csv` reports them (empty with the Westergaard field).
#[derive(Debug, Clone, Default)]
pub(crate) struct BoundaryParts {
    /// Name of each part, in the order the conditions apply.
    pub names: Vec<String>,
    /// Nodes of each part (a node shared by two parts is in both).
    pub nodes: Vec<Vec<u32>>,
    /// Per entry of `Model::prescribed`: the part whose condition holds it (the last one
    /// that names the node and component).
    pub prescribed: Vec<u16>,
    /// Per entry of `Model::neumann`: the part whose load it is.
    pub neumann: Vec<u16>,
}

/// The model: mesh, topology, parameters, in five rooms. Immutable during the run.
#[derive(Debug)]
pub struct Model {
    /// The bulk: nodes, elements, materials, masses.
    pub(crate) bulk: Bulk,
    /// The interface row and what acts on it: cohesive laws, insertion, contact and friction.
    pub(crate) interface: Interface,
    /// The boundary conditions, with the parts `boundary.csv` reports.
    pub(crate) boundary: Boundary,
    /// Velocity damping of interface nodes (docs/fem-model.md §6).
    pub(crate) damping: Damping,
    /// What the observers record beyond the state: probes, the pre-crack, Section 4 diagnostics.
    pub(crate) observed: Observed,
    /// Time step Δt [s].
    pub(crate) dt: f64,
    /// Dilatational speed c_d [m/s] of the fastest material (the stability guard's scale).
    pub(crate) cd: f64,
}

/// The bulk of the model: where the nodes are, how the elements join them, what they weigh.
#[derive(Debug)]
pub(crate) struct Bulk {
    /// Reference node positions X [m] (twins share a position).
    pub x0: Vec<Vector2<f64>>,
    /// The elements and their internal-force kernel (grid or Gmsh mesh).
    pub mesh: BulkMesh,
    /// Plane-strain Voigt matrix D [Pa] of each bulk material (0: `[material]`).
    pub d: Vec<[[f64; 3]; 3]>,
    /// Material index of each bulk element (empty: every element is of material 0).
    pub element_material: Vec<u8>,
    /// Lumped nodal mass [kg/m].
    pub mass: Vec<f64>,
    /// Per layer of the grid: kept out of the one-pass sweep of unsampled steps
    /// (`solver::sweep`); empty on a Gmsh mesh.
    pub deferred: Vec<bool>,
    /// Nodes per chunk of the corrector: a grid's node layer, else [`crate::model::layers::CHUNK`].
    pub chunk: usize,
    /// Per chunk of the corrector: holds an interface node, so its corrector and the next step's
    /// predictor stay two passes (`model::layers::apart_chunks`).
    pub apart: Vec<bool>,
}

/// The interface row and what acts on it (paper §2: extrinsic cohesive elements, eqs. 2–3, and
/// node-to-segment contact with Coulomb friction, eqs. 4–8).
#[derive(Debug)]
pub(crate) struct Interface {
    /// The twinned row of nodes and its facets (`None`: no interface and no pre-crack).
    pub row: Option<InterfaceRow>,
    /// Stress sampling of the (+, −) elements of each interface facet (insertion checks).
    pub facet_faces: Vec<[FaceStress; 2]>,
    /// Cohesive laws: 0 = `[interface]`, k = `interface_zones[k − 1]`; empty without an interface.
    pub laws: Vec<LinearCohesive>,
    /// Law index of each facet of the interface row.
    pub facet_law: Vec<u8>,
    /// Whether each facet's faces join Γ_det once free (pre-crack) or inserted (eqs. 10, 16).
    pub facet_detect: Vec<bool>,
    /// How closed cohesive elements resist interpenetration: the hybrid model's contact, or the
    /// standard model's compression penalty (eq. 4).
    pub closing: ClosingTreatment,
    /// Where the insertion check reads the stress (docs/fem-model.md §4).
    pub insertion_rule: InsertionRule,
    /// Contact penalties ε_n, ε_t [Pa/m], friction coefficient [-] and detection distances [m]
    /// (`None`: no contact surface).
    pub contact: Option<ContactParams>,
    /// Friction only on faces whose facets have fully failed (`contact_friction = "failed_only"`).
    pub friction_failed_only: bool,
}

/// The boundary conditions: prescribed displacements and loads, each a sum of ramps.
#[derive(Debug)]
pub(crate) struct Boundary {
    /// Time histories referenced by the boundary DOFs.
    pub ramps: Vec<Ramp>,
    /// The prescribed DOFs: displacement [m] as a sum of ramps.
    pub prescribed: Vec<BoundaryDof>,
    /// The loaded DOFs: force [N/m] as a sum of ramps.
    pub neumann: Vec<BoundaryDof>,
    /// The parts of `[fem.boundary]` and which part each prescribed and Neumann DOF belongs to.
    pub parts: BoundaryParts,
    /// Per node and component (x, y): the DOF is prescribed.
    pub fixed_dof: Vec<[bool; 2]>,
    /// (index into `prescribed`, twin node) for each prescribed DOF whose node has a twin that
    /// is free in that component: a chain end where a held boundary curve ends. While the pair
    /// is tied the twin follows the prescribed motion and its force goes to the support.
    pub held_twins: Vec<(u32, u32)>,
    /// The Westergaard boundary field has the lateral-contraction term (docs/fem-model.md §7).
    pub lateral_contraction: bool,
    /// The dashpots of the absorbing parts, one per node, by node id (docs/fem-model.md §7).
    pub dashpots: Vec<Dashpot>,
    /// Per node: its entry in `dashpots`, or u32::MAX (empty without dashpots).
    pub dashpot_of: Vec<u32>,
    /// The far field's motion, when a part carries it (`far_field = true`).
    pub far_field: Option<FarFieldMotion>,
}

/// Velocity damping of interface nodes: v ← c v on the damped set after each step.
#[derive(Debug)]
pub(crate) struct Damping {
    /// Which interface nodes are damped.
    pub set: DampingSet,
    /// Velocity factor c per step of the damped nodes [-] (1: none).
    pub factor: f64,
}

/// What the observers record beyond the state.
#[derive(Debug)]
pub(crate) struct Observed {
    /// Probe node ids.
    pub probes: Vec<u32>,
    /// Pre-crack (x_c, a) [m]: its centre and half-length, for the tip records.
    pub crack: Option<(f64, f64)>,
    /// Section 4 diagnostics to record.
    pub diagnostics: Diagnostics,
}

/// The bulk mesh and its internal-force kernel.
#[derive(Debug)]
pub(crate) enum BulkMesh {
    /// The built-in structured or mapped grid of Q4 elements.
    Grid {
        /// Node layers and element rows.
        grid: Grid,
        /// Element stiffness storage (or the mapped-mesh forces).
        stiffness: Stiffness,
    },
    /// A Gmsh mesh of T3 and Q4 elements, split along its interface.
    Gmsh(Box<GmshBulk>),
}

/// A Gmsh mesh's elements and kernel.
#[derive(Debug)]
pub(crate) struct GmshBulk {
    /// The T3/Q4 force kernel (positions, masses, connectivity in its own order).
    pub kernel: UnstructuredBulk,
    /// Node indices of each element, counter-clockwise, in the mesh's order.
    pub elements: Vec<ElementNodes>,
}

/// The nodes of one bulk element: 4 for a Q4, 3 for a T3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ElementNodes {
    nodes: [u32; 4],
    len: u8,
}

impl ElementNodes {
    /// The element's nodes (3 or 4), counter-clockwise.
    pub(crate) fn from_slice(nodes: &[usize]) -> ElementNodes {
        let mut out = [u32::MAX; 4];
        for (o, &n) in out.iter_mut().zip(nodes) {
            *o = n as u32;
        }
        ElementNodes {
            nodes: out,
            len: nodes.len() as u8,
        }
    }

    /// The nodes, counter-clockwise.
    #[inline]
    pub(crate) fn as_slice(&self) -> &[u32] {
        &self.nodes[..self.len as usize]
    }
}

/// Cohesive state of the interface row's facets (struct of arrays, indexed by facet).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct Facets {
    pub inserted: Vec<bool>,
    /// Normal orientation sign s_e fixed at insertion.
    pub sign: Vec<f64>,
    pub gauss: Vec<[CohesiveState; 2]>,
    /// Previous opening Δ [m] and traction T [Pa] per Gauss point (energy accounting).
    pub prev_opening: Vec<[Vector2<f64>; 2]>,
    pub prev_traction: Vec<[Vector2<f64>; 2]>,
    /// Insertion time [s] (NaN: not inserted).
    pub insert_time: Vec<f64>,
    /// Time of full failure per Gauss point [s] (NaN: not yet).
    pub fail_time: Vec<[f64; 2]>,
    /// Cumulative cohesive work per unit length per Gauss point ∫T·dΔ [J/m²].
    pub work_density: Vec<[f64; 2]>,
    /// Inserted facets, in insertion order (capacity: every cohesive facet).
    pub active: Vec<u32>,
    /// Last time a cohesive element touching column i was inserted [s] (NaN: never).
    pub column_insert_time: Vec<f64>,
}

/// Accumulated energies [J/m].
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct EnergyTotals {
    pub boundary_work: f64,
    pub cohesive_total: f64,
    pub contact_work: f64,
    pub friction: f64,
    pub damping: f64,
    /// Work taken out of the body by the absorbing boundaries' dashpots (≥ 0).
    pub absorbed: f64,
}

/// Node-to-segment contact state (hybrid model with contact surfaces only).
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub(crate) struct ContactPart {
    pub surface: DetectionSurface,
    pub state: ContactState,
    /// Scratch of the contact pass: not part of a checkpoint (each pass rebuilds it).
    #[serde(skip)]
    pub ws: ContactWorkspace,
    /// Contact force of the previous step per interface-row slot [N/m] (minus row then plus row).
    pub f_prev: Vec<Vector2<f64>>,
    pub max_penetration: f64,
    /// Contacts lost to the detection distance in the last step, and since t = 0 [-].
    pub dropped_step: usize,
    pub dropped_total: u64,
}

/// Evolving state: everything a checkpoint holds of the model (`solver::checkpoint`).
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct State {
    pub(crate) step: u64,
    /// Time t [s].
    pub(crate) t: f64,
    /// Displacement u [m], velocity v [m/s], acceleration a [m/s²], per node.
    pub(crate) u: Vec<Vector2<f64>>,
    pub(crate) v: Vec<Vector2<f64>>,
    pub(crate) a: Vec<Vector2<f64>>,
    /// Tied twin of each node or u32::MAX (docs/fem-model.md §3.1).
    pub(crate) tied_twin: Vec<u32>,
    pub(crate) facets: Facets,
    pub(crate) contact: Option<ContactPart>,
    pub(crate) energy: EnergyTotals,
    /// ū_n per prescribed DOF [m], its velocity [m/s] and the previous static reaction −f [N/m].
    pub(crate) presc_u: Vec<f64>,
    pub(crate) presc_v: Vec<f64>,
    pub(crate) presc_r: Vec<f64>,
    /// Previous Neumann force per entry [N/m].
    pub(crate) neumann_f: Vec<f64>,
    /// Previous dashpot force per entry of `Boundary::dashpots` [N/m].
    pub(crate) dashpot_f: Vec<Vector2<f64>>,
}

/// A facet that reached σ_c at the insertion check: its index in the interface row, then the
/// traction vector t_q [Pa] and effective stress σ_eff [Pa] at its two Gauss points.
pub(crate) type Reached = (u32, [(Vector2<f64>, f64); 2]);

/// Nodal forces [N/m] of one cohesive element, on nodes [a⁺, b⁺, a⁻, b⁻] of its facet.
pub(crate) type ElementForces = [Vector2<f64>; 4];

/// Every buffer of the step, allocated at build.
#[derive(Debug)]
pub struct Workspace {
    /// Assembled nodal force [N/m].
    pub(crate) f: Vec<Vector2<f64>>,
    /// Current positions x = X + u [m] (contact only).
    pub(crate) x: Vec<Vector2<f64>>,
    /// Contact forces, non-zero on interface-row nodes only [N/m].
    pub(crate) f_con: Vec<Vector2<f64>>,
    /// Per node: contact friction is off this step (`contact_friction = "failed_only"` and the
    /// node's facets have not all failed); empty otherwise.
    pub(crate) frictionless: Vec<bool>,
    /// Interface-row displacements before the predictor [m] (minus row then plus row).
    pub(crate) row_u_old: Vec<Vector2<f64>>,
    /// Ramp values at the current time.
    pub(crate) ramp_values: Vec<f64>,
    /// Strain energy of the last sampled step [J/m].
    pub(crate) strain_energy: f64,
    /// Wall time per phase of the step (profiling; never part of the records).
    pub(crate) clock: crate::profile::Clock,
    /// The free nodes off the interface layers already hold the next step's predictor
    /// (u_{n+1} + Δt v_{n+1} + ½Δt² a_{n+1}, v_{n+1} + ½Δt a_{n+1}): the corrector of an unsampled
    /// step fuses the next step's predictor into the same sweep over memory.
    pub(crate) predicted: bool,
    /// Scratch of the one-pass sweep of unsampled steps.
    pub(crate) sweep: crate::model::layers::SweepBuffers,
    /// The facets that reached σ_c at this step's insertion check (capacity: the row's facets).
    pub(crate) reached: Vec<Reached>,
    /// Each active cohesive element's nodal forces [N/m] of this step, computed beside the bulk
    /// forces and added to `f` after them (capacity: the row's facets).
    pub(crate) cohesive_forces: Vec<ElementForces>,
    /// On a grid, whose one-pass sweep moves u on in the bulk phase: the nodes the
    /// insertion check reads (those of the elements on both sides of the cohesive facets, which
    /// hold those the cohesive law reads), sorted; empty elsewhere.
    pub(crate) check_nodes: Vec<u32>,
    /// u_{n+1} [m] of `check_nodes`, copied before the sweep for the check and the cohesive law
    /// beside it (indexed by node, zeroed by the allocator: the other entries are never read,
    /// their pages never touched); empty where `check_nodes` is.
    pub(crate) check_u: Vec<Vector2<f64>>,
}

impl Model {
    /// Time step Δt [s].
    pub fn time_step(&self) -> f64 {
        self.dt
    }

    /// Number of nodes (twins counted twice).
    pub fn num_nodes(&self) -> usize {
        self.bulk.x0.len()
    }

    /// Number of bulk elements.
    pub fn num_elements(&self) -> usize {
        match &self.bulk.mesh {
            BulkMesh::Grid { grid, .. } => grid.num_elements(),
            BulkMesh::Gmsh(g) => g.elements.len(),
        }
    }

    /// The structured grid, if the model is built on one.
    pub(crate) fn grid(&self) -> Option<&Grid> {
        match &self.bulk.mesh {
            BulkMesh::Grid { grid, .. } => Some(grid),
            BulkMesh::Gmsh(_) => None,
        }
    }

    /// Plane-strain Voigt matrix D [Pa] of bulk element `e`'s material.
    #[inline]
    pub(crate) fn d_of(&self, e: usize) -> &[[f64; 3]; 3] {
        &self.bulk.d[self.bulk.element_material.get(e).copied().unwrap_or(0) as usize]
    }

    /// The nodes of bulk element `e`, counter-clockwise.
    #[inline]
    pub(crate) fn element_nodes(&self, e: usize) -> ElementNodes {
        match &self.bulk.mesh {
            BulkMesh::Grid { grid, .. } => ElementNodes {
                nodes: grid.element_nodes(e),
                len: 4,
            },
            BulkMesh::Gmsh(g) => g.elements[e],
        }
    }

    /// f = −f_int(u) [N/m] for every node (overwrites `f`); parallel and the same to the bit for
    /// any number of threads.
    pub(crate) fn internal_forces(&self, u: &[Vector2<f64>], f: &mut [Vector2<f64>]) {
        match &self.bulk.mesh {
            BulkMesh::Grid { grid, stiffness } => crate::model::bulk::internal_forces(grid, stiffness, u, f),
            BulkMesh::Gmsh(g) => g.kernel.internal_forces(u, f),
        }
    }
}

impl State {
    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Steps done.
    pub fn step_count(&self) -> u64 {
        self.step
    }

    /// Number of inserted cohesive elements.
    pub fn num_inserted(&self) -> usize {
        self.facets.active.len()
    }

    /// Displacements [m] per node.
    pub fn displacements(&self) -> &[Vector2<f64>] {
        &self.u
    }

    /// The contact nodes (N_det, the nodes of Γ_det, paper eq. 10) and how many of them had a
    /// contact element in the last step [-]; (0, 0) without contact.
    pub fn contact_nodes(&self) -> (usize, usize) {
        self.contact.as_ref().map_or((0, 0), |c| {
            let nodes = c.surface.nodes();
            let touching = nodes
                .iter()
                .filter(|&&i| c.state.at(i as usize).in_contact)
                .count();
            (nodes.len(), touching)
        })
    }
}

impl Workspace {
    /// Wall time per phase so far.
    pub fn profile(&self) -> Vec<crate::profile::PhaseTime> {
        self.clock.phases()
    }
}
