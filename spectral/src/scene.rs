//! Scene: serde `RawScene` (unknown keys collected) → `validate()` → typed [`Scene`]. Every
//! problem of a file is reported at once, each with its key and line. No physics here beyond the
//! derived plane-strain constants.

use serde::Deserialize;

use crate::error::SceneError;
pub use crate::law::point::ContactFriction;

/// Plane-strain wave speeds [m/s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WaveSpeeds {
    /// Dilatational (P) speed c_d = η c_s [m/s].
    pub cd: f64,
    /// Shear speed c_s = sqrt(μ/ρ) [m/s].
    pub cs: f64,
    /// Rayleigh speed c_R [m/s].
    pub cr: f64,
}

/// History-convolution path (docs/spectral-model.md §4.1, §4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Convolution {
    /// Truncated direct convolution of docs/spectral-model.md §4 (the reference path).
    Direct,
    /// Recursive convolution with sum-of-exponentials kernels; cost independent of the history length.
    Fast,
}

/// How the recursion states are stored (`[spectral] fast_storage`, docs/spectral-model.md
/// §4.3). The arithmetic is double precision either way; only what is kept from one step to the
/// next differs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FastStorage {
    /// Each state in double precision (the default): 128 B a pole and mode.
    #[default]
    F64,
    /// Each state rounded to single precision when stored: 64 B a pole and mode, so a step moves
    /// 192 B a pole and mode instead of 320.
    F32,
}

impl FastStorage {
    /// The storage the scene's word names.
    pub fn from_name(name: &str) -> Option<FastStorage> {
        [FastStorage::F64, FastStorage::F32]
            .into_iter()
            .find(|s| s.name() == name)
    }

    /// The scene's word for it.
    pub fn name(self) -> &'static str {
        match self {
            FastStorage::F64 => "f64",
            FastStorage::F32 => "f32",
        }
    }
}

/// Which interface points are broken at t = 0 (`spectral.initial_interface`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitialInterface {
    /// The pre-crack |x − center_x| < a is broken, the rest cohesive (the default).
    PreCrack,
    /// Every point is broken: a frictional or free fault with no cohesion, the set-up that
    /// verifies radiation damping exactly (docs/spectral-model.md §7.3).
    Broken,
}

/// Linear ramp through S(s) = s³(10 − 15 s + 6 s²), paper eq. (B.1).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Ramp {
    /// Value before the ramp [Pa].
    pub initial: f64,
    /// Value after the ramp [Pa].
    pub r#final: f64,
    /// Ramp start time [s].
    pub ramp_start: f64,
    /// Ramp end time [s]; equal to `ramp_start` gives a step.
    pub ramp_end: f64,
}

