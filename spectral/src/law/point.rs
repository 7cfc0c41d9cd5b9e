//! The whole interface law of one grid point for one step (docs/spectral-model.md §5.4): strengths
//! from the current jumps (§5.1) → normal solve (§5.2 a–c) → Prakash update of σ̃ (§5.3, paper
//! eq. 14) → shear solve with the strength the friction rule gives (§5.2 d, §5.5). Pure: (law,
//! drive, old point) → new point.

use super::cohesive::{self, CohesiveParams, Strength};
use super::contact::{self, NormalBranch, NormalInput};
use super::friction;
use super::{Impedances, PointState};

/// Where Coulomb friction acts (`[friction] contact_friction`, the FE model's key and meaning;
/// docs/spectral-model.md §5.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactFriction {
    /// On every closed point that has begun to weaken, on top of its cohesive shear strength:
    /// τ = τ_s + μ|σ̃| (paper §2.3, Fig. 4d; default). Broken points in contact get μ|σ̃| alone,
    /// as with `FailedOnly`.
    AllFaces,
    /// Only on broken points in contact: τ = μ|σ̃| (paper §3.2).
    FailedOnly,
}

/// What the law of a point needs besides its state. SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointLaw {
    /// Cohesive law parameters.
    pub cohesive: CohesiveParams,
    /// Shear impedances Z^± = μ^±/c_s^± of the two faces [Pa s/m].
    pub z_shear: Impedances,
    /// Normal impedances Z_n^± = η^± μ^±/c_s^± of the two faces [Pa s/m].
    pub z_normal: Impedances,
    /// Time step Δt [s].
    pub dt: f64,
    /// Coulomb coefficient μ [-].
    pub friction_coeff: f64,
    /// r = Δt/t* [-] of the Prakash update; `None` (t* = 0): plain Coulomb, σ̃ = σ.
    pub relax: Option<f64>,
    /// Contact (no interpenetration) on broken points.
    pub contact: bool,
    /// Where friction acts.
    pub rule: ContactFriction,
}

/// The loads on a point at this step: each face's dynamic stress S^± = T^0 + f^± [Pa] and the
/// current jumps [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// (S^+_1, S^-_1): shear dynamic stresses of the top and bottom faces [Pa].
    pub shear: (f64, f64),
    /// (S^+_2, S^-_2): normal dynamic stresses of the top and bottom faces [Pa].
    pub normal: (f64, f64),
    /// Opening δ_n = u^+_2 − u^-_2 [m].
    pub opening: f64,
    /// Slip δ_t = u^+_1 − u^-_1 [m].
    pub slip: f64,
}

/// The loads of a run of consecutive grid points as the solver holds them, point for point in
/// each slice: the law builds each point's [`Drive`] from them (S^± = T^0 + T^nuc + f^± for the
/// shear, S^± = T^0 + f^± for the normal, the jumps from the face displacements).
#[derive(Debug, Clone, Copy)]
pub struct Drives<'a> {
    /// Far-field (shear, normal) stresses (T^0_1, T^0_2) at this step [Pa].
    pub load: (f64, f64),
    /// Nucleation shear stress added to T^0_1 at each point [Pa].
    pub nucleation: &'a [f64],
    /// Dynamic stress f^+_1 of the top face [Pa].
    pub f_top_x: &'a [f64],
    /// Dynamic stress f^-_1 of the bottom face [Pa].
    pub f_bottom_x: &'a [f64],
    /// Dynamic stress f^+_2 of the top face [Pa].
    pub f_top_y: &'a [f64],
    /// Dynamic stress f^-_2 of the bottom face [Pa].
    pub f_bottom_y: &'a [f64],
    /// Displacement u^+_1 of the top face [m].
    pub u_top_x: &'a [f64],
    /// Displacement u^-_1 of the bottom face [m].
    pub u_bottom_x: &'a [f64],
    /// Displacement u^+_2 of the top face [m].
    pub u_top_y: &'a [f64],
    /// Displacement u^-_2 of the bottom face [m].
    pub u_bottom_y: &'a [f64],
}

