//! The explicit time loop on an unstructured T3/Q4 mesh, bulk only: lumped masses, the internal
//! forces of [`UnstructuredBulk`], displacement boundary conditions on named physical groups, and
//! probes. No cohesive elements, no contact, no scene (docs/meshes.md, "Running a bulk-only
//! unstructured mesh").
//!
//! The integrator is the explicit central-difference scheme in its velocity form (Belytschko,
//! Liu & Moran, *Nonlinear Finite Elements for Continua and Structures*, 2000, §6.2.1), the same as
//! the structured solver's ([`crate::solver::central_difference`]):
//!
//! - u_{n+1} = u_n + Δt v_n + ½Δt² a_n, and v* = v_n + ½Δt a_n;
//! - prescribed components: u_{n+1} = ū(t_{n+1}), v_{n+1} = ū'(t_{n+1}), a_{n+1} = 0;
//! - a_{n+1} = (f_int(u_{n+1}) + f_ext)/m with the lumped masses m (f_ext = 0: no loads yet);
//! - v_{n+1} = v* + ½Δt a_{n+1}.
//!
//! The step is Δt = α h_min/c_d ([`UnstructuredBulk::stable_time_step`]) with 0 < α ≤ 1.
//!
//! Boundary conditions ([`GroupBc`]) act on every node of a named physical group (normally a
//! curve). A group sets each of the two components to a prescribed motion ([`Prescribed`]: zero,
//! i.e. a roller on that component, the smooth ramp [`Ramp`], or a closure) or leaves it free.
//! Groups are applied in the order given: on a node of several groups, each component takes the
//! motion of the last group that prescribes it, so a corner of "left" (u_x ramp) and "top"
//! (u_y = 0) gets both.
//!
//! Nothing allocates inside the time loop: [`UnstructuredDriver::run_until`] reserves the probe
//! records it will write before stepping. The result does not depend on the number of threads
//! (the kernel's sums have a fixed order; the node loops here are serial).

use crate::gmsh::{MeshError, UnstructuredMesh};
use crate::law::elastic::PlaneStrain;
use crate::mesh::gmsh::first_surface;
use crate::mesh::nearest_node;
use crate::model::bulk;
use crate::model::reduce::ordered_sum;
use crate::model::unstructured::{BulkMaterial, UnstructuredBulk, UnstructuredError};
use crate::output::ProbeRecord;
use crate::scene::Ramp;
use nalgebra::Vector2;
use std::fmt;
use std::sync::Arc;
use thiserror::Error;

/// A driver that cannot be built, or a run that went wrong.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DriverError {
    /// A boundary condition names a physical group the mesh does not have.
    #[error("boundary condition: {0}")]
    BoundaryGroup(MeshError),
    /// The bulk kernel refused the mesh or the density.
    #[error(transparent)]
    Kernel(#[from] UnstructuredError),
    /// A surface material names a physical group the mesh does not have, or one that is not a
    /// surface.
    #[error("surface material: {0}")]
    MaterialGroup(MeshError),
    /// An element lies in two listed surfaces that give it different materials.
    #[error(
        "element {element} lies in the surfaces \"{first}\" and \"{second}\", which give it different materials"
    )]
    MaterialOverlap {
        /// Element tag in the mesh file.
        element: u64,
        /// The first listed surface that holds it.
        first: String,
        /// The later listed surface that disagrees.
        second: String,
    },
    /// More than 255 surface materials.
    #[error("at most 255 surface materials (got {0})")]
    TooManyMaterials(usize),
    /// A time-step safety factor outside (0, 1].
    #[error("alpha = {0} must be in (0, 1] (Δt = α h_min/c_d)")]
    BadAlpha(f64),
    /// A probe interval of zero steps.
    #[error("the probe interval must be at least one step")]
    ZeroProbeInterval,
    /// A mesh without nodes.
    #[error("the mesh has no nodes")]
    EmptyMesh,
    /// A displacement or velocity became NaN or infinite.
    #[error("the solution became non-finite at t = {t} s")]
    NonFinite {
        /// Time of the step where it was found [s].
        t: f64,
    },
}