/// Optional shear-load perturbation for nucleation: a cos² bump added to s_xy, constant in time.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
pub struct Nucleation {
    /// Peak added shear stress [Pa].
    pub shear: f64,
    /// Bump centre x [m].
    pub center: f64,
    /// Bump half-width [m] (the bump vanishes for |x − center| ≥ half_width).
    pub half_width: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawScene {
    #[allow(dead_code)]
    name: Option<String>,
    material: RawMaterial,
    interface: RawInterface,
    crack: RawCrack,
    friction: RawFriction,
    loading: RawLoading,
    spectral: RawSpectral,
    #[allow(dead_code)]
    fem: Option<toml::Value>,
    #[allow(dead_code)]
    compare: Option<toml::Value>,
}

/// `[material]`: the three keys for two identical half-spaces, or `top` and `bottom` tables.
#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawMaterial {
    youngs_modulus: Option<f64>,
    poisson_ratio: Option<f64>,
    density: Option<f64>,
    top: Option<RawSolid>,
    bottom: Option<RawSolid>,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawSolid {
    youngs_modulus: f64,
    poisson_ratio: f64,
    density: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawInterface {
    sigma_c: f64,
    delta_c: f64,
    beta: f64,
    kappa: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawCrack {
    half_length: f64,
    center_x: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawFriction {
    friction_coeff: f64,
    contact_friction: Option<String>,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawLoading {
    duration: f64,
    normal: Ramp,
    shear: Ramp,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
struct RawSpectral {
    length: f64,
    grid_points: i64,
    cs_dt_over_dx: Option<f64>,
    time_step: Option<f64>,
    kernel_cutoff: f64,
    t_star: f64,
    output_interval: f64,
    field_output_interval: Option<f64>,
    convolution: Option<Convolution>,
    fast_tolerance: Option<f64>,
    fast_storage: Option<String>,
    contact: Option<bool>,
    nucleation: Option<Nucleation>,
    initial_interface: Option<String>,
}

/// Default relative accuracy of the sum-of-exponentials kernel fit (docs/spectral-model.md §4.3) [-].
pub const DEFAULT_FAST_TOLERANCE: f64 = 1e-5;

/// One isotropic linear-elastic half-space, plane strain. SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solid {
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson ratio ν [-].
    pub poisson_ratio: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
}

impl Solid {
    /// Shear modulus μ = E/(2(1+ν)) [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// η = c_d/c_s = sqrt(2(1−ν)/(1−2ν)) [-] (plane strain).
    pub fn eta(&self) -> f64 {
        let nu = self.poisson_ratio;
        (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)).sqrt()
    }

    /// Plane-strain wave speeds [m/s].
    pub fn wave_speeds(&self) -> WaveSpeeds {
        let cs = (self.shear_modulus() / self.density).sqrt();
        let eta = self.eta();
        WaveSpeeds {
            cd: eta * cs,
            cs,
            cr: rayleigh_ratio(eta) * cs,
        }
    }

    /// Shear impedance ρ c_s = μ/c_s [Pa s/m].
    pub fn shear_impedance(&self) -> f64 {
        self.shear_modulus() / self.wave_speeds().cs
    }

    /// Normal impedance ρ c_d = η μ/c_s [Pa s/m].
    pub fn normal_impedance(&self) -> f64 {
        self.eta() * self.shear_modulus() / self.wave_speeds().cs
    }
}

/// A validated scene: the shared problem plus the spectral discretisation. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Young's modulus E of the top half-space (of both, unless `bottom` is set) [Pa].
    pub youngs_modulus: f64,
    /// Poisson ratio ν of the top half-space (of both, unless `bottom` is set) [-].
    pub poisson_ratio: f64,
    /// Density ρ of the top half-space (of both, unless `bottom` is set) [kg/m³].
    pub density: f64,
    /// The bottom half-space when `[material]` is split into `top` and `bottom` (docs/spectral-model.md
    /// §2.1); `None`: two identical half-spaces.
    pub bottom: Option<Solid>,
    /// Cohesive strength σ_c [Pa].
    pub sigma_c: f64,
    /// Critical opening δ_c [m].
    pub delta_c: f64,
    /// TSL shear/normal coupling β [-] (paper eq. 2).
    pub beta: f64,
    /// TSL parameter κ [-] (paper eq. 2).
    pub kappa: f64,
    /// Pre-crack half-length a [m] (0: no pre-crack).
    pub half_length: f64,
    /// Pre-crack centre x [m]; the grid is centred on it.
    pub center_x: f64,
    /// Coulomb friction coefficient μ [-].
    pub friction_coeff: f64,
    /// Where friction acts (`[friction] contact_friction`; default `all_faces`).
    pub contact_friction: ContactFriction,
    /// Run duration T [s].
    pub duration: f64,
    /// Far-field s_yy(t) ramp [Pa].
    pub normal: Ramp,
    /// Far-field s_xy(t) ramp [Pa].
    pub shear: Ramp,
    /// Periodic length X [m].
    pub length: f64,
    /// Number of grid points N [-] (even).
    pub grid_points: usize,
    /// CFL parameter c_s Δt/Δx [-], in (0, 0.5].
    pub cs_dt_over_dx: f64,
    /// Kernel truncation tcut in T = |k| c_s t [-].
    pub kernel_cutoff: f64,
    /// Prakash regularisation time t* [s] (0: plain Coulomb).
    pub t_star: f64,
    /// Interval between contact-mean records [s].
    pub output_interval: f64,
    /// Interval between space-time field snapshots [s] (None: no field output).
    pub field_output_interval: Option<f64>,
    /// History-convolution path.
    pub convolution: Convolution,
    /// Max abs error of the fast path's kernel fit on [0, tcut], relative to max|K| [-].
    pub fast_tolerance: f64,
    /// How the fast path stores its recursion states between steps.
    pub fast_storage: FastStorage,
    /// Contact (no interpenetration) on broken points; off only for verification set-ups.
    pub contact: bool,
    /// Optional nucleation perturbation of s_xy.
    pub nucleation: Option<Nucleation>,
    /// Which points are broken at t = 0.
    pub initial_interface: InitialInterface,
    /// The form the scene was read from: a variant ([`Scene::with_friction_coeff`], ...) edits
    /// it and validates it again, so a variant is checked exactly like a file.
    raw: RawScene,
}

impl Scene {
    /// Parses and validates. A file that does not parse gives that one error with its line;
    /// otherwise every problem found is reported at once (`SceneError::Invalid`), unknown keys
    /// included, each naming the key as written, its line in `text` and what is allowed.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        preflight::read(text, validate::validate, SceneError::problems).map_err(SceneError::from)
    }

    /// The same scene with another edit of its raw form, validated again.
    fn variant(&self, edit: impl FnOnce(&mut RawScene)) -> Result<Scene, SceneError> {
        let mut raw = self.raw.clone();
        edit(&mut raw);
        validate::validate(raw)
    }

    /// The same scene with Coulomb coefficient μ [-] on contacting broken points.
    pub fn with_friction_coeff(&self, friction_coeff: f64) -> Result<Scene, SceneError> {
        self.variant(|r| r.friction.friction_coeff = friction_coeff)
    }

    /// The same scene with friction acting where `rule` says (`[friction] contact_friction`).
    pub fn with_contact_friction(&self, rule: ContactFriction) -> Result<Scene, SceneError> {
        self.variant(|r| r.friction.contact_friction = Some(contact_friction_name(rule).to_string()))
    }

    /// The same scene stepped with Δt [s] (replaces `cs_dt_over_dx`; paper §3.2 runs the spectral
    /// model at the FE model's step). Refused where c_s Δt/Δx leaves (0, 0.5].
    pub fn with_time_step(&self, time_step: f64) -> Result<Scene, SceneError> {
        self.variant(|r| {
            r.spectral.cs_dt_over_dx = None;
            r.spectral.time_step = Some(time_step);
        })
    }

    /// The same scene on N grid points [-] (even).
    pub fn with_grid_points(&self, grid_points: usize) -> Result<Scene, SceneError> {
        self.variant(|r| r.spectral.grid_points = i64::try_from(grid_points).unwrap_or(i64::MAX))
    }

    /// The top half-space (y > 0): the whole material unless `[material]` is split.
    pub fn top(&self) -> Solid {
        Solid {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
        }
    }

    /// The bottom half-space (y < 0): the top one unless `[material]` is split.
    pub fn bottom(&self) -> Solid {
        self.bottom.unwrap_or_else(|| self.top())
    }

    /// True when `[material]` is split into `top` and `bottom` (the bimaterial path, even with
    /// equal halves).
    pub fn is_split(&self) -> bool {
        self.bottom.is_some()
    }

    /// Shear modulus μ = E/(2(1+ν)) of the top half-space [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.top().shear_modulus()
    }

    /// η = c_d/c_s of the top half-space [-] (plane strain).
    pub fn eta(&self) -> f64 {
        self.top().eta()
    }

    /// Plane-strain wave speeds of the top half-space [m/s].
    pub fn wave_speeds(&self) -> WaveSpeeds {
        self.top().wave_speeds()
    }

    /// The larger of the two shear-wave speeds, which sets the step [m/s].
    pub fn fastest_shear_speed(&self) -> f64 {
        self.top().wave_speeds().cs.max(self.bottom().wave_speeds().cs)
    }

    /// Grid spacing Δx = X/N [m].
    pub fn grid_spacing(&self) -> f64 {
        self.length / self.grid_points as f64
    }

    /// Time step the run will use, Δt = β Δx / c_s [s], with the faster half-space's c_s.
    pub fn time_step(&self) -> f64 {
        self.cs_dt_over_dx * self.grid_spacing() / self.fastest_shear_speed()
    }

    /// Run duration T [s] (`[loading].duration`).
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Pre-crack half-length a [m].
    pub fn half_length(&self) -> f64 {
        self.half_length
    }

    /// Pre-crack centre x [m].
    pub fn center_x(&self) -> f64 {
        self.center_x
    }

    /// The scene's name of a friction rule.
    pub fn contact_friction_name(rule: ContactFriction) -> &'static str {
        match rule {
            ContactFriction::AllFaces => "all_faces",
            ContactFriction::FailedOnly => "failed_only",
        }
    }

