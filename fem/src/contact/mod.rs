//! Node-to-segment penalty contact with regularised Coulomb friction (paper Section 2, eqs. 5-10, Algorithm 1).
//!
//! Interface: `docs/fem-contact-api.md`. Detection (`search`) and resolution (`forces`) are split
//! as in Akantu; `geometry` is the pure projection. Every node of Γ_det is a slave and every
//! segment a master (no master/slave bias); forces are averaged with w = ½ (Algorithm 1).

pub(crate) mod forces;
pub(crate) mod geometry;
pub(crate) mod search;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_sliding;

use nalgebra::Vector2;
use rayon::prelude::*;

use crate::hint::prefetch;
use crate::law::friction::Friction;
pub(crate) use forces::AVERAGING_WEIGHT;
use forces::{ContactResponse, SlaveHistory, node_geometry, respond, scatter};
use geometry::{Projection, SegmentFrame};
use search::{BucketGrid, Limits, MAX_TIED, Slave, UNTIED, closest_master_or_depth};

/// Parameters of the contact pass (docs/fem-model.md §5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ContactParams {
    /// Normal penalty ε_n [Pa/m] (traction per penetration; paper eq. 8; docs/fem-model.md §5.2).
    pub eps_n: f64,
    /// Tangential penalty ε_t [Pa/m].
    pub eps_t: f64,
    /// Coulomb coefficient μ [-].
    pub friction_coeff: f64,
    /// Detection-distance limit d_max [m]: candidates with |g| > d_max are ignored (paper: h_min).
    pub max_gap: f64,
    /// Projection tolerance ε_ext [-]: accept −1 − ε_ext ≤ ξ ≤ 1 + ε_ext (default 1e-3).
    pub projection_tolerance: f64,
    /// r = Δt/t* [-] of the Prakash regularisation of the friction pressure (paper eq. 14);
    /// `None`: t* = 0, plain Coulomb.
    pub prakash_ratio: Option<f64>,
}

/// Γ_det (paper eq. 10): segments (j1, j2) stored in the counter-clockwise order of their single
/// owning bulk element, so the outward normal is n_e = (t_y, −t_x).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct DetectionSurface {
    /// Segments (j1, j2), owner counter-clockwise.
    segments: Vec<[u32; 2]>,
    /// N_det: nodes of the segments, each once, in order of first appearance.
    nodes: Vec<u32>,
    /// Membership flag of N_det, per node of the mesh.
    is_node: Vec<bool>,
}

impl DetectionSurface {
    /// Empty surface for a mesh of `num_nodes` nodes with room for `max_segments` segments: all that
    /// can ever be added (declared free faces + both copies of every interface facet), so
    /// `add_segment` never allocates inside the time loop.
    pub fn with_capacity(num_nodes: usize, max_segments: usize) -> Self {
        Self {
            segments: Vec::with_capacity(max_segments),
            nodes: Vec::with_capacity(num_nodes.min(2 * max_segments)),
            is_node: vec![false; num_nodes],
        }
    }

    /// Adds one segment; an inserted cohesive facet adds its + copy and its − copy (two calls).
    /// Beyond the capacity given to `with_capacity` it still works, at the cost of an allocation.
    pub fn add_segment(&mut self, j1: u32, j2: u32) {
        self.segments.push([j1, j2]);
        for j in [j1, j2] {
            let Some(flag) = self.is_node.get_mut(j as usize) else {
                continue;
            };
            if !*flag {
                *flag = true;
                self.nodes.push(j);
            }
        }
    }

    /// Reserves the capacities `like` has (a surface read back from a checkpoint, to which the
    /// time loop adds segments without allocating).
    pub fn keep_capacity(&mut self, like: &DetectionSurface) {
        self.segments
            .reserve(like.segments.capacity().saturating_sub(self.segments.len()));
        self.nodes
            .reserve(like.nodes.capacity().saturating_sub(self.nodes.len()));
    }