impl Drives<'_> {
    /// The lengths of the nine slices.
    pub fn lengths(&self) -> [usize; 9] {
        [
            self.nucleation.len(),
            self.f_top_x.len(),
            self.f_bottom_x.len(),
            self.f_top_y.len(),
            self.f_bottom_y.len(),
            self.u_top_x.len(),
            self.u_bottom_x.len(),
            self.u_top_y.len(),
            self.u_bottom_y.len(),
        ]
    }
}

/// Per-point interface state and the results of its last step.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Point {
    /// Strengths and state.
    pub strength: Strength,
    /// Regularised normal stress σ̃ [Pa] (≤ 0).
    pub reg_normal: f64,
    /// Broken and in contact this step (normal branch `Contact`).
    pub in_contact: bool,
    /// Slipping this step.
    pub slipping: bool,
    /// Friction adds to the shear strength this step [-].
    pub friction_on: bool,
    /// (T_1, T_2) [Pa].
    pub traction: [f64; 2],
    /// Face velocities (top x, top y, bottom x, bottom y) [m/s].
    pub v: [f64; 4],
}

impl Point {
    /// A point at rest with the given strength.
    pub fn at_rest(strength: Strength) -> Point {
        Point {
            strength,
            reg_normal: 0.0,
            in_contact: false,
            slipping: false,
            friction_on: false,
            traction: [0.0; 2],
            v: [0.0; 4],
        }
    }
}

/// One step of the law at one point.
///
/// `FailedOnly`: σ̃ relaxes towards T_2 where the point is broken and in contact and towards 0
/// elsewhere; the shear strength is μ|σ̃| in contact, τ_s otherwise.
///
/// `AllFaces`: a point is *closed* when its faces carry compression (T_2 < 0: the stick branch
/// under compression, or contact). σ̃ relaxes towards T_2 on every closed point and towards 0 on
/// open ones, so that it follows the interface's normal stress history whatever the damage.
/// On a closed point that has begun to weaken (not intact), the shear strength is τ_s + μ|σ̃|;
/// on an open or intact one, τ_s.
///
/// Inlined into the solver's per-point loop: called, it returns the point through memory with
/// field-sized stores that the caller reads back wider, a store-forwarding stall per point.
#[inline(always)]
pub fn step(law: &PointLaw, d: &Drive, old: &Point) -> Point {
    let mut s = cohesive::update(&law.cohesive, d.opening, d.slip, old.strength);
    let normal = contact::solve(&NormalInput {
        s_top: d.normal.0,
        s_bottom: d.normal.1,
        strength: s.sigma,
        opening: d.opening,
        impedance: law.z_normal,
        dt: law.dt,
        contact: law.contact,
    });
    let in_contact = normal.branch == NormalBranch::Contact;
    let (closed, friction_on) = match law.rule {
        ContactFriction::FailedOnly => (in_contact, in_contact),
        ContactFriction::AllFaces => {
            let closed = in_contact || (normal.branch == NormalBranch::Stuck && normal.traction < 0.0);
            (closed, closed && s.state != PointState::Intact)
        }
    };
    // eq. (14) at every step: towards the compressive traction where closed, towards 0 apart
    let sigma = if closed { normal.traction } else { 0.0 };
    let reg_normal = friction::regularized_normal(old.reg_normal, sigma, law.relax);
    let friction = law.friction_coeff * reg_normal.abs();
    if in_contact {
        s.state = PointState::Contact;
    }
    // superposed on what is left of the cohesive shear strength (τ_s = 0 once broken)
    let tau = if friction_on { s.tau + friction } else { s.tau };
    let shear = friction::solve_shear(d.shear.0, d.shear.1, tau, law.z_shear);
    Point {
        strength: s,
        reg_normal,
        in_contact,
        slipping: shear.slipping,
        friction_on,
        traction: [shear.traction, normal.traction],
        v: [shear.v_top, normal.v_top, shear.v_bottom, normal.v_bottom],
    }
}

#[cfg(test)]
#[path = "point_tests.rs"]
mod tests;
