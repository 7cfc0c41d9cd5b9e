//! Scene: serde `RawScene` (unknown keys refused) → `validate()` → typed [`Scene`]. No physics here
//! beyond the derived plane-strain constants.

use serde::Deserialize;

use crate::error::SceneError;

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

/// Linear ramp through S(s) = s³(10 − 15 s + 6 s²), paper eq. (B.1).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
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
#[serde(deny_unknown_fields)]
pub struct Nucleation {
    /// Peak added shear stress [Pa].
    pub shear: f64,
    /// Bump centre x [m].
    pub center: f64,
    /// Bump half-width [m] (the bump vanishes for |x − center| ≥ half_width).
    pub half_width: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
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

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    youngs_modulus: f64,
    poisson_ratio: f64,
    density: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawInterface {
    sigma_c: f64,
    delta_c: f64,
    beta: f64,
    kappa: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCrack {
    half_length: f64,
    center_x: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFriction {
    friction_coeff: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoading {
    duration: f64,
    normal: Ramp,
    shear: Ramp,
}

#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
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
    contact: Option<bool>,
    nucleation: Option<Nucleation>,
}

/// Default relative accuracy of the sum-of-exponentials kernel fit (docs/spectral-model.md §4.3) [-].
pub const DEFAULT_FAST_TOLERANCE: f64 = 1e-5;

/// A validated scene: the shared problem plus the spectral discretisation. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson ratio ν [-].
    pub poisson_ratio: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
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
    /// Coulomb friction coefficient on contacting broken points [-].
    pub friction_coeff: f64,
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
    /// Contact (no interpenetration) on broken points; off only for verification set-ups.
    pub contact: bool,
    /// Optional nucleation perturbation of s_xy.
    pub nucleation: Option<Nucleation>,
    /// The form the scene was read from: a variant ([`Scene::with_friction_coeff`], ...) edits
    /// it and validates it again, so a variant is checked exactly like a file.
    raw: RawScene,
}

fn check(field: &'static str, value: f64, ok: bool, allowed: &'static str) -> Result<(), SceneError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(SceneError::OutOfRange {
            field,
            value,
            allowed,
        })
    }
}