    /// Process-zone size l_p = E G_c/σ_c², G_c = σ_c δ_c/2 [m], with the softer half-space's E.
    pub fn process_zone(&self) -> f64 {
        let e = self.youngs_modulus.min(self.bottom().youngs_modulus);
        process_zone(e, self.sigma_c, self.delta_c)
    }

    /// What a valid scene does that its user should know before running it: a grid that
    /// resolves the process zone with fewer than 4 points, a crack whose periodic images are
    /// near (a periodic length below 20a).
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        let per_zone = self.process_zone() / self.grid_spacing();
        if per_zone < WARN_POINTS_PER_ZONE {
            w.push(format!(
                "spectral.grid_points = {}: {per_zone:.2} points per process zone l_p = {:e} m \
                 (at least {WARN_POINTS_PER_ZONE} advised); tip positions and speeds are coarse",
                self.grid_points,
                self.process_zone()
            ));
        }
        let (top, bottom) = (self.top(), self.bottom());
        if !slip_wave_exists(top, bottom) {
            w.push(format!(
                "material: no generalized Rayleigh wave exists between these half-spaces (c_s = \
                 {:.4e} and {:.4e} m/s; the contrast is past its existence limit): a mode-II tip \
                 has no interface wave speed below the slower c_s to tend to, and the run is not \
                 covered by the checks of docs/spectral-model.md §2.1",
                top.wave_speeds().cs,
                bottom.wave_speeds().cs
            ));
        }
        let a = self.half_length;
        if self.initial_interface == InitialInterface::PreCrack
            && a > 0.0
            && self.length < WARN_LENGTH_OVER_A * a
        {
            w.push(format!(
                "spectral.length = {} m = {:.1}a: the crack's periodic images are {:.1}a away and \
                 load its tips (the centre-crack case uses 30a)",
                self.length,
                self.length / a,
                (self.length - 2.0 * a) / a
            ));
        }
        w
    }

    /// Index of the last step: records at t_n = n Δt for n = 0..=last_step, t_n ≤ T.
    pub fn last_step(&self) -> u64 {
        (self.duration / self.time_step() * (1.0 + 1e-12)).floor() as u64
    }
}