    /// Number of segments in Γ_det.
    pub fn num_segments(&self) -> usize {
        self.segments.len()
    }

    /// Nodes of Γ_det (N_det), each once.
    pub fn nodes(&self) -> &[u32] {
        &self.nodes
    }

    /// Segments (j1, j2) of Γ_det, owner counter-clockwise.
    pub fn segments(&self) -> &[[u32; 2]] {
        &self.segments
    }
}

/// One node's contact results of the last `resolve` and its friction history (all zero, false
/// and `None` for a node outside N_det).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct NodeContact {
    /// Slave had a contact element this step (used for damping, docs/fem-model.md §6).
    pub in_contact: bool,
    /// Penetration p = −g ≥ 0 [m].
    pub penetration: f64,
    /// Normal pressure p_N = ε_n p ≥ 0 [Pa].
    pub normal_pressure: f64,
    /// Regularised pressure σ̃ ≥ 0 [Pa] of the Coulomb strength μ σ̃ (paper eq. 14): follows p_N
    /// over t* while the slave touches with friction, relaxes towards 0 otherwise (p_N with t* = 0).
    pub regularized_pressure: f64,
    /// Whether the slave has ever had a contact element (its σ̃ starts at its first pressure).
    touched: bool,
    /// Signed tangential traction T along the master tangent t_e [Pa].
    pub tangential_traction: f64,
    /// Slip (true) or stick (false) this step.
    pub slipping: bool,
    /// Nodal area A_i [m] (per unit thickness).
    pub area: f64,
    /// Work done against the friction traction since t = 0, Σ −w A T Δs over every step in
    /// contact: the energy friction takes out of the relative sliding at this slave [J/m]. An
    /// audit quantity, summed from the kinematic slip, not from the return map's plastic slip.
    pub friction_work: f64,
    /// The Coulomb bound of that work, Σ w A μ σ̃ |Δs| over the slipping steps [J/m] (σ̃ = p_N
    /// with t* = 0).
    pub coulomb_work: f64,
    /// Friction history of the last step's contact element (None: no contact, history reset).
    history: Option<SlaveHistory>,
}

/// The state of a node outside N_det.
static OUTSIDE: NodeContact = NodeContact {
    in_contact: false,
    penetration: 0.0,
    normal_pressure: 0.0,
    regularized_pressure: 0.0,
    touched: false,
    tangential_traction: 0.0,
    slipping: false,
    area: 0.0,
    friction_work: 0.0,
    coulomb_work: 0.0,
    history: None,
};

impl NodeContact {
    /// Stores this step's contact element: results and next step's friction history.
    fn record(&mut self, segment: [u32; 2], proj: &Projection, r: &ContactResponse) {
        self.in_contact = true;
        self.touched = true;
        self.penetration = -proj.gap;
        self.normal_pressure = r.normal_pressure;
        self.regularized_pressure = r.friction_pressure;
        self.tangential_traction = r.friction.traction;
        self.slipping = r.friction.slipping;
        self.history = Some(SlaveHistory {
            segment,
            xi: proj.xi,
            tangent: proj.frame.tangent,
            traction: r.friction.traction,
        });
    }

    /// Clears the results and friction history (no contact element this step); σ̃ relaxes
    /// towards 0 with ratio r = Δt/t* (eq. 14 with σ = 0; `None`: it is 0 at once).
    fn clear(&mut self, prakash_ratio: Option<f64>) {
        self.in_contact = false;
        self.penetration = 0.0;
        self.normal_pressure = 0.0;
        self.regularized_pressure =
            crate::law::friction::regularized_normal(self.regularized_pressure, 0.0, prakash_ratio);
        self.tangential_traction = 0.0;
        self.slipping = false;
        self.history = None;
    }
}