/// A displacement component of the plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// u_x.
    X,
    /// u_y.
    Y,
}

impl Axis {
    fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
        }
    }
}

/// The motion imposed on one displacement component of a group's nodes.
#[derive(Clone)]
pub enum Prescribed {
    /// ū = 0 at all times: a roller (the other component may stay free) or, on both, a clamp.
    Zero,
    /// ū(t) = [`Ramp::value`] [m], the quintic smoothstep S(s) = s³(10 − 15s + 6s²) between the
    /// ramp's initial and final values; velocity [`Ramp::rate`] [m/s].
    Ramp(Ramp),
    /// ū(t) from a closure of the time t [s] returning the array (displacement [m], velocity [m/s]).
    Function(Arc<dyn Fn(f64) -> [f64; 2] + Send + Sync>),
}

impl Prescribed {
    /// [ū(t) [m], ū'(t) [m/s]].
    fn at(&self, t: f64) -> [f64; 2] {
        match self {
            Prescribed::Zero => [0.0, 0.0],
            Prescribed::Ramp(r) => [r.value(t), r.rate(t)],
            Prescribed::Function(f) => f(t),
        }
    }
}

impl fmt::Debug for Prescribed {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Prescribed::Zero => write!(f, "Zero"),
            Prescribed::Ramp(r) => f.debug_tuple("Ramp").field(r).finish(),
            Prescribed::Function(_) => write!(f, "Function(..)"),
        }
    }
}

/// The boundary condition of one named physical group: per component, a prescribed motion or
/// free (`None`).
#[derive(Debug, Clone)]
pub struct GroupBc {
    /// Name of the physical group (its nodes, whatever its dimension).
    pub group: String,
    /// [u_x, u_y]: the prescribed motion, or `None` for free.
    pub components: [Option<Prescribed>; 2],
}

impl GroupBc {
    /// Both components free (a traction-free boundary; the same as naming no condition, but the
    /// group name is still checked).
    pub fn free(group: &str) -> Self {
        Self {
            group: group.to_string(),
            components: [None, None],
        }
    }

    /// A roller: `axis` fixed to 0, the other component free.
    pub fn roller(group: &str, axis: Axis) -> Self {
        Self::free(group).with(axis, Prescribed::Zero)
    }

    /// `axis` follows `motion`, the other component free.
    pub fn prescribed(group: &str, axis: Axis, motion: Prescribed) -> Self {
        Self::free(group).with(axis, motion)
    }

    /// The same condition with `axis` following `motion` as well.
    pub fn with(mut self, axis: Axis, motion: Prescribed) -> Self {
        self.components[axis.index()] = Some(motion);
        self
    }
}

/// The material of the elements of one physical surface ([`UnstructuredDriver::with_materials`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceMaterial {
    /// Name of the physical surface (dimension 2).
    pub group: String,
    /// Its plane-strain material (E [Pa], ν [-], ρ [kg/m³]).
    pub material: PlaneStrain,
}

/// Time step and probes of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct DriverOptions {
    /// Safety factor α ∈ (0, 1] of Δt = α h_min/c_d [-].
    pub alpha: f64,
    /// Probe points [m]: each records the node nearest to it (the smallest index on a tie).
    pub probes: Vec<Vector2<f64>>,
    /// Record the probes every this many steps (and at t = 0) [steps].
    pub probe_every: usize,
}

impl Default for DriverOptions {
    fn default() -> Self {
        Self {
            alpha: 0.5,
            probes: Vec::new(),
            probe_every: 1,
        }
    }
}

