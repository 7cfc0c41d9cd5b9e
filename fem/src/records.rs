//! The records of a run (docs/solver-api.md): what the observers of `diag` take from the state
//! at each sample and at the end, gathered in [`RunOutput`]. Plain data: `output` writes them as
//! CSV, `compare` and the tests read them. The field snapshots ParaView shows are in [`fields`].

pub mod fields;

use serde::{Deserialize, Serialize};

/// One sample of the crack-tip history; positions are x coordinates [m], time t [s].
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct TipRecord {
    /// Time [s].
    pub t: f64,
    /// Right crack tip (fully broken up to here) [m].
    pub tip_right: f64,
    /// Left crack tip [m].
    pub tip_left: f64,
    /// Right cohesive-zone tip (damage > 0, contiguous) [m].
    pub cz_tip_right: f64,
    /// Left cohesive-zone tip [m].
    pub cz_tip_left: f64,
}

/// The cracked extent of one interface chain at one sample: what a crack-growth history needs on
/// any interface network, with or without a pre-crack. Each of a cohesive facet's two Gauss points
/// stands for half of the facet's reference length; pre-crack facets are not counted.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct CrackRecord {
    /// Time [s].
    pub t: f64,
    /// Interface chain [-] (0, 1, … as docs/meshes.md orders them; 0 on the built-in grids).
    pub chain: u16,
    /// Length of the chain's cohesive facets [m] (what may break).
    pub cohesive_length: f64,
    /// Length whose Gauss points are fully broken, d = 1 [m].
    pub broken_length: f64,
    /// Length whose Gauss points carry a cohesive element with 0 < d < 1 (process zones) [m].
    pub process_zone_length: f64,
    /// Smallest chain coordinate of a broken Gauss point [m] (NaN: none broken).
    pub broken_from: f64,
    /// Largest chain coordinate of a broken Gauss point [m] (NaN: none broken).
    pub broken_to: f64,
}

/// One crack (or one process zone that has not broken yet) on one interface chain at one sample,
/// with its crack tips and cohesive-zone tips: every crack of every chain, with or without a
/// pre-crack. A crack is a stretch of consecutive broken points of the chain; its cohesive zones
/// reach to the ends of the run of consecutive damaged points that holds it (two cracks joined by
/// a damaged ligament share them). A pre-crack facet counts as broken from end to end, a cohesive
/// facet by its two Gauss points. Coordinates are the chain's own (x on the built-in grids); on
/// a closed chain a run across the chain's first node has its start beyond its end.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct CrackTipRecord {
    /// Time [s].
    pub t: f64,
    /// Interface chain [-] (0, 1, … as docs/meshes.md orders them; 0 on the built-in grids).
    pub chain: u16,
    /// The crack's rank on its chain at this sample, from the chain's start [-].
    pub crack: u16,
    /// Crack tip towards the chain's start: the crack's first broken point [m] (NaN: a process
    /// zone, nothing broken yet).
    pub tip_start: f64,
    /// Crack tip towards the chain's end: the crack's last broken point [m] (NaN as above).
    pub tip_end: f64,
    /// Cohesive-zone tip towards the chain's start: the first point of the damaged run [m].
    pub cz_start: f64,
    /// Cohesive-zone tip towards the chain's end: the last point of the damaged run [m].
    pub cz_end: f64,
}

/// The displacement of one part of `[fem.boundary]` (a side, curve or point) and the force its
/// conditions apply to the body, at one sample: a load–displacement curve for any part.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct BoundaryRecord {
    /// Time [s].
    pub t: f64,
    /// The part, as an index into [`RunOutput::boundary_parts`] [-].
    pub part: u16,
    /// Mean displacement of the part's nodes [m].
    pub ux: f64,
    /// Mean displacement of the part's nodes [m].
    pub uy: f64,
    /// Total force on the part's nodes [N/m]: on a component a displacement holds, the static
    /// reaction R = −f (the force the support applies against the internal, cohesive and contact
    /// forces of the node; its own inertia m ā is not in it); on a loaded component, the applied
    /// traction, force or pressure; on an absorbing part, plus its dashpots' forces −C v. A node
    /// and component held by two parts counts for the last.
    pub fx: f64,
    /// Total force on the part's nodes [N/m] (as `fx`).
    pub fy: f64,
}