/// Every node's contact results of the last `resolve` and friction history, stored per node of
/// N_det in the order of [`DetectionSurface::nodes`] (a node keeps its place: N_det only grows),
/// so that each slave's task in `resolve` owns its entry; [`ContactState::at`] reads them by node
/// id.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct ContactState {
    /// Per node of the mesh, its place in `nodes`, or `u32::MAX` outside N_det (or before the
    /// first `resolve` that meets it).
    place: Vec<u32>,
    /// The nodes of N_det `resolve` has met, in its order: the first `nodes.len()` of
    /// [`DetectionSurface::nodes`].
    nodes: Vec<NodeContact>,
}

impl ContactState {
    /// An empty state for a mesh of `num_nodes` nodes whose Γ_det holds at most `max_segments`
    /// segments (the room `resolve` needs, so that it never allocates).
    pub fn new(num_nodes: usize, max_segments: usize) -> Self {
        Self {
            place: vec![u32::MAX; num_nodes],
            nodes: Vec::with_capacity(num_nodes.min(2 * max_segments)),
        }
    }

    /// Node n's contact state (all zero for a node outside N_det).
    pub fn at(&self, n: usize) -> &NodeContact {
        match self.place.get(n) {
            Some(&k) if k != u32::MAX => &self.nodes[k as usize],
            _ => &OUTSIDE,
        }
    }

    /// The nodes of N_det with their states, in increasing node id whatever the order of N_det:
    /// the order of a sum over the mesh's nodes. It skips the mesh's nodes sixteen at a time
    /// where none is in N_det, so a record step does not visit every node one by one.
    pub fn in_node_order(&self) -> impl Iterator<Item = (usize, &NodeContact)> {
        const BLOCK: usize = 16;
        self.place
            .chunks(BLOCK)
            .enumerate()
            .filter(|(_, block)| block.iter().any(|&k| k != u32::MAX))
            .flat_map(move |(b, block)| {
                block
                    .iter()
                    .enumerate()
                    .filter(|&(_, &k)| k != u32::MAX)
                    .map(move |(j, &k)| (b * BLOCK + j, &self.nodes[k as usize]))
            })
    }

    /// Gives the nodes of N_det that joined it since the last call (the tail of `nodes`) their
    /// place, with an empty state.
    fn admit(&mut self, nodes: &[u32]) {
        for &n in &nodes[self.nodes.len().min(nodes.len())..] {
            self.place[n as usize] = self.nodes.len() as u32;
            self.nodes.push(OUTSIDE);
        }
    }

    /// Room for nodes of N_det (for the no-allocation tests).
    #[cfg(test)]
    pub fn capacity(&self) -> usize {
        self.nodes.capacity()
    }
}

/// Preallocated scratch (bucket grid, candidate lists): no allocation in `resolve`.
#[derive(Debug, Clone)]
pub(crate) struct ContactWorkspace {
    /// Bucket grid of master segments.
    grid: BucketGrid,
    /// Frame of every segment of Γ_det at the current positions (`None`: degenerate).
    frames: Vec<Option<SegmentFrame>>,
    /// Per-node Σ (L_e/2) n_e [m].
    area_sum: Vec<Vector2<f64>>,
    /// Per-node slave normal n_i [-].
    normal: Vec<Vector2<f64>>,
    /// One detection result per node of Γ_det, in its order.
    detected: Vec<Detected>,
}

/// An empty workspace, to be replaced by one sized for its mesh ([`ContactWorkspace::new`]).
impl Default for ContactWorkspace {
    fn default() -> Self {
        Self::new(0, 0)
    }
}

impl ContactWorkspace {
    /// Scratch for a mesh of `num_nodes` nodes and at most `max_segments` segments in Γ_det.
    pub fn new(num_nodes: usize, max_segments: usize) -> Self {
        Self {
            grid: BucketGrid::with_capacity(max_segments),
            detected: Vec::with_capacity(num_nodes.min(2 * max_segments)),
            frames: Vec::with_capacity(max_segments),
            area_sum: vec![Vector2::zeros(); num_nodes],
            normal: vec![Vector2::zeros(); num_nodes],
        }
    }
}

