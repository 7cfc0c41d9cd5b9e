//! Scene: TOML text -> `RawScene` (serde) -> `validate()` -> typed `Scene`. No physics beyond the
//! stable-step formula needed to check a requested step.

mod boundary;
mod diagnostics;
mod fem;
mod interface_spec;
mod raw;

pub use boundary::{BoundaryComponent, BoundaryKind, BoundarySpec};
pub use diagnostics::Diagnostics;
pub use fem::{DampingSet, FemSpec, InsertionRule, ModelKind};
pub use interface_spec::{ContactSurface, InterfaceZone};
pub(crate) use interface_spec::{in_range, zone_of};

use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;
use crate::law::elastic::{PlaneStrain, WaveSpeeds};
use raw::{RawRamp, RawScene};

/// A ramp through the quintic smoothstep of paper eq. (B.1):
/// value(t) = initial + (final − initial) S((t − t₀)/(t₁ − t₀)), S(s) = s³(10 − 15s + 6s²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ramp {
    /// Value before the ramp (unit of the quantity: [Pa] or [m]).
    pub initial: f64,
    /// Value after the ramp (same unit).
    pub final_value: f64,
    /// Ramp start t₀ [s].
    pub ramp_start: f64,
    /// Ramp end t₁ [s] (t₁ = t₀ gives a step).
    pub ramp_end: f64,
}

impl Ramp {
    /// A constant zero.
    pub const ZERO: Ramp = Ramp {
        initial: 0.0,
        final_value: 0.0,
        ramp_start: 0.0,
        ramp_end: 0.0,
    };

    /// Value at time t [s].
    pub fn value(&self, t: f64) -> f64 {
        let s = if self.ramp_end > self.ramp_start {
            ((t - self.ramp_start) / (self.ramp_end - self.ramp_start)).clamp(0.0, 1.0)
        } else if t >= self.ramp_start {
            1.0
        } else {
            0.0
        };
        self.initial + (self.final_value - self.initial) * s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)
    }
}

/// Pre-crack on the row y = 0: |x − center_x| < half_length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crack {
    /// Half length a [m].
    pub half_length: f64,
    /// Centre x_c [m].
    pub center_x: f64,
}

/// Far-field loading: duration and the two stress histories (paper Section 3, cases.md).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loading {
    /// Run duration T [s].
    pub duration: f64,
    /// Far-field normal stress σ_yy^∞(t) [Pa] (tension positive).
    pub normal: Ramp,
    /// Far-field shear stress σ_xy^∞(t) [Pa].
    pub shear: Ramp,
}

/// A validated scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// Bulk material (plane strain).
    pub material: PlaneStrain,
    /// Cohesive law of the interface row outside the pre-crack; `None`: no cohesive interface.
    pub interface: Option<LinearCohesive>,
    /// Pre-crack; `None`: none.
    pub crack: Option<Crack>,
    /// Coulomb coefficient μ [-] on crack faces.
    pub friction_coeff: f64,
    /// Loading histories.
    pub loading: Loading,
    /// FE discretisation and options.
    pub fem: FemSpec,
    /// Time step of the run [s].
    time_step: f64,
}

impl Scene {
    /// Parses and validates; errors name the field, the value and the allowed range.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let raw: RawScene = toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))?;
        validate(raw)
    }

    /// Time step the run will use [s].
    pub fn time_step(&self) -> f64 {
        self.time_step
    }

    /// Run duration T [s].
    pub fn duration(&self) -> f64 {
        self.loading.duration
    }

    /// Pre-crack half-length a [m] (0 without a pre-crack).
    pub fn half_length(&self) -> f64 {
        self.crack.map_or(0.0, |c| c.half_length)
    }

    /// Pre-crack centre x [m] (0 without a pre-crack).
    pub fn center_x(&self) -> f64 {
        self.crack.map_or(0.0, |c| c.center_x)
    }

    /// Plane-strain wave speeds [m/s].
    pub fn wave_speeds(&self) -> WaveSpeeds {
        self.material.wave_speeds()
    }

    /// Whether node-to-segment contact runs (hybrid model with a pre-crack or a cohesive interface).
    pub fn has_contact(&self) -> bool {
        self.fem.model == ModelKind::Hybrid && (self.crack.is_some() || self.interface.is_some())
    }

    /// Whether a penalty (contact or standard compression penalty) limits the step.
    fn has_penalty(&self) -> bool {
        self.has_contact() || (self.fem.model == ModelKind::Standard && self.interface.is_some())
    }

    /// Largest stable step [s]: fem-method §2 with α = 0.95 (the largest allowed safety factor).
    pub fn stable_limit(&self) -> f64 {
        let h = self.fem.min_edge();
        let beta_p = if self.has_penalty() {
            self.fem.eps_n.max(self.fem.eps_t) * h / self.material.youngs_modulus
        } else {
            0.0
        };
        crate::law::elastic::stable_time_step(fem::MAX_SAFETY, h, self.wave_speeds().cd, beta_p)
    }
}

pub(crate) fn check(field: &'static str, value: f64, ok: bool, allowed: &str) -> Result<f64, SceneError> {
    if ok && value.is_finite() {
        Ok(value)
    } else {
        Err(SceneError::OutOfRange {
            field,
            value,
            allowed: allowed.to_string(),
        })
    }
}

fn ramp(field: &'static str, r: Option<RawRamp>) -> Result<Ramp, SceneError> {
    let Some(r) = r else { return Ok(Ramp::ZERO) };
    check(field, r.initial, true, "a finite number")?;
    check(field, r.final_, true, "a finite number")?;
    check(field, r.ramp_start, r.ramp_start >= 0.0, ">= 0 s")?;
    check(field, r.ramp_end, r.ramp_end >= r.ramp_start, ">= ramp_start")?;
    Ok(Ramp {
        initial: r.initial,
        final_value: r.final_,
        ramp_start: r.ramp_start,
        ramp_end: r.ramp_end,
    })
}