/// The kernel's material table (`material` first, then each surface's) and each element's index
/// into it (empty without `surfaces`: every element of `material`).
fn element_materials(
    mesh: &UnstructuredMesh,
    material: &PlaneStrain,
    surfaces: &[SurfaceMaterial],
) -> Result<(Vec<BulkMaterial>, Vec<u8>), DriverError> {
    if surfaces.len() > 255 {
        return Err(DriverError::TooManyMaterials(surfaces.len()));
    }
    let bulk = |m: &PlaneStrain| BulkMaterial {
        d: m.d_matrix(),
        density: m.density,
    };
    let mut table = vec![bulk(material)];
    table.extend(surfaces.iter().map(|s| bulk(&s.material)));
    if surfaces.is_empty() {
        return Ok((table, Vec::new()));
    }
    // each element's material from the first listed surface that holds it (k + 1 for the k-th)
    let mut groups = Vec::with_capacity(surfaces.len());
    for s in surfaces {
        let group = mesh
            .group_of_dim(
                &s.group,
                2,
                "a material's group is a physical surface (dimension 2)",
            )
            .map_err(DriverError::MaterialGroup)?;
        groups.push(&group.elements[..]);
    }
    let from = first_surface(mesh.elements.len(), groups, |a, b| {
        surfaces[a].material == surfaces[b].material
    })
    .map_err(|(e, first, second)| DriverError::MaterialOverlap {
        element: mesh.elements[e].tag,
        first: surfaces[first].group.clone(),
        second: surfaces[second].group.clone(),
    })?;
    Ok((table, from.iter().map(|s| s.map_or(0, |k| k as u8 + 1)).collect()))
}

/// One prescribed degree of freedom.
#[derive(Debug, Clone, Copy)]
struct PrescribedDof {
    node: u32,
    dof: u8,
    /// Index into `UnstructuredDriver::motions`.
    motion: u32,
}

/// The bulk-only explicit run on an unstructured mesh: the state (u, v, a at time t) and what
/// advances it.
#[derive(Debug, Clone)]
pub struct UnstructuredDriver {
    bulk: UnstructuredBulk,
    /// Reference node positions [m].
    positions: Vec<Vector2<f64>>,
    /// 1/m per node [m/kg].
    inv_mass: Vec<f64>,
    /// Time step Δt [s].
    dt: f64,
    /// Current time [s].
    t: f64,
    /// Steps taken.
    steps: u64,
    /// Displacements [m].
    u: Vec<Vector2<f64>>,
    /// Velocities [m/s].
    v: Vec<Vector2<f64>>,
    /// Accelerations [m/s²].
    a: Vec<Vector2<f64>>,
    /// −K u at the current u [N/m] (the internal forces; no external forces yet).
    f: Vec<Vector2<f64>>,
    /// One motion per (group, component) that prescribes one.
    motions: Vec<Prescribed>,
    /// [ū [m], ū' [m/s]] of each motion at the time being stepped to.
    motion_values: Vec<[f64; 2]>,
    /// Prescribed DOFs, by node then component.
    prescribed: Vec<PrescribedDof>,
    /// Probe nodes.
    probe_nodes: Vec<usize>,
    probe_every: u64,
    records: Vec<ProbeRecord>,
}

impl UnstructuredDriver {
    /// Builds the bulk of `mesh` with `material` (plane strain, thickness 1 m), checks the
    /// boundary groups, and sets the state at t = 0: u and v zero except on the prescribed
    /// components, which take ū(0) and ū'(0).
    pub fn new(
        mesh: &UnstructuredMesh,
        material: &PlaneStrain,
        bcs: &[GroupBc],
        options: &DriverOptions,
    ) -> Result<Self, DriverError> {
        Self::with_materials(mesh, material, &[], bcs, options)
    }

