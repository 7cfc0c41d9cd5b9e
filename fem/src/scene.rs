//! Scene: TOML text -> `RawScene` (serde) -> `validate()` -> typed `Scene`. No physics beyond the
//! stable-step formula needed to check a requested step.

mod boundary;
mod checks;
mod damping;
mod diagnostics;
mod fem;
mod interface_spec;
mod material;
mod mesh;
mod paraview;
mod problem;
mod raw;
mod rough;
pub mod write_msh;

pub use boundary::{BoundaryComponent, BoundaryCurve, BoundaryKind, BoundarySpec, GRID_SIDES};
pub use damping::{Damping, DampingRate, DampingSet};
pub use diagnostics::Diagnostics;
pub use fem::{FemSpec, InsertionRule, ModelKind};
pub use interface_spec::{ContactFriction, ContactSurface, InterfaceZone};
pub(crate) use interface_spec::{in_range, zone_of};
pub use mesh::MeshSpec;
pub use paraview::{MAX_FIELD_FILES, ParaviewSpec};
pub use preflight::line_of;
pub use problem::{Crack, Loading, Ramp};

use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;
use crate::law::elastic::{PlaneStrain, WaveSpeeds};
use checks::{check, collected, keep};
use raw::{RawRamp, RawScene};

/// A validated scene.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// Bulk material (plane strain): of the whole body, or with a split `[material]` of the body
    /// above the interface row (`[material.top]`, y > 0); [`Scene::material_below`] gives the other.
    pub material: PlaneStrain,
    /// `[material.bottom]`, the body below the interface row (y < 0) of a split `[material]`;
    /// `None`: the same as `material` (the flat table).
    pub bottom_material: Option<PlaneStrain>,
    /// Cohesive law of the interface row outside the pre-crack; `None`: no cohesive interface.
    pub interface: Option<LinearCohesive>,
    /// Pre-crack; `None`: none.
    pub crack: Option<Crack>,
    /// Coulomb coefficient μ [-] on crack faces.
    pub friction_coeff: f64,
    /// Where contact friction acts (`[friction] contact_friction`, read by both models).
    pub contact_friction: ContactFriction,
    /// Loading histories.
    pub loading: Loading,
    /// FE discretisation and options.
    pub fem: FemSpec,
    /// Time step of the run [s].
    time_step: f64,
    /// The form the scene was read from: a variant ([`Scene::with_friction_coeff`], ...) edits
    /// it and validates it again, so a variant is checked exactly like a file.
    raw: RawScene,
}

