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

/// Per-node results of the last `resolve` plus friction history (struct of arrays indexed by node id;
/// entries of nodes outside N_det stay zero/false).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct ContactState {
    /// Slave had a contact element this step (used for damping, docs/fem-model.md §6).
    pub in_contact: Vec<bool>,
    /// Penetration p = −g ≥ 0 [m].
    pub penetration: Vec<f64>,
    /// Normal pressure p_N = ε_n p ≥ 0 [Pa].
    pub normal_pressure: Vec<f64>,
    /// Regularised pressure σ̃ ≥ 0 [Pa] of the Coulomb strength μ σ̃ (paper eq. 14): follows p_N
    /// over t* while the slave touches with friction, relaxes towards 0 otherwise (p_N with t* = 0).
    pub regularized_pressure: Vec<f64>,
    /// Whether the slave has ever had a contact element (its σ̃ starts at its first pressure).
    touched: Vec<bool>,
    /// Signed tangential traction T along the master tangent t_e [Pa].
    pub tangential_traction: Vec<f64>,
    /// Slip (true) or stick (false) this step.
    pub slipping: Vec<bool>,
    /// Nodal area A_i [m] (per unit thickness).
    pub area: Vec<f64>,
    /// Work done against the friction traction since t = 0, Σ −w A T Δs over every step in
    /// contact: the energy friction takes out of the relative sliding at this slave [J/m]. An
    /// audit quantity, summed from the kinematic slip, not from the return map's plastic slip.
    pub friction_work: Vec<f64>,
    /// The Coulomb bound of that work, Σ w A μ σ̃ |Δs| over the slipping steps [J/m] (σ̃ = p_N
    /// with t* = 0).
    pub coulomb_work: Vec<f64>,
    /// Friction history of the last step's contact element (None: no contact, history reset).
    history: Vec<Option<SlaveHistory>>,
}

impl ContactState {
    /// All-zero state for a mesh of `num_nodes` nodes.
    pub fn new(num_nodes: usize) -> Self {
        Self {
            in_contact: vec![false; num_nodes],
            penetration: vec![0.0; num_nodes],
            normal_pressure: vec![0.0; num_nodes],
            regularized_pressure: vec![0.0; num_nodes],
            touched: vec![false; num_nodes],
            tangential_traction: vec![0.0; num_nodes],
            slipping: vec![false; num_nodes],
            area: vec![0.0; num_nodes],
            friction_work: vec![0.0; num_nodes],
            coulomb_work: vec![0.0; num_nodes],
            history: vec![None; num_nodes],
        }
    }

    /// Stores node i's contact element of this step: results and next step's friction history.
    fn record(&mut self, i: usize, segment: [u32; 2], proj: &Projection, r: &ContactResponse) {
        self.in_contact[i] = true;
        self.touched[i] = true;
        self.penetration[i] = -proj.gap;
        self.normal_pressure[i] = r.normal_pressure;
        self.regularized_pressure[i] = r.friction_pressure;
        self.tangential_traction[i] = r.friction.traction;
        self.slipping[i] = r.friction.slipping;
        self.history[i] = Some(SlaveHistory {
            segment,
            xi: proj.xi,
            tangent: proj.frame.tangent,
            traction: r.friction.traction,
        });
    }

    /// Asks the cache for node i's entries of every array ([`prefetch`]).
    #[inline(always)]
    fn prefetch(&self, i: usize) {
        prefetch(&self.in_contact, i);
        prefetch(&self.penetration, i);
        prefetch(&self.normal_pressure, i);
        prefetch(&self.regularized_pressure, i);
        prefetch(&self.touched, i);
        prefetch(&self.tangential_traction, i);
        prefetch(&self.slipping, i);
        prefetch(&self.area, i);
        prefetch(&self.friction_work, i);
        prefetch(&self.coulomb_work, i);
        prefetch(&self.history, i);
    }