/// Totals of one contact pass.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct ContactSummary {
    /// Number of slave nodes with a contact element.
    pub contacts: usize,
    /// Friction dissipation of this step, Σ_slip w A_i μ σ̃ Δs_p [J/m] (w = ½; σ̃ = p_N with t* = 0).
    pub friction_dissipation: f64,
    /// Largest penetration [m].
    pub max_penetration: f64,
    /// Slaves whose only facing master lay deeper than d_max: contacts lost this step [-].
    pub dropped: usize,
}

/// One contact pass at the current positions (paper Algorithm 1, docs/fem-model.md §5): bucket search,
/// exclusion rules, smallest-|g| valid master, normal penalty, friction return map, averaged
/// scatter with w = ½ (action = reaction).
/// - `x`: current positions of all nodes [m].
/// - `tied_twin[i]`: the node i is currently tied to (docs/fem-model.md §3.1), or `u32::MAX`; tied
///   twins are never a contact pair.
/// - `frictionless[i]`: slave i carries no friction this step (empty: every slave does).
/// - adds the contact forces [N/m] into `f` (all nodes; the caller routes forces on prescribed
///   DOFs into reactions and sums tied twins).
#[allow(clippy::too_many_arguments)]
pub(crate) fn resolve(
    p: &ContactParams,
    surface: &mut DetectionSurface,
    x: &[Vector2<f64>],
    tied_twin: &[u32],
    frictionless: &[bool],
    state: &mut ContactState,
    ws: &mut ContactWorkspace,
    f: &mut [Vector2<f64>],
) -> ContactSummary {
    if surface.num_segments() == 0 {
        return ContactSummary::default(); // Γ_det = ∅ (standard model, nothing inserted yet)
    }
    let segments = surface.segments();
    let nodes = surface.nodes();
    node_geometry(
        segments,
        nodes,
        x,
        &mut ws.frames,
        (&mut ws.area_sum, &mut ws.normal),
    );
    ws.grid
        .update(segments, nodes, x, p.max_gap, p.projection_tolerance);
    let law = Friction {
        eps_t: p.eps_t,
        friction_coeff: p.friction_coeff,
        prakash_ratio: p.prakash_ratio,
    };
    let no_friction = Friction {
        friction_coeff: 0.0,
        ..law
    };
    let limits = Limits {
        max_gap: p.max_gap,
        projection_tolerance: p.projection_tolerance,
    };
    // Detection and the contact law per slave node are independent: in parallel, each slave's
    // task writing its own node's state (stored in the order of N_det, which lists each node
    // once) and handing on what the shared sums need. Forces and sums follow serially in node
    // order, so the result does not depend on the number of threads. Chunks of at least 1024
    // nodes: on the paper's centre crack (about 1000 nodes in Γ_det) splitting cost more than it
    // saved (126 against 116 µs per step on 2 threads), so short interfaces run in one piece and
    // long ones in parallel.
    let frictionless_law = |i: usize| frictionless.get(i).copied().unwrap_or(false);
    let (grid, frames, area_sum, normal) = (&ws.grid, &ws.frames, &ws.area_sum, &ws.normal);
    let detect_and_respond = |k: usize, own: &mut NodeContact, node: u32| -> Detected {
        let i = node as usize;
        let slave = Slave {
            node,
            tied: tied_of(tied_twin, i),
            normal: normal[i],
        };
        // the slave's list holds every master it can take; a slave without one reads its
        // cell, whose wider reach tells whether a master lies deeper than d_max (lost)
        let (candidates, listed) = grid.candidates_of(k, x[i]);
        let (mut found, mut lost) = closest_master_or_depth(&slave, candidates, segments, frames, x, &limits);
        if found.is_none() && listed {
            let cell = grid.candidates(x[i]);
            (found, lost) = closest_master_or_depth(&slave, cell, segments, frames, x, &limits);
        }
        let area = area_sum[i].norm();
        own.area = area;
        let Some((e, proj)) = found else {
            own.clear(p.prakash_ratio);
            return Detected::Lost(lost);
        };
        let segment = segments[e as usize];
        let law = if frictionless_law(i) { &no_friction } else { &law };
        let r = respond(
            p.eps_n,
            law,
            area,
            (segment, &proj),
            (
                own.history.as_ref(),
                own.touched.then_some(own.regularized_pressure),
            ),
            x,
        );
        own.record(segment, &proj, &r);
        let w_area = forces::AVERAGING_WEIGHT * area;
        own.friction_work -= w_area * r.friction.traction * r.slip;
        if r.friction.slipping && law.friction_coeff > 0.0 {
            own.coulomb_work += w_area * law.friction_coeff * r.friction_pressure * r.slip.abs();
        }
        Detected::Hit {
            segment,
            xi_clamped: proj.xi_clamped,
            force: r.force,
            depth: -proj.gap,
            dissipation: w_area * law.friction_coeff * r.friction_pressure * r.friction.plastic_slip,
        }
    };
    state.admit(nodes);
    // Each task writes what it hands on into its own slot. Returned through rayon's `map` and
    // `collect_into_vec`, the value passed through the stack and was read back at once in other
    // widths (docs/performance.md, "Contact at scale": "What each slave hands on, written in
    // its slot").
    ws.detected.resize(nodes.len(), Detected::Lost(false));
    state
        .nodes
        .par_iter_mut()
        .zip(nodes.par_iter())
        .zip(ws.detected.par_iter_mut())
        .enumerate()
        .with_min_len(1024)
        .for_each(|(k, ((own, &node), out))| {
            *out = detect_and_respond(k, own, node);
        });
    let mut summary = ContactSummary::default();
    for (k, (&node, detected)) in nodes.iter().zip(&ws.detected).enumerate() {
        if let Some(&ahead) = nodes.get(k + AHEAD) {
            prefetch(f, ahead as usize);
        }
        match *detected {
            Detected::Lost(lost) => summary.dropped += usize::from(lost),
            Detected::Hit {
                segment,
                xi_clamped,
                force,
                depth,
                dissipation,
            } => {
                scatter(f, node, segment, xi_clamped, force);
                summary.contacts += 1;
                summary.max_penetration = summary.max_penetration.max(depth);
                summary.friction_dissipation += dissipation;
            }
        }
    }
    summary
}