/// c_R/c_s: root ξ of (2 − ξ²)² = 4 sqrt(1 − ξ²) sqrt(1 − ξ²/η²) in (0, 1), by bisection (§7.2).
pub fn rayleigh_ratio(eta: f64) -> f64 {
    let f = |x: f64| (2.0 - x * x).powi(2) - 4.0 * (1.0 - x * x).sqrt() * (1.0 - x * x / (eta * eta)).sqrt();
    let (mut lo, mut hi) = (0.5, 1.0 - 1e-15);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < 0.0 { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}

/// Whether two half-spaces carry a generalized Rayleigh wave (Weertman 1963): the interface wave
/// of a closed interface that slips freely, and the speed a mode-II tip on a bimaterial interface
/// tends to. From each face's normal stiffness when it slips freely, μ R/(A11) of §2 at
/// s = i v/c_s (docs/spectral-model.md §2.1): positive for both faces as v → 0, and the wave
/// exists when their sum has turned negative at the slower shear speed. Identical halves always
/// carry one (the Rayleigh wave); past a contrast of about 25 % in c_s through μ it is gone.
pub fn slip_wave_exists(top: Solid, bottom: Solid) -> bool {
    let v = top.wave_speeds().cs.min(bottom.wave_speeds().cs);
    let stiffness = |s: Solid| {
        let x = (v / s.wave_speeds().cs).powi(2);
        let (a, b) = ((1.0 - x).max(0.0).sqrt(), (1.0 - x / (s.eta() * s.eta())).sqrt());
        let d = 1.0 - a * b;
        let (a11, a22, g) = (x * b / d, x * a / d, 2.0 - x / d);
        s.shear_modulus() * (a11 * a22 - g * g) / a11
    };
    top == bottom || stiffness(top) + stiffness(bottom) < 0.0
}

/// Grid points per process zone below which a run is refused (the zone falls between points).
const MIN_POINTS_PER_ZONE: f64 = 1.0;
/// Grid points per process zone below which a run is warned about.
const WARN_POINTS_PER_ZONE: f64 = 4.0;
/// Periodic length over half-length below which the crack's periodic images are warned about
/// (the centre-crack case uses 30).
const WARN_LENGTH_OVER_A: f64 = 20.0;

/// The scene's name of a friction rule.
pub fn contact_friction_name(rule: ContactFriction) -> &'static str {
    match rule {
        ContactFriction::AllFaces => "all_faces",
        ContactFriction::FailedOnly => "failed_only",
    }
}

/// Process-zone size l_p = E G_c/σ_c² with G_c = σ_c δ_c/2 [m] (the scale the grid must resolve).
fn process_zone(youngs_modulus: f64, sigma_c: f64, delta_c: f64) -> f64 {
    youngs_modulus * delta_c / (2.0 * sigma_c)
}

/// One error as it is; several as `Invalid` (lines are added by [`Scene::from_toml_str`]).
fn collected(mut errors: Vec<SceneError>) -> SceneError {
    if errors.len() == 1 {
        return errors.pop().expect("invariant: one error");
    }
    SceneError::Invalid {
        problems: errors.iter().flat_map(SceneError::problems).collect(),
    }
}

#[cfg(test)]
#[path = "scene_tests.rs"]
mod tests;
mod validate;