/// Damage at one interface Gauss point.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct InterfaceRecord {
    /// Time [s].
    pub t: f64,
    /// Reference x of the Gauss point [m].
    pub x: f64,
    /// Damage d [-] (0 if not inserted).
    pub damage: f64,
    /// Cohesive element inserted.
    pub inserted: bool,
    /// Interface chain the point lies on [-] (0, 1, … as docs/meshes.md orders them); written
    /// only on a mesh with several chains (the coordinate is then each chain's own arc length).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chain: Option<u16>,
}

/// Contact state of one node of the upper face (Γ1 ∪ Γ⁺coh).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct FaceRecord {
    /// Time [s].
    pub t: f64,
    /// Reference x of the node [m].
    pub x: f64,
    /// Penetration p = −g ≥ 0 [m].
    pub penetration: f64,
    /// Normal contact pressure p_N ≥ 0 [Pa].
    pub normal_traction: f64,
    /// Magnitude of the tangential contact traction |T| [Pa].
    pub tangential_traction: f64,
    /// Interface chain the point lies on [-] (0, 1, … as docs/meshes.md orders them); written
    /// only on a mesh with several chains (the coordinate is then each chain's own arc length).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chain: Option<u16>,
}

/// Means over the contacting nodes of the upper face (Figs. 6c, D.15).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct ContactMeanRecord {
    /// Time [s].
    pub t: f64,
    /// T̄ⁿ = Σ A p_N / Σ A [Pa].
    pub mean_normal_traction: f64,
    /// T̄ᵗ = Σ A |T| / Σ A [Pa].
    pub mean_tangential_traction: f64,
    /// Largest penetration on the face [m].
    pub max_penetration: f64,
    /// Contacts lost in the sample's step because the penetration exceeded the detection
    /// distance d_max (`fem.max_gap`), anywhere on Γ_det [-].
    pub dropped_contacts_step: usize,
    /// The same, summed over every step since t = 0 [-].
    pub dropped_contacts_total: u64,
}

/// Energies [J/m] (docs/fem-model.md §8.3), measured from t = 0.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct EnergyRecord {
    /// Time [s].
    pub t: f64,
    /// E_kin = ½ Σ m |v|² [J/m].
    pub kinetic: f64,
    /// E_strain = ½ Σ uᵀ K u [J/m].
    pub strain: f64,
    /// E_coh,tot: work absorbed by the cohesive elements [J/m].
    pub cohesive: f64,
    /// E_coh,diss = E_coh,tot − E_coh,rev [J/m].
    pub cohesive_dissipated: f64,
    /// Friction dissipation [J/m].
    pub friction_dissipated: f64,
    /// Kinetic energy removed by velocity scaling [J/m].
    pub damping_removed: f64,
    /// Work of the contact forces W_con (≤ 0 when dissipative) [J/m].
    pub contact_work: f64,
    /// Energy stored in the contact penalty springs now, Σ w A (½ ε_n p² + T²/(2 ε_t)) over the
    /// slaves in contact [J/m], from the penetrations and tractions (not from the applied forces).
    /// Frictionless contact is conservative: W_con + E_stored = 0 at every sample.
    pub contact_stored: f64,
    /// Work of the boundary forces W_ext [J/m] (loads and supports; not the dashpots).
    pub boundary_work: f64,
    /// E_abs: work taken out by the dashpots of absorbing boundaries (≥ 0) [J/m].
    pub absorbed_work: f64,
    /// Residual W_ext + W_con − (E_kin + E_strain + E_coh,tot + E_damp + E_abs) [J/m].
    pub residual: f64,
}

/// Insertion and failure time of one interface Gauss point.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct ArrivalRecord {
    /// Reference x [m].
    pub x: f64,
    /// Insertion time [s] (NaN: never).
    pub insertion_time: f64,
    /// Time of full failure d = 1 [s] (NaN: never).
    pub failure_time: f64,
    /// Cumulative cohesive work ∫T·dΔ at this point [J/m²] (→ G_c at full failure).
    pub work_density: f64,
    /// Interface chain the point lies on [-] (0, 1, … as docs/meshes.md orders them); written
    /// only on a mesh with several chains (the coordinate is then each chain's own arc length).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chain: Option<u16>,
}