/// Slaves ahead whose force entries the serial pass of [`resolve`] asks the cache for: a slave's
/// masters lie anywhere in the node arrays ([`prefetch`]).
const AHEAD: usize = 8;

/// What detection and the contact law found for one slave node, as far as the serial pass needs
/// it (the slave's own state is already written).
#[derive(Debug, Clone, Copy)]
enum Detected {
    /// No master segment; `true` if the node was lost because it lies deeper than the detection
    /// distance.
    Lost(bool),
    /// A contact element.
    Hit {
        /// The master segment (j1, j2).
        segment: [u32; 2],
        /// ξ_c, the projection's natural coordinate clamped to the segment [-].
        xi_clamped: f64,
        /// The force on the slave before averaging, F [N/m].
        force: Vector2<f64>,
        /// The penetration −g [m].
        depth: f64,
        /// The slave's friction dissipation this step, w A_i μ σ̃ Δs_p [J/m].
        dissipation: f64,
    },
}

/// The nodes node i is tied to: its twin, or the rest of its tie ring at a junction (at most
/// [`MAX_TIED`]; the split refuses wider junctions).
fn tied_of(tied_twin: &[u32], i: usize) -> [u32; MAX_TIED] {
    let mut out = UNTIED;
    let mut t = tied_twin.get(i).copied().unwrap_or(u32::MAX);
    for slot in &mut out {
        if t == u32::MAX || t == i as u32 {
            break;
        }
        *slot = t;
        t = tied_twin[t as usize];
    }
    out
}