    /// As [`Self::new`], with the elements of each physical surface of `surfaces` of that
    /// surface's material and every other element of `material`. Masses and forces then use each
    /// element's own material, and the step is Δt = α min_e h_e/c_d,e, each element with its own
    /// length and its own material's P-wave speed ([`UnstructuredBulk::min_transit_time`]). An
    /// element in two listed surfaces must get the same material from both.
    pub fn with_materials(
        mesh: &UnstructuredMesh,
        material: &PlaneStrain,
        surfaces: &[SurfaceMaterial],
        bcs: &[GroupBc],
        options: &DriverOptions,
    ) -> Result<Self, DriverError> {
        if !(options.alpha > 0.0 && options.alpha <= 1.0) {
            return Err(DriverError::BadAlpha(options.alpha));
        }
        if options.probe_every == 0 {
            return Err(DriverError::ZeroProbeInterval);
        }
        if mesh.positions.is_empty() {
            return Err(DriverError::EmptyMesh);
        }
        let (table, element_material) = element_materials(mesh, material, surfaces)?;
        let bulk = UnstructuredBulk::with_materials(mesh, &table, &element_material)?;
        let nn = bulk.num_nodes();

        // per node and component, the last group's motion
        let mut motions = Vec::new();
        let mut slot: Vec<[Option<u32>; 2]> = vec![[None, None]; nn];
        for bc in bcs {
            let group = mesh.group(&bc.group).map_err(DriverError::BoundaryGroup)?;
            for (d, c) in bc.components.iter().enumerate() {
                let Some(motion) = c else { continue };
                motions.push(motion.clone());
                let k = (motions.len() - 1) as u32;
                for &n in &group.nodes {
                    slot[n][d] = Some(k);
                }
            }
        }
        let prescribed: Vec<PrescribedDof> = slot
            .iter()
            .enumerate()
            .flat_map(|(n, s)| {
                (0..2).filter_map(move |d| {
                    s[d].map(|motion| PrescribedDof {
                        node: n as u32,
                        dof: d as u8,
                        motion,
                    })
                })
            })
            .collect();

        let probe_nodes = options
            .probes
            .iter()
            .map(|p| nearest_node(&mesh.positions, *p))
            .collect();
        let dt = if surfaces.is_empty() {
            bulk.stable_time_step(options.alpha, material.wave_speeds().cd)
        } else {
            options.alpha * bulk.min_transit_time()
        };
        let mut driver = Self {
            dt,
            inv_mass: bulk.masses().iter().map(|m| 1.0 / m).collect(),
            bulk,
            positions: mesh.positions.clone(),
            t: 0.0,
            steps: 0,
            u: vec![Vector2::zeros(); nn],
            v: vec![Vector2::zeros(); nn],
            a: vec![Vector2::zeros(); nn],
            f: vec![Vector2::zeros(); nn],
            motion_values: vec![[0.0; 2]; motions.len()],
            motions,
            prescribed,
            probe_nodes,
            probe_every: options.probe_every as u64,
            records: Vec::new(),
        };
        driver.set_initial(|_| (Vector2::zeros(), Vector2::zeros()));
        Ok(driver)
    }

    /// Sets the state at the current time: `field(x)` gives (u [m], v [m/s]) at the reference
    /// position x [m] of each node; the prescribed components then take their imposed motion, and
    /// the accelerations follow from the forces (a = f/m, 0 on prescribed components).
    pub fn set_initial(&mut self, field: impl Fn(Vector2<f64>) -> (Vector2<f64>, Vector2<f64>)) {
        for (n, x) in self.positions.iter().enumerate() {
            (self.u[n], self.v[n]) = field(*x);
        }
        self.evaluate_motions(self.t);
        self.impose();
        self.bulk.internal_forces(&self.u, &mut self.f);
        for ((a, f), im) in self.a.iter_mut().zip(&self.f).zip(&self.inv_mass) {
            *a = f * *im;
        }
        self.release_prescribed_accelerations();
    }