/// Displacement and velocity of a probe node.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct ProbeRecord {
    /// Time [s].
    pub t: f64,
    /// Probe index in `[fem].probes`.
    pub probe: usize,
    /// Reference position of the node [m].
    pub x: f64,
    /// Reference position of the node [m].
    pub y: f64,
    /// Displacement [m].
    pub ux: f64,
    /// Displacement [m].
    pub uy: f64,
    /// Velocity [m/s].
    pub vx: f64,
    /// Velocity [m/s].
    pub vy: f64,
}

/// Residual stress of paper eq. (17) at one sample.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct ResidualStressRecord {
    /// Time [s].
    pub t: f64,
    /// σ̄ = ∫ (σ n)·e_x dA / (x₁ − x₀) over the + facets with midpoint in `residual_stress_x` [Pa].
    pub residual_stress: f64,
}

/// Contact (KKT) conditions on the crack faces of the contact surface at one sample.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct KktRecord {
    /// Time [s].
    pub t: f64,
    /// Crack-face nodes: both copies of the nodes of free (pre-crack or inserted) facets of the
    /// contact surface [-].
    pub crack_face_nodes: usize,
    /// Nodes carrying a compressive traction (contact pressure, or the cohesive law's
    /// compression penalty in the standard model) [-].
    pub compressive_nodes: usize,
    /// Nodes carrying a compressive traction while their true distance to the opposing face is
    /// positive (open) [-].
    pub violating_nodes: usize,
    /// violating_nodes / crack_face_nodes [-] (0 without crack faces).
    pub violating_share: f64,
    /// Largest compressive traction on a violating node [Pa] (0 if none).
    pub max_violating_traction: f64,
    /// Nodes in true contact (distance < 0) without a compressive traction, plus the violating
    /// ones: where the contact zone and the traction zone differ [-].
    pub mismatch_nodes: usize,
    /// Largest tangential slip |(u⁺ − u⁻)·t| of a crack-face twin pair (the two nodes that
    /// faced each other at t = 0) [m].
    pub max_slip: f64,
}

/// Element stresses at a snapshot (averages of the four Gauss points).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct FieldRecord {
    /// Snapshot index in `snapshot_times`.
    pub snapshot: usize,
    /// Time [s].
    pub t: f64,
    /// Reference centroid [m].
    pub x: f64,
    /// Reference centroid [m].
    pub y: f64,
    /// σ_xx [Pa].
    pub sxx: f64,
    /// σ_yy [Pa].
    pub syy: f64,
    /// σ_xy [Pa].
    pub sxy: f64,
}

/// One node of the upper face of the contact surface at a snapshot (paper Figure 11).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct ProfileRecord {
    /// Snapshot index in `snapshot_times`.
    pub snapshot: usize,
    /// Time [s].
    pub t: f64,
    /// Reference position [m].
    pub x: f64,
    /// Reference position [m].
    pub y: f64,
    /// σ_yy at the node, extrapolated from the adjacent upper elements [Pa].
    pub syy: f64,
    /// The node's facet is free (pre-crack or inserted).
    pub crack_face: bool,
    /// True signed distance to the opposing face (> 0 open, < 0 penetrating) [m].
    pub gap: f64,
    /// Compressive traction the node carries [Pa] (≥ 0).
    pub compressive_traction: f64,
}

/// Friction audit of one slave node at the end of the run (`friction.csv`, runs with μ > 0).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct FrictionRecord {
    /// Reference position x [m].
    pub x: f64,
    /// Reference position y [m].
    pub y: f64,
    /// Work done against the friction traction, Σ −w A T Δs over the steps in contact [J/m]:
    /// what friction took out of the sliding at this node (never negative for a dissipative law).
    pub friction_work: f64,
    /// Its Coulomb bound Σ w A μ p_N |Δs| over the slipping steps [J/m].
    pub coulomb_work: f64,
}