impl Scene {
    /// Parses and validates. A file that does not parse (syntax, a value of the wrong type) gives
    /// that one error with its line; otherwise every problem found is reported at once, unknown
    /// keys included, each naming the key as written, its line in `text`, the value and what is
    /// allowed (`SceneError::Invalid`).
    ///
    /// Relative paths in the scene (`fem.mesh.file`) are taken from the working directory; use
    /// [`Scene::from_toml_str_in`] or [`Scene::from_file`] for a scene read from a file.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        preflight::read(text, validate, SceneError::problems).map_err(SceneError::from)
    }

    /// As [`Scene::from_toml_str`], with relative paths in the scene taken from `base_dir` (the
    /// folder of the scene file).
    pub fn from_toml_str_in(text: &str, base_dir: &std::path::Path) -> Result<Scene, SceneError> {
        let validate_in = |mut raw: RawScene| {
            raw.base_dir = Some(base_dir.to_path_buf());
            validate(raw)
        };
        preflight::read(text, validate_in, SceneError::problems).map_err(SceneError::from)
    }

    /// Reads and validates the scene file at `path` (relative paths in it are taken from its folder).
    pub fn from_file(path: &std::path::Path) -> Result<Scene, SceneError> {
        let text = preflight::input::Cap::scene()
            .and_then(|cap| preflight::input::read_text_capped(path, cap))
            .map_err(|e| SceneError::Parse(format!("cannot read {}: {e}", path.display())))?;
        Scene::from_toml_str_in(&text, path.parent().unwrap_or(std::path::Path::new(".")))
    }

    /// The same scene with another edit of its raw form, validated again.
    fn variant(&self, edit: impl FnOnce(&mut RawScene)) -> Result<Scene, SceneError> {
        let mut raw = self.raw.clone();
        edit(&mut raw);
        validate(raw)
    }

    /// The same scene with Coulomb coefficient μ [-] on the crack faces.
    pub fn with_friction_coeff(&self, friction_coeff: f64) -> Result<Scene, SceneError> {
        self.variant(|r| match &mut r.friction {
            Some(f) => f.friction_coeff = friction_coeff,
            None => {
                r.friction = Some(raw::RawFriction {
                    friction_coeff,
                    contact_friction: None,
                })
            }
        })
    }

    /// The same scene with contact friction acting where `rule` says (`[friction]
    /// contact_friction`; a scene without `[friction]` gets μ = 0 with it).
    pub fn with_contact_friction(&self, rule: ContactFriction) -> Result<Scene, SceneError> {
        let name = match rule {
            ContactFriction::AllFaces => "all_faces",
            ContactFriction::FailedOnly => "failed_only",
        };
        self.variant(|r| {
            let f = r.friction.get_or_insert(raw::RawFriction {
                friction_coeff: 0.0,
                contact_friction: None,
            });
            f.contact_friction = Some(name.to_string());
        })
    }

    /// The same scene run with the hybrid or the standard model (paper Section 4).
    pub fn with_model(&self, model: ModelKind) -> Result<Scene, SceneError> {
        let name = match model {
            ModelKind::Hybrid => "hybrid",
            ModelKind::Standard => "standard",
        };
        self.variant(|r| r.fem.model = Some(name.to_string()))
    }

    /// The same scene meshed with element size h [m] (the time step follows unless the scene
    /// fixes `fem.time_step`).
    pub fn with_element_size(&self, element_size: f64) -> Result<Scene, SceneError> {
        self.variant(|r| r.fem.element_size = element_size)
    }

    /// The same scene on the FE domain `x_range` × `y_range` [m] (the interface row stays at y = 0).
    pub fn with_domain(&self, x_range: [f64; 2], y_range: [f64; 2]) -> Result<Scene, SceneError> {
        self.variant(|r| {
            r.fem.x_range = x_range;
            r.fem.y_range = y_range;
        })
    }

    /// The same scene with or without the mode-II part of u_y in the boundary field (paper
    /// eq. C.9 drops it; with it the field is an exact elastic solution).
    pub fn with_mode_ii_uy(&self, exact: bool) -> Result<Scene, SceneError> {
        self.variant(|r| r.fem.mode_ii_uy = Some(exact))
    }

    /// The same scene with contact penalties ε_n, ε_t [Pa/m] (the stable step follows, eq. 12).
    pub fn with_penalties(&self, eps_n: f64, eps_t: f64) -> Result<Scene, SceneError> {
        self.variant(|r| {
            r.fem.eps_n = Some(eps_n);
            r.fem.eps_t = Some(eps_t);
        })
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

    /// Plane-strain wave speeds of `[material]` [m/s] (with `[fem.mesh.materials]`, of the
    /// elements without a material of their own; with a split `[material]`, of the top body,
    /// `[material.top]`; [`Scene::materials`] lists every material).
    pub fn wave_speeds(&self) -> WaveSpeeds {
        self.material.wave_speeds()
    }

    /// The material of the body below the interface row: `[material.bottom]` of a split
    /// `[material]`, else `material` itself.
    pub fn material_below(&self) -> PlaneStrain {
        self.bottom_material.unwrap_or(self.material)
    }

    /// Whether node-to-segment contact runs (hybrid model with a pre-crack or a cohesive interface).
    pub fn has_contact(&self) -> bool {
        self.fem.model == ModelKind::Hybrid && (self.crack.is_some() || self.interface.is_some())
    }

    /// Whether a penalty (contact or standard compression penalty) limits the step.
    fn has_penalty(&self) -> bool {
        self.has_contact() || (self.fem.model == ModelKind::Standard && self.interface.is_some())
    }

    /// Largest stable step [s]: docs/fem-model.md §2 with α = 0.95 (the largest allowed safety factor).
    /// With several materials (`[fem.mesh.materials]`), the smallest over the elements of
    /// α h_e/c_d,e · f(ε h_e/E_e), each element with its own length and material: per material
    /// that is its shortest element's, since h f(εh/E) grows with h.
    /// On the built-in grid with a split `[material]`, the smaller of the two materials' at the
    /// grid's shortest edge: the faster material's, up to the penalty factor.
    pub fn stable_limit(&self) -> f64 {
        match self.fem.mesh.as_ref().filter(|m| !m.materials.is_empty()) {
            None => match &self.bottom_material {
                None => self.stable_limit_of(&self.material, self.fem.min_edge()),
                Some(bottom) => self
                    .stable_limit_of(&self.material, self.fem.min_edge())
                    .min(self.stable_limit_of(bottom, self.fem.min_edge())),
            },
            Some(m) => std::iter::once(&self.material)
                .chain(&m.materials)
                .zip(&m.min_length)
                .filter(|(_, h)| h.is_finite())
                .map(|(mat, &h)| self.stable_limit_of(mat, h))
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The stable step [s] of elements of `material` and length `h` [m].
    fn stable_limit_of(&self, material: &PlaneStrain, h: f64) -> f64 {
        let beta_p = if self.has_penalty() {
            self.fem.eps_n.max(self.fem.eps_t) * h / material.youngs_modulus
        } else {
            0.0
        };
        crate::law::elastic::stable_time_step(fem::MAX_SAFETY, h, material.wave_speeds().cd, beta_p)
    }

    /// Every bulk material of the scene: `[material]` (the top one of a split table), then
    /// `[material.bottom]` or those of `[fem.mesh.materials]` (element material index k is the k-th).
    pub fn materials(&self) -> Vec<PlaneStrain> {
        let mut out = vec![self.material];
        out.extend(self.bottom_material);
        if let Some(m) = &self.fem.mesh {
            out.extend(&m.materials);
        }
        out
    }

    /// What a valid scene does that its user should know before running it: two bulk
    /// materials that carry no generalized Rayleigh wave (the contrast is past its existence
    /// limit), so that a mode-II tip has no interface wave speed to tend to.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if let Some(b) = &self.bottom_material
            && !crate::law::elastic::slip_wave_exists(&self.material, b)
        {
            w.push(format!(
                "material: no generalized Rayleigh wave exists between the top and bottom \
                 materials (c_s = {:.4e} and {:.4e} m/s; the contrast is past its existence \
                 limit): a mode-II tip has no interface wave speed below the slower c_s to tend to",
                self.material.wave_speeds().cs,
                b.wave_speeds().cs
            ));
        }
        if self.fem.output_interval < self.time_step {
            w.push(format!(
                "fem.output_interval = {:e} s is below the time step {:e} s: records are taken at \
                 most once per step, so every step is recorded",
                self.fem.output_interval, self.time_step
            ));
        }
        w
    }

    /// Index of the grid's node row on the interface, y = 0, counted from the bottom row [-].
    pub(crate) fn interface_row(&self) -> usize {
        (-self.fem.y_range[0] / self.fem.element_size).round() as usize
    }

    /// Whether the bulk has several materials (`[fem.mesh.materials]` or a split `[material]`).
    pub fn has_several_materials(&self) -> bool {
        self.bottom_material.is_some() || self.fem.mesh.as_ref().is_some_and(|m| !m.materials.is_empty())
    }
}

/// A ramp of `[loading]`; `field` is its key (`loading.normal`); none given is zero.
fn ramp(field: &str, r: Option<RawRamp>, duration: f64) -> Result<Ramp, SceneError> {
    r.map_or(Ok(Ramp::ZERO), |r| checks::ramp(field, &r, duration))
}

fn interface(i: &raw::RawInterface) -> Result<LinearCohesive, SceneError> {
    checks::cohesive_law("interface", [i.sigma_c, i.delta_c, i.beta, i.kappa])
}

fn crack(c: &raw::RawCrack) -> Result<Crack, SceneError> {
    check("crack.half_length", c.half_length, c.half_length > 0.0, "> 0 m")?;
    check("crack.center_x", c.center_x, true, "a finite number")?;
    Ok(Crack {
        half_length: c.half_length,
        center_x: c.center_x,
    })
}

/// Validates every section, collecting the problems of each (one invalid key does not hide the
/// next); returns them all as `SceneError::Invalid`, or the single one alone.
fn validate(raw: RawScene) -> Result<Scene, SceneError> {
    let kept = raw.clone();
    let mut errors = Vec::new();
    let material = material::materials(&raw.material, raw.fem.mesh.is_some(), &mut errors);
    let interface = keep(&mut errors, raw.interface.as_ref().map(interface).transpose());
    let crack = keep(&mut errors, raw.crack.as_ref().map(crack).transpose());
    let friction_coeff = raw.friction.as_ref().map_or(0.0, |f| f.friction_coeff);
    keep(
        &mut errors,
        check(
            "friction.friction_coeff",
            friction_coeff,
            (0.0..=10.0).contains(&friction_coeff),
            "[0, 10]",
        ),
    );
    let contact_friction = keep(
        &mut errors,
        interface_spec::contact_friction(raw.friction.as_ref()),
    );
    let l = &raw.loading;
    let duration = keep(
        &mut errors,
        check("loading.duration", l.duration, l.duration > 0.0, "> 0 s"),
    );
    // the ramps and [fem] are checked against T; without a valid T, against no limit
    let t_end = duration.unwrap_or(f64::INFINITY);
    let normal = keep(&mut errors, ramp("loading.normal", l.normal, t_end));
    let shear = keep(&mut errors, ramp("loading.shear", l.shear, t_end));
    // a crack that failed its own checks is not used to check the mesh against it
    let crack_for_fem = match (&raw.crack, &crack) {
        (Some(_), None) => None,
        (_, c) => Some(c.as_ref().and_then(|c| c.as_ref())),
    };
    if crack_for_fem.is_none() {
        fem::check_fem_alone(&raw.fem, t_end, &mut errors);
    }
    let fem = crack_for_fem.and_then(|c| {
        fem::validate_fem(
            &raw.fem,
            c,
            raw.interface.is_some(),
            raw.base_dir.as_deref(),
            t_end,
            &mut errors,
        )
    });
    let (
        Some(material),
        Some(interface),
        Some(crack),
        Some(normal),
        Some(shear),
        Some(fem),
        Some(duration),
        Some(contact_friction),
    ) = (
        material,
        interface,
        crack,
        normal,
        shear,
        fem,
        duration,
        contact_friction,
    )
    else {
        return Err(collected(errors));
    };
    let (material, bottom_material) = material;
    let mut scene = Scene {
        name: raw.name.unwrap_or_else(|| "unnamed".to_string()),
        material,
        bottom_material,
        interface,
        crack,
        friction_coeff,
        contact_friction,
        loading: Loading {
            duration,
            normal,
            shear,
        },
        fem,
        time_step: 0.0,
        raw: kept,
    };
    cross_checks(&mut scene, duration, &mut errors);
    if errors.is_empty() {
        Ok(scene)
    } else {
        Err(collected(errors))
    }
}

/// The most steps a scene may ask for: far beyond any budget (the default is 10⁸), and within
/// what a step counter and an f64 time hold exactly (2⁵³ ≈ 9e15).
const MAX_STEPS_EVER: f64 = 1e15;

/// The checks across sections, once each section is valid: zones need an `[interface]`, a penalty
/// needs ε_n > 0, a requested Δt [s] must be stable (else the step is α/α_max of the limit), and
/// ParaView's files over the `duration` [s] must stay within their limit.
fn cross_checks(scene: &mut Scene, duration: f64, errors: &mut Vec<SceneError>) {
    if let Some(bottom) = scene.bottom_material {
        let top = scene.material;
        // the Westergaard field and the far field's motion depend on E and ν alone: with the
        // same elastic constants on both sides (a contrast in ρ only) they are exact as they are
        if (bottom.youngs_modulus, bottom.poisson_ratio) != (top.youngs_modulus, top.poisson_ratio) {
            keep(errors, material::split_boundary(scene.fem.boundary.as_ref()));
        }
        keep(
            errors,
            material::well_posed(&top, &bottom, scene.friction_coeff, scene.fem.t_star),
        );
    }
    if !scene.fem.interface_zones.is_empty() && scene.interface.is_none() {
        errors.push(checks::inconsistent(
            "fem.interface_zones",
            "needs an [interface] section (the law outside the zones)",
        ));
    }
    if scene.has_penalty() && scene.fem.eps_n <= 0.0 {
        errors.push(SceneError::OutOfRange {
            field: "fem.eps_n".to_string(),
            value: scene.fem.eps_n,
            allowed: "> 0 Pa/m when contact or the standard penalty is active".to_string(),
        });
    }
    let limit = scene.stable_limit();
    scene.time_step = match scene.fem.requested_time_step {
        Some(dt) if dt > limit => {
            errors.push(SceneError::UnstableTimeStep {
                dt_s: dt,
                limit_s: limit,
            });
            dt
        }
        Some(dt) => dt,
        None => limit * scene.fem.time_step_safety / fem::MAX_SAFETY,
    };
    // a step so small that no run could take T/Δt of them (Δt = 0 under an absurd penalty, or a
    // count beyond what a step counter holds) is refused here, naming what makes it small, not
    // later by the budget with advice no run could follow
    let steps = duration / scene.time_step;
    if !(scene.time_step > 0.0 && steps <= MAX_STEPS_EVER) {
        let penalty = scene.fem.eps_n.max(scene.fem.eps_t);
        let key = match (scene.has_penalty(), scene.fem.eps_t > scene.fem.eps_n) {
            (true, false) if penalty * scene.fem.min_edge() > scene.material.youngs_modulus => "fem.eps_n",
            (true, true) if penalty * scene.fem.min_edge() > scene.material.youngs_modulus => "fem.eps_t",
            _ if scene.fem.requested_time_step.is_some() => "fem.time_step",
            _ => "fem.element_size",
        };
        errors.push(checks::inconsistent(
            key,
            format!(
                "the time step would be {:e} s, {steps:.3e} steps over loading.duration = {duration} s \
                 (at most {MAX_STEPS_EVER:e}); Δt = α h/c_d · f(β_p) with β_p = max(ε_n, ε_t) h/E \
                 (docs/fem-model.md §2)",
                scene.time_step
            ),
        ));
    }
    if let Some(p) = &scene.fem.paraview {
        let pieces = if scene.crack.is_some() || scene.interface.is_some() {
            2
        } else {
            1
        };
        keep(errors, paraview::file_count(p, duration, scene.time_step, pieces));
    }
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

    /// `[friction] contact_friction`: all_faces by default, failed_only on request, anything else
    /// refused naming the key; the old `[fem]` key is refused naming where it went, and a variant
    /// changes the rule without touching μ.
    #[test]
    fn the_friction_rule_is_a_key_of_the_shared_problem() {
        let s = Scene::from_toml_str(&center_crack()).unwrap();
        assert_eq!(s.contact_friction, ContactFriction::AllFaces);
        let text = center_crack().replace("contact_friction = \"all_faces\"", "contact_friction = \"some\"");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(
            e.contains("friction.contact_friction") && e.contains("failed_only"),
            "{e}"
        );
        let old = center_crack()
            .replace("contact_friction = \"all_faces\"", "")
            .replacen("\n[fem] ", "\n[fem]\ncontact_friction = \"failed_only\"\n# ", 1);
        let e = Scene::from_toml_str(&old).unwrap_err().to_string();
        assert!(
            e.contains("fem.contact_friction") && e.contains("moved to [friction]"),
            "{e}"
        );
        let v = s.with_contact_friction(ContactFriction::FailedOnly).unwrap();
        assert_eq!(v.contact_friction, ContactFriction::FailedOnly);
        assert_eq!(v.friction_coeff, s.friction_coeff);
        let back = v.with_friction_coeff(0.1).unwrap();
        assert_eq!(
            back.contact_friction,
            ContactFriction::FailedOnly,
            "μ changes keep the rule"
        );
    }

    #[test]
    fn bad_values_name_the_field() {
        let text = center_crack().replace("poisson_ratio = 0.35", "poisson_ratio = 0.6");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("material.poisson_ratio") && e.contains("0.6"), "{e}");
        let text = center_crack().replace("time_step_safety = 0.5", "time_step = 1e-5");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("fem.time_step") && e.contains("stable limit"), "{e}");
        let text = center_crack().replace("element_size = 1e-3", "element_size = 0.7e-3");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(
            e.contains("fem.element_size") && e.contains("not a multiple"),
            "{e}"
        );
        let text = center_crack().replace("half_length = 0.125", "half_length = 0.1255");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("crack tip"), "{e}");
        let text = center_crack().replace("model = \"hybrid\"", "model = \"hybird\"");
        let e = Scene::from_toml_str(&text).unwrap_err().to_string();
        assert!(e.contains("fem.model"), "{e}");
        for bad in ["-1e-5", "inf", "nan"] {
            let text = center_crack().replace("\n[fem]", &format!("\n[fem]\nt_star = {bad}"));
            let e = Scene::from_toml_str(&text).unwrap_err().to_string();
            assert!(e.contains("fem.t_star") && e.contains(">= 0 s"), "{bad}: {e}");
        }
        let text = center_crack().replace("\n[fem]", "\n[fem]\nt_star = 2e-5");
        assert_eq!(Scene::from_toml_str(&text).unwrap().fem.t_star, 2e-5);
        let text = center_crack().replace("[fem]", "[fem]\nunknown_key = 1");
        assert!(Scene::from_toml_str(&text).is_err());
    }

    #[test]
    fn variants_are_validated_like_the_file() {
        let s = Scene::from_toml_str(&center_crack()).unwrap();
        let v = s.with_friction_coeff(0.0).unwrap();
        assert_eq!(v.friction_coeff, 0.0);
        assert_eq!(v.time_step(), s.time_step());
        let e = s.with_friction_coeff(100.0).unwrap_err().to_string();
        assert!(e.contains("friction.friction_coeff") && e.contains("100"), "{e}");
        // a stiffer penalty lowers the stable step (eq. 12)
        let stiff = s.with_penalties(1000.0 * 70e6, 1000.0 * 70e6).unwrap();
        assert_eq!(stiff.fem.eps_n, 7e10);
        assert!(stiff.time_step() < s.time_step());
        let fine = s.with_element_size(0.5e-3).unwrap();
        // Δt ∝ h f(β_p) with β_p = ε_n h/E (eq. 12): 300 E at h = 0.5 mm gives β_p = 0.15
        let pf = crate::law::elastic::penalty_factor;
        let expect = 0.5 * pf(0.15) / pf(0.3);
        assert!((fine.time_step() / s.time_step() - expect).abs() < 1e-12);
        assert!(
            s.with_element_size(0.7e-3).is_err(),
            "0.7 mm does not fit the domain"
        );
        let big = s.with_domain([-0.5, 0.5], [-0.25, 0.25]).unwrap();
        assert_eq!(big.fem.x_range, [-0.5, 0.5]);
        assert!(
            s.with_domain([-0.5, 0.5], [0.1, 0.25]).is_err(),
            "y = 0 must be inside"
        );
        assert!(s.with_mode_ii_uy(true).unwrap().fem.mode_ii_uy);
        let standard = s.with_model(ModelKind::Standard).unwrap();
        assert_eq!(standard.fem.model, ModelKind::Standard);
        assert_eq!(
            standard.with_model(ModelKind::Hybrid).unwrap().fem.model,
            ModelKind::Hybrid
        );
    }

    #[test]
    fn every_problem_is_reported_at_once_with_its_line() {
        let good = center_crack();
        let line = |needle: &str| good.lines().position(|l| l.starts_with(needle)).unwrap() + 1;
        let text = good
            .replace("poisson_ratio = 0.35", "poisson_ratio = 0.6")
            .replace(
                "element_size = 1e-3",
                "element_sise = 1e-3\nelement_size = 0.7e-3",
            )
            .replace(
                "ramp_start = 0.0, ramp_end = 0.004 }",
                "ramp_start = 0.5, ramp_end = 0.6 }",
            )
            .replace(
                "time_step_safety = 0.5",
                "time_step_safety = 0.5\ntime_step = 1e-6",
            );
        let e = Scene::from_toml_str(&text).unwrap_err();
        let SceneError::Invalid { problems } = &e else {
            panic!("expected every problem: {e}");
        };
        let keys: Vec<&str> = problems.iter().map(|p| p.key.as_str()).collect();
        for key in [
            "material.poisson_ratio",
            "loading.normal.ramp_start",
            "fem.element_sise",
            "fem.element_size",
            "fem.time_step",
        ] {
            assert!(keys.contains(&key), "{key} missing from {keys:?}");
        }
        let p = problems
            .iter()
            .find(|p| p.key == "material.poisson_ratio")
            .unwrap();
        assert_eq!(p.line, Some(line("poisson_ratio")), "{e}");
        let p = problems.iter().find(|p| p.key == "fem.element_sise").unwrap();
        assert_eq!(
            p.line,
            Some(line("element_size")),
            "the unknown key on the user's line: {e}"
        );
        assert!(e.to_string().contains("unknown key fem.element_sise"), "{e}");
        // in the order of the file
        let lines: Vec<usize> = problems.iter().filter_map(|p| p.line).collect();
        assert!(lines.windows(2).all(|w| w[0] <= w[1]), "{lines:?}");
    }
}