    /// Advances the state by one step Δt. Allocates nothing when called on a rayon pool thread
    /// (as [`Self::run_until`] does) and the probe records have room ([`Self::reserve_steps`]).
    pub fn step(&mut self) {
        if self.steps == 0 {
            self.record();
        }
        let dt = self.dt;
        let t1 = self.t + dt;
        // predictor: u_{n+1}, v* = v_n + ½Δt a_n
        for ((u, v), a) in self.u.iter_mut().zip(self.v.iter_mut()).zip(&self.a) {
            *u += dt * *v + 0.5 * dt * dt * a;
            *v += 0.5 * dt * a;
        }
        self.evaluate_motions(t1);
        self.impose();
        self.bulk.internal_forces(&self.u, &mut self.f);
        // corrector: a_{n+1} = f/m, v_{n+1} = v* + ½Δt a_{n+1}
        for (((a, v), f), im) in self
            .a
            .iter_mut()
            .zip(self.v.iter_mut())
            .zip(&self.f)
            .zip(&self.inv_mass)
        {
            *a = f * *im;
            *v += 0.5 * dt * *a;
        }
        // prescribed components keep their imposed velocity and zero acceleration
        for p in &self.prescribed {
            let (n, d) = (p.node as usize, p.dof as usize);
            self.v[n][d] = self.motion_values[p.motion as usize][1];
            self.a[n][d] = 0.0;
        }
        self.t = t1;
        self.steps += 1;
        if self.steps.is_multiple_of(self.probe_every) {
            self.record();
        }
    }

    /// Steps until the time reaches `t_end` [s] (the last step may pass it by less than Δt), after
    /// reserving the probe records of those steps: the loop itself allocates nothing. Fails if the
    /// displacements or velocities end non-finite.
    pub fn run_until(&mut self, t_end: f64) -> Result<(), DriverError> {
        let remaining = ((t_end - self.t) / self.dt - 1e-9).ceil().max(0.0) as u64;
        self.reserve_steps(remaining);
        // The steps run inside a rayon scope, i.e. on a pool thread: the kernel's parallel loop
        // then uses the worker's own deque instead of injecting jobs from outside (which
        // allocates), as in `fem::run`.
        rayon::scope(|_| {
            for _ in 0..remaining {
                self.step();
            }
        });
        let finite = self
            .u
            .iter()
            .chain(&self.v)
            .all(|w| w.x.is_finite() && w.y.is_finite());
        if finite {
            Ok(())
        } else {
            Err(DriverError::NonFinite { t: self.t })
        }
    }

    /// Reserves the probe records of `steps` more steps (and of t = 0 if no step was taken).
    pub fn reserve_steps(&mut self, steps: u64) {
        let samples = (self.steps + steps) / self.probe_every - self.steps / self.probe_every
            + u64::from(self.steps == 0);
        self.records.reserve(samples as usize * self.probe_nodes.len());
    }

    /// Time step Δt [s].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Current time t [s].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The bulk kernel.
    pub fn bulk(&self) -> &UnstructuredBulk {
        &self.bulk
    }

    /// Displacements at the current time [m].
    pub fn displacements(&self) -> &[Vector2<f64>] {
        &self.u
    }

    /// Velocities at the current time [m/s].
    pub fn velocities(&self) -> &[Vector2<f64>] {
        &self.v
    }

    /// Internal forces −K u at the current displacements [N/m].
    pub fn internal_forces(&self) -> &[Vector2<f64>] {
        &self.f
    }

    /// The probes' nodes (indices into the mesh's nodes), in the order of
    /// [`DriverOptions::probes`].
    pub fn probe_nodes(&self) -> &[usize] {
        &self.probe_nodes
    }

    /// Probe records so far, in time order, the probes of one time in order ([`ProbeRecord::probe`]
    /// is the index into [`DriverOptions::probes`], x, y the node's reference position).
    pub fn records(&self) -> &[ProbeRecord] {
        &self.records
    }

    /// Kinetic energy ½ Σ m |v|² [J/m] (a sum in a fixed order, as the structured solver's).
    pub fn kinetic_energy(&self) -> f64 {
        let m = self.bulk.masses();
        0.5 * ordered_sum(self.v.len(), |i| m[i] * self.v[i].norm_squared())
    }

    /// Strain energy ½ uᵀ K u = −½ Σ u·f [J/m].
    pub fn strain_energy(&self) -> f64 {
        bulk::strain_energy(&self.u, &self.f)
    }