/// What a run was: its step, its modelling choices and its energy bill (`run.csv`, one row).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RunRecord {
    /// Time step [s].
    pub time_step: f64,
    /// Steps done [-].
    pub steps: u64,
    /// `hybrid` or `standard`.
    pub model: String,
    /// The Westergaard boundary field had the lateral-contraction term.
    pub lateral_contraction: bool,
    /// The boundary field had the mode-II part of u_y that paper eq. (C.9) drops.
    pub mode_ii_uy: bool,
    /// The damping choice, in words.
    pub damping: String,
    /// Fracture energy: the cohesive dissipation at the end of the run [J/m].
    pub fracture_energy: f64,
    /// Energy the damping removed [J/m].
    pub damping_removed: f64,
    /// damping_removed / fracture_energy [-]; `None` (an empty field in run.csv) without
    /// fracture, where the share has no meaning.
    pub damping_share: Option<f64>,
    /// Contacts lost over the run because a penetration exceeded the detection distance
    /// (`fem.max_gap`) [-]; anything but 0 deserves a larger `max_gap` or a stiffer penalty.
    pub dropped_contacts: u64,
    /// How the run ended: `finished` (it reached T), `interrupted`, `unstable` or
    /// `output_failed`; every file of a run that did not finish ends at `last_step`.
    pub status: preflight::Status,
    /// Last step computed [-].
    pub last_step: u64,
}

/// Everything a run produces. A checkpoint holds it (`solver::checkpoint`), the wall times
/// aside.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct RunOutput {
    /// Time step [s].
    pub time_step: f64,
    /// Steps done.
    pub steps: u64,
    /// How the run ended (set when it ends; `interrupted` until then).
    pub status: preflight::Status,
    /// Bulk elements of the mesh.
    pub elements: usize,
    /// `hybrid` or `standard`.
    pub model: String,
    /// Whether the Westergaard field had the lateral-contraction term.
    pub lateral_contraction: bool,
    /// Whether the boundary field had the mode-II part of u_y.
    pub mode_ii_uy: bool,
    /// The damping choice, in words.
    pub damping: String,
    /// Tip history (only with a pre-crack, `[crack]`).
    pub tips: Vec<TipRecord>,
    /// Cracked extent per interface chain per sample (with an interface).
    pub cracks: Vec<CrackRecord>,
    /// Every crack and process zone of every chain per sample, with its tips (with an interface).
    pub crack_tips: Vec<CrackTipRecord>,
    /// Damage per interface Gauss point per sample.
    #[serde(with = "all_fields")]
    pub interface: Vec<InterfaceRecord>,
    /// Upper-face contact state per node per sample.
    #[serde(with = "all_fields")]
    pub faces: Vec<FaceRecord>,
    /// Mean contact tractions per sample.
    pub contact: Vec<ContactMeanRecord>,
    /// Energies per sample.
    pub energy: Vec<EnergyRecord>,
    /// Insertion/failure times per interface Gauss point (at the end of the run).
    #[serde(with = "all_fields")]
    pub arrivals: Vec<ArrivalRecord>,
    /// Friction audit per slave node that ever carried friction (at the end of the run).
    pub friction: Vec<FrictionRecord>,
    /// Probe histories.
    pub probes: Vec<ProbeRecord>,
    /// Names of the parts of `[fem.boundary]`, in the order they apply (empty with the
    /// Westergaard field).
    pub boundary_parts: Vec<String>,
    /// Displacement and force per part of `[fem.boundary]` per sample.
    pub boundary: Vec<BoundaryRecord>,
    /// Residual stress of eq. (17) per sample (only with `residual_stress_x`).
    pub residual_stress: Vec<ResidualStressRecord>,
    /// KKT conditions per sample (only with `kkt_metric`).
    pub kkt: Vec<KktRecord>,
    /// Element stresses at the snapshots (only with `snapshot_times`).
    pub fields: Vec<FieldRecord>,
    /// Upper-face profiles at the snapshots (only with `snapshot_times`).
    pub profiles: Vec<ProfileRecord>,
    /// Times at which the snapshots were taken [s] (first sample at or after each requested time).
    pub snapshot_times: Vec<f64>,
    /// Wall time per phase of the step and the loop (profiling; differs between runs, so it is
    /// printed, never written, and not checkpointed).
    #[serde(skip)]
    pub profile: Vec<crate::profile::PhaseTime>,
    /// Step of the checkpoint this run resumed from; 0 for a run from t = 0 (never written: the
    /// records of a resumed run are those of a run that never stopped).
    #[serde(skip)]
    pub resumed_from: u64,
}