fn check_ramp(prefix: &'static [&'static str; 4], r: &Ramp) -> Result<(), SceneError> {
    check(prefix[0], r.initial, true, "a finite stress")?;
    check(prefix[1], r.r#final, true, "a finite stress")?;
    check(prefix[2], r.ramp_start, r.ramp_start >= 0.0, ">= 0")?;
    check(prefix[3], r.ramp_end, r.ramp_end >= r.ramp_start, ">= ramp_start")
}

impl Scene {
    /// Parses and validates; errors name the field, the value and the allowed range.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text)?;
        validate(raw)
    }

    /// The same scene with another edit of its raw form, validated again.
    fn variant(&self, edit: impl FnOnce(&mut RawScene)) -> Result<Scene, SceneError> {
        let mut raw = self.raw.clone();
        edit(&mut raw);
        validate(raw)
    }

    /// The same scene with Coulomb coefficient μ [-] on contacting broken points.
    pub fn with_friction_coeff(&self, friction_coeff: f64) -> Result<Scene, SceneError> {
        self.variant(|r| r.friction.friction_coeff = friction_coeff)
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

    /// Grid spacing Δx = X/N [m].
    pub fn grid_spacing(&self) -> f64 {
        self.length / self.grid_points as f64
    }

    /// Time step the run will use, Δt = β Δx / c_s [s].
    pub fn time_step(&self) -> f64 {
        self.cs_dt_over_dx * self.grid_spacing() / self.wave_speeds().cs
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

fn validate(r: RawScene) -> Result<Scene, SceneError> {
    let raw = r.clone();
    let m = &r.material;
    check(
        "material.youngs_modulus",
        m.youngs_modulus,
        m.youngs_modulus > 0.0,
        "> 0",
    )?;
    check(
        "material.poisson_ratio",
        m.poisson_ratio,
        m.poisson_ratio > 0.0 && m.poisson_ratio < 0.5,
        "(0, 0.5)",
    )?;
    check("material.density", m.density, m.density > 0.0, "> 0")?;
    let i = &r.interface;
    check("interface.sigma_c", i.sigma_c, i.sigma_c > 0.0, "> 0")?;
    check("interface.delta_c", i.delta_c, i.delta_c > 0.0, "> 0")?;
    check("interface.beta", i.beta, i.beta > 0.0, "> 0")?;
    check("interface.kappa", i.kappa, i.kappa > 0.0, "> 0")?;
    check(
        "crack.half_length",
        r.crack.half_length,
        r.crack.half_length >= 0.0,
        ">= 0",
    )?;
    check("crack.center_x", r.crack.center_x, true, "finite")?;
    let mu_f = r.friction.friction_coeff;
    check("friction.friction_coeff", mu_f, mu_f >= 0.0, ">= 0")?;
    let l = &r.loading;
    check("loading.duration", l.duration, l.duration > 0.0, "> 0")?;
    check_ramp(
        &[
            "loading.normal.initial",
            "loading.normal.final",
            "loading.normal.ramp_start",
            "loading.normal.ramp_end",
        ],
        &l.normal,
    )?;
    check_ramp(
        &[
            "loading.shear.initial",
            "loading.shear.final",
            "loading.shear.ramp_start",
            "loading.shear.ramp_end",
        ],
        &l.shear,
    )?;
    let s = &r.spectral;
    check("spectral.length", s.length, s.length > 0.0, "> 0")?;
    let n = s.grid_points;
    check(
        "spectral.grid_points",
        n as f64,
        (4..=(1 << 24)).contains(&n) && n % 2 == 0,
        "an even integer in [4, 2^24]",
    )?;
    let dx = s.length / n as f64;
    let shear_modulus = m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
    let cs = (shear_modulus / m.density).sqrt();
    let cfl = match (s.cs_dt_over_dx, s.time_step) {
        (Some(b), None) => {
            check(
                "spectral.cs_dt_over_dx",
                b,
                b > 0.0 && b <= 0.5,
                "(0, 0.5] (docs/spectral-model.md §7.8)",
            )?;
            b
        }
        (None, Some(dt)) => {
            let b = dt * cs / dx;
            check(
                "spectral.time_step",
                dt,
                b > 0.0 && b <= 0.5,
                "(0, 0.5 dx/c_s] i.e. c_s dt/dx in (0, 0.5] (docs/spectral-model.md §7.8)",
            )?;
            b
        }
        _ => {
            return Err(SceneError::Inconsistent(
                "[spectral] needs exactly one of cs_dt_over_dx [-] or time_step [s]".into(),
            ));
        }
    };
    check(
        "spectral.kernel_cutoff",
        s.kernel_cutoff,
        s.kernel_cutoff > 0.0 && s.kernel_cutoff <= 1000.0,
        "(0, 1000]",
    )?;
    check(
        "spectral.t_star",
        s.t_star,
        s.t_star >= 0.0,
        ">= 0 (0: plain Coulomb)",
    )?;
    check(
        "spectral.output_interval",
        s.output_interval,
        s.output_interval > 0.0,
        "> 0",
    )?;
    if let Some(fi) = s.field_output_interval {
        check("spectral.field_output_interval", fi, fi > 0.0, "> 0")?;
    }
    let fast_tolerance = s.fast_tolerance.unwrap_or(DEFAULT_FAST_TOLERANCE);
    check(
        "spectral.fast_tolerance",
        fast_tolerance,
        (1e-10..=1e-2).contains(&fast_tolerance),
        "[1e-10, 1e-2]",
    )?;
    if let Some(nu) = &s.nucleation {
        check("spectral.nucleation.shear", nu.shear, true, "finite")?;
        check("spectral.nucleation.center", nu.center, true, "finite")?;
        check(
            "spectral.nucleation.half_width",
            nu.half_width,
            nu.half_width > 0.0,
            "> 0",
        )?;
    }
    Ok(Scene {
        youngs_modulus: m.youngs_modulus,
        poisson_ratio: m.poisson_ratio,
        density: m.density,
        sigma_c: i.sigma_c,
        delta_c: i.delta_c,
        beta: i.beta,
        kappa: i.kappa,
        half_length: r.crack.half_length,
        center_x: r.crack.center_x,
        friction_coeff: mu_f,
        duration: l.duration,
        normal: l.normal,
        shear: l.shear,
        length: s.length,
        grid_points: n as usize,
        cs_dt_over_dx: cfl,
        kernel_cutoff: s.kernel_cutoff,
        t_star: s.t_star,
        output_interval: s.output_interval,
        field_output_interval: s.field_output_interval,
        convolution: s.convolution.unwrap_or(Convolution::Fast),
        fast_tolerance,
        contact: s.contact.unwrap_or(true),
        nucleation: s.nucleation,
        raw,
    })
}

#[cfg(test)]
#[path = "scene_tests.rs"]
mod tests;