    fn evaluate_motions(&mut self, t: f64) {
        for (value, motion) in self.motion_values.iter_mut().zip(&self.motions) {
            *value = motion.at(t);
        }
    }

    /// Prescribed components take ū and ū' of `motion_values`.
    fn impose(&mut self) {
        for p in &self.prescribed {
            let (n, d) = (p.node as usize, p.dof as usize);
            let [ubar, vbar] = self.motion_values[p.motion as usize];
            self.u[n][d] = ubar;
            self.v[n][d] = vbar;
        }
    }

    fn release_prescribed_accelerations(&mut self) {
        for p in &self.prescribed {
            self.a[p.node as usize][p.dof as usize] = 0.0;
        }
    }

    fn record(&mut self) {
        for (probe, &n) in self.probe_nodes.iter().enumerate() {
            self.records.push(ProbeRecord {
                t: self.t,
                probe,
                x: self.positions[n].x,
                y: self.positions[n].y,
                ux: self.u[n].x,
                uy: self.u[n].y,
                vx: self.v[n].x,
                vy: self.v[n].y,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's material (E = 70 MPa, ν = 0.35, ρ = 1230 kg/m³).
    fn material() -> PlaneStrain {
        PlaneStrain::new(70e6, 0.35, 1230.0)
    }

    /// The committed 2 m × 1 m T3 mesh (h = 0.125 m) with groups left, right, top, bottom.
    fn rect_tri() -> UnstructuredMesh {
        let path = format!("{}/../meshes/rect_tri.msh", env!("CARGO_MANIFEST_DIR"));
        UnstructuredMesh::read(std::path::Path::new(&path)).unwrap()
    }

    fn ramp(final_value: f64, ramp_end: f64) -> Prescribed {
        Prescribed::Ramp(Ramp {
            initial: 0.0,
            final_value,
            ramp_start: 0.0,
            ramp_end,
        })
    }

    #[test]
    fn rigid_translation_moves_uniformly_without_force() {
        let mesh = rect_tri();
        let w = Vector2::new(1e-3, -2e-3); // m/s
        let motion = |d: usize| Prescribed::Function(Arc::new(move |t: f64| [w[d] * t, w[d]]));
        let bcs: Vec<GroupBc> = ["left", "right", "top", "bottom"]
            .iter()
            .map(|g| GroupBc::prescribed(g, Axis::X, motion(0)).with(Axis::Y, motion(1)))
            .collect();
        let mut drv = UnstructuredDriver::new(&mesh, &material(), &bcs, &DriverOptions::default()).unwrap();
        drv.set_initial(|_| (Vector2::zeros(), w));
        drv.run_until(200.0 * drv.dt()).unwrap();
        assert_eq!(drv.steps(), 200);
        let t = drv.time();
        let k_scale = 70e6 * (w * t).norm(); // |K u| of one element's worth of stiffness [N/m]
        for n in 0..drv.bulk().num_nodes() {
            let (u, v, f) = (
                drv.displacements()[n],
                drv.velocities()[n],
                drv.internal_forces()[n],
            );
            assert!((u - w * t).norm() <= 1e-12 * (w * t).norm(), "node {n}: u {u:?}");
            assert!((v - w).norm() <= 1e-12 * w.norm(), "node {n}: v {v:?}");
            assert!(f.norm() <= 1e-9 * k_scale, "node {n}: f {f:?}");
        }
        // rounding only: ~1e-17 J/m against a kinetic energy of ~6e-3 J/m
        let (strain, kinetic) = (drv.strain_energy(), drv.kinetic_energy());
        println!("rigid translation: strain energy {strain:.2e} J/m, kinetic {kinetic:.2e} J/m");
        assert!(strain.abs() <= 1e-12 * kinetic, "strain energy {strain}");
    }

    /// Free boundaries and a smooth initial velocity: K + U stays constant. Central differences
    /// conserve exactly, on a linear system, the shadow energy ½vᵀMv + ½uᵀKu − (Δt²/8) uᵀKM⁻¹Ku
    /// (per mode ω: ½v² + ½ω²u²(1 − ω²Δt²/4)), so K + U oscillates about it by at most
    /// (ωΔt)²/4 of the strain energy, without drift. Here Δt = 0.5 h_min/c_d and the initial field
    /// (a quarter cosine over the 2 m plate, wavenumber π/2 per m) puts its energy in modes with
    /// ωΔt ≲ 0.5 (π/2) h_min c/c_d ≈ 0.05 (h_min ≈ 0.067 m, c ≤ c_d), a bound of about 7e-4.
    /// Measured: 5.2e-4 over 1000 steps, with the strain energy reaching 0.8 E0. Tolerance 1e-3.
    #[test]
    fn energy_is_conserved_with_free_boundaries() {
        let mesh = rect_tri();
        let opts = DriverOptions {
            alpha: 0.5,
            ..DriverOptions::default()
        };
        let mut drv = UnstructuredDriver::new(&mesh, &material(), &[], &opts).unwrap();
        let v0 = 0.1; // m/s
        drv.set_initial(|x| {
            let s = (std::f64::consts::PI * x.x / 2.0).cos();
            (Vector2::zeros(), Vector2::new(v0 * s, 0.5 * v0 * s))
        });
        let e0 = drv.kinetic_energy() + drv.strain_energy();
        let mut worst: f64 = 0.0;
        let mut max_strain: f64 = 0.0;
        for _ in 0..1000 {
            drv.step();
            let e = drv.kinetic_energy() + drv.strain_energy();
            worst = worst.max((e - e0).abs() / e0);
            max_strain = max_strain.max(drv.strain_energy() / e0);
        }
        println!(
            "energy: max |ΔE|/E0 = {worst:.3e} over 1000 steps (Δt = {:.3e} s, strain energy up to {max_strain:.2} E0)",
            drv.dt()
        );
        assert!(
            max_strain > 0.3,
            "the test must exchange kinetic and strain energy"
        );
        assert!(worst <= 1e-3, "energy drift {worst:e}");
    }

    #[test]
    fn later_groups_combine_per_component() {
        let mesh = rect_tri();
        let corner = nearest_node(&mesh.positions, Vector2::new(0.0, 1.0));
        let bottom_corner = nearest_node(&mesh.positions, Vector2::new(0.0, 0.0));
        let bcs = [
            GroupBc::prescribed("left", Axis::X, ramp(1e-5, 1e-4)),
            GroupBc::roller("top", Axis::Y),
            // a later group wins on a component both prescribe
            GroupBc::roller("bottom", Axis::X),
        ];
        let mut drv = UnstructuredDriver::new(&mesh, &material(), &bcs, &DriverOptions::default()).unwrap();
        drv.run_until(2e-4).unwrap();
        let u = drv.displacements();
        assert_eq!(u[corner], Vector2::new(1e-5, 0.0));
        assert_eq!(u[bottom_corner].x, 0.0);
        assert!(u[bottom_corner].y != 0.0, "bottom-left corner: u_y is free");
    }

    #[test]
    fn unknown_group_is_an_error_naming_it() {
        let mesh = rect_tri();
        let bcs = [GroupBc::roller("left", Axis::X), GroupBc::roller("lfet", Axis::Y)];
        let err = UnstructuredDriver::new(&mesh, &material(), &bcs, &DriverOptions::default()).unwrap_err();
        assert!(matches!(
            &err,
            DriverError::BoundaryGroup(MeshError::MissingGroup { group, .. }) if group == "lfet"
        ));
        let message = err.to_string();
        assert!(
            message.contains("\"lfet\"") && message.contains("left"),
            "{message}"
        );
    }

    #[test]
    fn a_surface_material_weighs_its_elements_and_bad_surfaces_are_errors() {
        let mesh = rect_tri();
        let opts = DriverOptions::default();
        let base = UnstructuredDriver::new(&mesh, &material(), &[], &opts).unwrap();
        let heavy = PlaneStrain::new(70e6, 0.35, 2.0 * 1230.0);
        let given = |group: &str, m: PlaneStrain| SurfaceMaterial {
            group: group.into(),
            material: m,
        };
        // every element in "bulk", twice as dense: masses doubled exactly, Δt × √2 (c_d ∝ 1/√ρ)
        let drv = UnstructuredDriver::with_materials(&mesh, &material(), &[given("bulk", heavy)], &[], &opts)
            .unwrap();
        for (m, m0) in drv.bulk().masses().iter().zip(base.bulk().masses()) {
            assert_eq!(*m, 2.0 * m0);
        }
        assert!((drv.dt() / (2f64.sqrt() * base.dt()) - 1.0).abs() < 1e-14);
        let err = |surfaces: &[SurfaceMaterial]| {
            UnstructuredDriver::with_materials(&mesh, &material(), surfaces, &[], &opts).unwrap_err()
        };
        assert!(matches!(
            err(&[given("blk", heavy)]),
            DriverError::MaterialGroup(MeshError::MissingGroup { group, .. }) if group == "blk"
        ));
        assert!(matches!(
            err(&[given("left", heavy)]),
            DriverError::MaterialGroup(MeshError::WrongDimension { group, .. }) if group == "left"
        ));
        let overlap = err(&[given("bulk", heavy), given("bulk", material())]);
        assert!(
            matches!(&overlap, DriverError::MaterialOverlap { first, second, .. } if first == "bulk" && second == "bulk"),
            "{overlap}"
        );
        // the same material twice is no conflict
        UnstructuredDriver::with_materials(
            &mesh,
            &material(),
            &[given("bulk", heavy), given("bulk", heavy)],
            &[],
            &opts,
        )
        .unwrap();
    }

    #[test]
    fn bad_options_are_errors() {
        let mesh = rect_tri();
        for alpha in [0.0, 1.5, f64::NAN] {
            let opts = DriverOptions {
                alpha,
                ..DriverOptions::default()
            };
            let err = UnstructuredDriver::new(&mesh, &material(), &[], &opts).unwrap_err();
            assert!(matches!(err, DriverError::BadAlpha(_)));
        }
        let opts = DriverOptions {
            probe_every: 0,
            ..DriverOptions::default()
        };
        let err = UnstructuredDriver::new(&mesh, &material(), &[], &opts).unwrap_err();
        assert_eq!(err, DriverError::ZeroProbeInterval);
    }

    #[test]
    fn probes_record_at_their_interval_and_runs_repeat_exactly() {
        let mesh = rect_tri();
        let opts = DriverOptions {
            alpha: 0.5,
            probes: vec![Vector2::new(1.0, 0.5), Vector2::new(1.9, 0.45)],
            probe_every: 3,
        };
        let bcs = [
            GroupBc::prescribed("left", Axis::X, ramp(1e-5, 2e-3)).with(Axis::Y, ramp(-1e-5, 1e-3)),
            GroupBc::roller("bottom", Axis::Y),
        ];
        let run = || {
            let mut drv = UnstructuredDriver::new(&mesh, &material(), &bcs, &opts).unwrap();
            drv.run_until(100.0 * drv.dt()).unwrap();
            drv
        };
        let (a, b) = (run(), run());
        // t = 0 and every third of 100 steps, two probes each
        assert_eq!(a.records().len(), 2 * (1 + 33));
        for (p, &n) in a.probe_nodes().iter().enumerate() {
            assert_eq!(n, nearest_node(&mesh.positions, opts.probes[p]));
        }
        assert!(a.records().last().unwrap().ux != 0.0);
        for (ra, rb) in a.records().iter().zip(b.records()) {
            assert_eq!(
                (ra.t, ra.ux.to_bits(), ra.uy.to_bits()),
                (rb.t, rb.ux.to_bits(), rb.uy.to_bits())
            );
        }
    }
}