fn material(m: &raw::RawMaterial) -> Result<PlaneStrain, SceneError> {
    check(
        "material.youngs_modulus",
        m.youngs_modulus,
        m.youngs_modulus > 0.0,
        "> 0 Pa",
    )?;
    check(
        "material.poisson_ratio",
        m.poisson_ratio,
        (0.0..0.5).contains(&m.poisson_ratio),
        "[0, 0.5)",
    )?;
    check("material.density", m.density, m.density > 0.0, "> 0 kg/m^3")?;
    Ok(PlaneStrain::new(m.youngs_modulus, m.poisson_ratio, m.density))
}

fn interface(i: &raw::RawInterface) -> Result<LinearCohesive, SceneError> {
    check("interface.sigma_c", i.sigma_c, i.sigma_c > 0.0, "> 0 Pa")?;
    check("interface.delta_c", i.delta_c, i.delta_c > 0.0, "> 0 m")?;
    check("interface.beta", i.beta, i.beta > 0.0, "> 0")?;
    check("interface.kappa", i.kappa, i.kappa > 0.0, "> 0")?;
    Ok(LinearCohesive {
        sigma_c: i.sigma_c,
        delta_c: i.delta_c,
        beta: i.beta,
        kappa: i.kappa,
    })
}

fn crack(c: &raw::RawCrack) -> Result<Crack, SceneError> {
    check("crack.half_length", c.half_length, c.half_length > 0.0, "> 0 m")?;
    check("crack.center_x", c.center_x, true, "a finite number")?;
    Ok(Crack {
        half_length: c.half_length,
        center_x: c.center_x,
    })
}

fn validate(raw: RawScene) -> Result<Scene, SceneError> {
    let material = material(&raw.material)?;
    let interface = raw.interface.as_ref().map(interface).transpose()?;
    let crack = raw.crack.as_ref().map(crack).transpose()?;
    let friction_coeff = raw.friction.as_ref().map_or(0.0, |f| f.friction_coeff);
    check(
        "friction.friction_coeff",
        friction_coeff,
        (0.0..=10.0).contains(&friction_coeff),
        "[0, 10]",
    )?;
    let l = &raw.loading;
    check("loading.duration", l.duration, l.duration > 0.0, "> 0 s")?;
    let loading = Loading {
        duration: l.duration,
        normal: ramp("loading.normal", l.normal)?,
        shear: ramp("loading.shear", l.shear)?,
    };
    let fem = fem::validate_fem(&raw.fem, crack.as_ref(), loading.duration)?;
    let mut scene = Scene {
        name: raw.name.unwrap_or_else(|| "unnamed".to_string()),
        material,
        interface,
        crack,
        friction_coeff,
        loading,
        fem,
        time_step: 0.0,
    };
    if !scene.fem.interface_zones.is_empty() && scene.interface.is_none() {
        return Err(SceneError::Geometry(
            "fem.interface_zones needs an [interface] section (the law outside the zones)".to_string(),
        ));
    }
    if scene.has_penalty() && scene.fem.eps_n <= 0.0 {
        return Err(SceneError::OutOfRange {
            field: "fem.eps_n",
            value: scene.fem.eps_n,
            allowed: "> 0 Pa/m when contact or the standard penalty is active".to_string(),
        });
    }
    let limit = scene.stable_limit();
    scene.time_step = match scene.fem.requested_time_step {
        Some(dt) if dt > limit => {
            return Err(SceneError::UnstableTimeStep {
                dt_s: dt,
                limit_s: limit,
            });
        }
        Some(dt) => dt,
        None => limit * scene.fem.time_step_safety / fem::MAX_SAFETY,
    };
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn center_crack() -> String {
        crate::test_scenes::scene_text("center-crack")
    }

    #[test]
    fn center_crack_parses_with_expected_step() {
        let s = Scene::from_toml_str(&center_crack()).unwrap();
        let w = s.wave_speeds();
        let expect = 0.5 * 1e-3 / w.cd * crate::law::elastic::penalty_factor(0.3);
        assert!(
            (s.time_step() - expect).abs() < 1e-15,
            "{} vs {expect}",
            s.time_step()
        );
        assert!(s.has_contact());
    }

    #[test]
    fn ramp_is_smoothstep() {
        let r = Ramp {
            initial: 1.0,
            final_value: 3.0,
            ramp_start: 1.0,
            ramp_end: 3.0,
        };
        assert_eq!(r.value(0.0), 1.0);
        assert!((r.value(2.0) - 2.0).abs() < 1e-15);
        assert_eq!(r.value(5.0), 3.0);
    }

    #[test]
    fn bad_values_name_the_field() {
        let text = center_crack().replace("poisson_ratio = 0.35", "poisson_ratio = 0.6");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("material.poisson_ratio") && e.contains("0.6"), "{e}");
        let text = center_crack().replace("time_step_safety = 0.5", "time_step = 1e-5");
        let e = Scene::from_toml_str(&text).unwrap_err();
        assert!(matches!(e, SceneError::UnstableTimeStep { .. }), "{e}");
        let text = center_crack().replace("element_size = 1e-3", "element_size = 0.7e-3");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("geometry"), "{e}");
        let text = center_crack().replace("half_length = 0.125", "half_length = 0.1255");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("crack tip"), "{e}");
        let text = center_crack().replace("model = \"hybrid\"", "model = \"hybird\"");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("fem.model"), "{e}");
        let text = center_crack().replace("[fem]", "[fem]\nunknown_key = 1");
        assert!(Scene::from_toml_str(&text).is_err());
    }
}