    /// Clears node i's results and friction history (no contact element this step); its σ̃
    /// relaxes towards 0 with ratio r = Δt/t* (eq. 14 with σ = 0; `None`: it is 0 at once).
    fn clear(&mut self, i: usize, prakash_ratio: Option<f64>) {
        self.in_contact[i] = false;
        self.penetration[i] = 0.0;
        self.normal_pressure[i] = 0.0;
        self.regularized_pressure[i] =
            crate::law::friction::regularized_normal(self.regularized_pressure[i], 0.0, prakash_ratio);
        self.tangential_traction[i] = 0.0;
        self.slipping[i] = false;
        self.history[i] = None;
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
    // Detection and the contact law per slave node are independent: in parallel, into one slot
    // per node. Forces, state and sums follow serially in node order, so the result does not
    // depend on the number of threads. Chunks of at least 1024 nodes: on the paper's centre crack
    // (about 1000 nodes in Γ_det) splitting cost more than it saved (126 against 116 µs per step
    // on 2 threads), so short interfaces run in one piece and long ones in parallel.
    let frictionless_law = |i: usize| frictionless.get(i).copied().unwrap_or(false);
    let (grid, frames, area_sum, normal) = (&ws.grid, &ws.frames, &ws.area_sum, &ws.normal);
    let (history, regularized, touched) = (&state.history, &state.regularized_pressure, &state.touched);
    nodes
        .par_iter()
        .enumerate()
        .with_min_len(1024)
        .map(|(k, &node)| {
            let i = node as usize;
            let slave = Slave {
                node,
                tied: tied_of(tied_twin, i),
                normal: normal[i],
            };
            // the slave's list holds every master it can take; a slave without one reads its
            // cell, whose wider reach tells whether a master lies deeper than d_max (lost)
            let (candidates, listed) = grid.candidates_of(k, x[i]);
            let (mut found, mut lost) =
                closest_master_or_depth(&slave, candidates, segments, frames, x, &limits);
            if found.is_none() && listed {
                let cell = grid.candidates(x[i]);
                (found, lost) = closest_master_or_depth(&slave, cell, segments, frames, x, &limits);
            }
            found.map_or(Detected::Lost(lost), |(e, proj)| {
                let segment = segments[e as usize];
                let law = if frictionless_law(i) { &no_friction } else { &law };
                let area = area_sum[i].norm();
                let r = respond(
                    p.eps_n,
                    law,
                    area,
                    (segment, &proj),
                    (history[i].as_ref(), touched[i].then_some(regularized[i])),
                    x,
                );
                Detected::Hit { segment, proj, r }
            })
        })
        .collect_into_vec(&mut ws.detected);
    let mut summary = ContactSummary::default();
    for (k, (&node, detected)) in nodes.iter().zip(&ws.detected).enumerate() {
        if let Some(&ahead) = nodes.get(k + AHEAD) {
            state.prefetch(ahead as usize);
            prefetch(f, ahead as usize);
        }
        let i = node as usize;
        let area = ws.area_sum[i].norm();
        state.area[i] = area;
        // each slave's result read in place, not copied whole
        let (segment, proj, r) = match detected {
            Detected::Lost(lost) => {
                summary.dropped += usize::from(*lost);
                state.clear(i, p.prakash_ratio);
                continue;
            }
            Detected::Hit { segment, proj, r } => (*segment, proj, r),
        };
        let law = if frictionless_law(i) { &no_friction } else { &law };
        scatter(f, node, segment, proj.xi_clamped, r.force);
        state.record(i, segment, proj, r);
        summary.contacts += 1;
        summary.max_penetration = summary.max_penetration.max(-proj.gap);
        let w_area = forces::AVERAGING_WEIGHT * area;
        summary.friction_dissipation +=
            w_area * law.friction_coeff * r.friction_pressure * r.friction.plastic_slip;
        state.friction_work[i] -= w_area * r.friction.traction * r.slip;
        if r.friction.slipping && law.friction_coeff > 0.0 {
            state.coulomb_work[i] += w_area * law.friction_coeff * r.friction_pressure * r.slip.abs();
        }
    }
    summary
}

/// Slaves ahead whose entries the serial pass of [`resolve`] asks the cache for. The per-node
/// arrays are indexed by node id and nothing else in the step reads most of them: without the
/// hint, the pass met them out of the core's caches, one miss after another
/// (docs/performance.md, "Contact at scale").
const AHEAD: usize = 8;

/// What detection and the contact law found for one slave node.
#[derive(Debug, Clone, Copy)]
enum Detected {
    /// No master segment; `true` if the node was lost because it lies deeper than the detection
    /// distance.
    Lost(bool),
    /// The closest master segment, the projection on it and the contact law's response.
    Hit {
        segment: [u32; 2],
        proj: Projection,
        r: ContactResponse,
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