/// The checkpoint form of the records whose `chain` their CSV file leaves out when it is `None`
/// (`skip_serializing_if`): a checkpoint's form (postcard) has no field names, so it needs every
/// field, and these records go into it as tuples of all their fields, in order.
mod all_fields {
    use serde::de::DeserializeOwned;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// A record as the tuple of all its fields.
    pub(super) trait AsTuple: Sized {
        type Tuple: Serialize + DeserializeOwned;
        fn to_tuple(&self) -> Self::Tuple;
        fn from_tuple(t: Self::Tuple) -> Self;
    }

    pub(super) fn serialize<S: Serializer, R: AsTuple>(records: &[R], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(records.iter().map(AsTuple::to_tuple))
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>, R: AsTuple>(d: D) -> Result<Vec<R>, D::Error> {
        Ok(Vec::<R::Tuple>::deserialize(d)?
            .into_iter()
            .map(R::from_tuple)
            .collect())
    }
}

impl all_fields::AsTuple for InterfaceRecord {
    type Tuple = (f64, f64, f64, bool, Option<u16>);
    fn to_tuple(&self) -> Self::Tuple {
        let InterfaceRecord {
            t,
            x,
            damage,
            inserted,
            chain,
        } = *self;
        (t, x, damage, inserted, chain)
    }
    fn from_tuple((t, x, damage, inserted, chain): Self::Tuple) -> Self {
        InterfaceRecord {
            t,
            x,
            damage,
            inserted,
            chain,
        }
    }
}

impl all_fields::AsTuple for FaceRecord {
    type Tuple = (f64, f64, f64, f64, f64, Option<u16>);
    fn to_tuple(&self) -> Self::Tuple {
        let FaceRecord {
            t,
            x,
            penetration,
            normal_traction,
            tangential_traction,
            chain,
        } = *self;
        (t, x, penetration, normal_traction, tangential_traction, chain)
    }
    fn from_tuple((t, x, penetration, normal_traction, tangential_traction, chain): Self::Tuple) -> Self {
        FaceRecord {
            t,
            x,
            penetration,
            normal_traction,
            tangential_traction,
            chain,
        }
    }
}

impl all_fields::AsTuple for ArrivalRecord {
    type Tuple = (f64, f64, f64, f64, Option<u16>);
    fn to_tuple(&self) -> Self::Tuple {
        let ArrivalRecord {
            x,
            insertion_time,
            failure_time,
            work_density,
            chain,
        } = *self;
        (x, insertion_time, failure_time, work_density, chain)
    }
    fn from_tuple((x, insertion_time, failure_time, work_density, chain): Self::Tuple) -> Self {
        ArrivalRecord {
            x,
            insertion_time,
            failure_time,
            work_density,
            chain,
        }
    }
}

impl RunOutput {
    /// The contact audit of frictionless contact: max over samples of |W_con + E_stored| over the
    /// largest stored penalty energy [-] (0 without contact). Conservative contact keeps it at the
    /// time-integration error; a contact force that creates or loses energy does not.
    pub fn contact_conservation_error(&self) -> f64 {
        let scale = self.energy.iter().map(|e| e.contact_stored).fold(0.0, f64::max);
        if scale <= 0.0 {
            return 0.0;
        }
        self.energy
            .iter()
            .map(|e| (e.contact_work + e.contact_stored).abs())
            .fold(0.0, f64::max)
            / scale
    }

    /// The run's record: its choices and, from the last energy sample, its damping bill.
    pub fn record(&self) -> RunRecord {
        let last = self.energy.last().copied().unwrap_or_default();
        let fracture = last.cohesive_dissipated;
        RunRecord {
            time_step: self.time_step,
            steps: self.steps,
            model: self.model.clone(),
            lateral_contraction: self.lateral_contraction,
            mode_ii_uy: self.mode_ii_uy,
            damping: self.damping.clone(),
            fracture_energy: fracture,
            damping_removed: last.damping_removed,
            damping_share: (fracture > 0.0).then(|| last.damping_removed / fracture),
            dropped_contacts: self.contact.last().map_or(0, |c| c.dropped_contacts_total),
            status: self.status,
            last_step: self.steps,
        }
    }
}
