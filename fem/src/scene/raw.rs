//! The TOML form of a scene (serde); no physics, no checks. Unknown keys are collected while
//! parsing (`preflight::parse`, in `Scene::from_toml_str`) so that all of them are reported at once.

use serde::Deserialize;

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawScene {
    pub name: Option<String>,
    pub material: RawMaterialTable,
    pub interface: Option<RawInterface>,
    pub crack: Option<RawCrack>,
    pub friction: Option<RawFriction>,
    pub loading: RawLoading,
    pub fem: RawFem,
    /// Owned by the spectral model: accepted, not read.
    #[allow(dead_code)]
    pub spectral: Option<toml::Value>,
    /// Owned by the compare harness: accepted, not read.
    #[allow(dead_code)]
    pub compare: Option<toml::Value>,
    /// Folder that relative paths in the scene (`fem.mesh.file`) are resolved against: the scene
    /// file's folder, or the working directory for a scene given as text. Not a key.
    #[serde(skip)]
    pub base_dir: Option<std::path::PathBuf>,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawMaterial {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
}

/// `[material]`: the three flat keys (one material everywhere) or the two subtables `top` and
/// `bottom` (the bodies above and below the interface row). Every key is optional in the form so
/// that a missing one is reported by name with the other problems (`scene/material.rs`).
#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawMaterialTable {
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
    pub density: Option<f64>,
    pub top: Option<RawMaterialHalf>,
    pub bottom: Option<RawMaterialHalf>,
}

/// `[material.top]` or `[material.bottom]`.
#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawMaterialHalf {
    pub youngs_modulus: Option<f64>,
    pub poisson_ratio: Option<f64>,
    pub density: Option<f64>,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawInterface {
    pub sigma_c: f64,
    pub delta_c: f64,
    pub beta: f64,
    pub kappa: f64,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawCrack {
    pub half_length: f64,
    pub center_x: f64,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawFriction {
    pub friction_coeff: f64,
    pub contact_friction: Option<String>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawRamp {
    pub initial: f64,
    #[serde(rename = "final")]
    pub final_: f64,
    pub ramp_start: f64,
    pub ramp_end: f64,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawLoading {
    pub duration: f64,
    pub normal: Option<RawRamp>,
    pub shear: Option<RawRamp>,
}

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawBoundaryComponent {
    pub kind: String,
    pub initial: f64,
    #[serde(rename = "final")]
    pub final_: f64,
    pub ramp_start: f64,
    pub ramp_end: f64,
}

#[derive(Debug, Clone, Default, Deserialize)]
pub(crate) struct RawSide {
    pub x: Option<RawBoundaryComponent>,
    pub y: Option<RawBoundaryComponent>,
    /// A uniform pressure [Pa] along the outward normal, pushing into the body.
    pub pressure: Option<RawRamp>,
    /// Viscous dashpots that let waves out (Lysmer–Kuhlemeyer).
    pub absorbing: Option<bool>,
    /// The traction of the far-field stress of `[loading]`.
    pub far_field: Option<bool>,
}

/// `[fem.boundary]`: per side of the built-in grid (`bottom`, `right`, `top`, `left`) or per
/// physical curve of a `[fem.mesh]` file, by name.
pub(crate) type RawBoundary = std::collections::BTreeMap<String, RawSide>;

#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawFem {
    /// NaN when not given (required without `[fem.mesh]`, refused with it).
    #[serde(default = "nan2")]
    pub x_range: [f64; 2],
    #[serde(default = "nan2")]
    pub y_range: [f64; 2],
    #[serde(default = "nan")]
    pub element_size: f64,
    pub mesh: Option<RawMesh>,
    pub model: Option<String>,
    pub time_step_safety: Option<f64>,
    pub time_step: Option<f64>,
    pub eps_n: Option<f64>,
    pub eps_t: Option<f64>,
    pub t_star: Option<f64>,
    pub lateral_contraction: Option<bool>,
    pub mode_ii_uy: Option<bool>,
    pub output_interval: f64,
    pub insertion_rule: Option<String>,
    pub damping: Option<String>,
    pub damping_factor: Option<f64>,
    pub damping_time: Option<f64>,
    pub damping_window: Option<f64>,
    pub max_gap: Option<f64>,
    pub projection_tolerance: Option<f64>,
    pub upper_offset: Option<f64>,
    pub interface_polyline: Option<Vec<[f64; 2]>>,
    pub interface_sine: Option<RawSine>,
    pub interface_rough: Option<RawRough>,
    pub interface_zones: Option<Vec<RawZone>>,
    pub contact_surface: Option<String>,
    pub residual_stress_x: Option<[f64; 2]>,
    pub kkt_metric: Option<bool>,
    pub snapshot_times: Option<Vec<f64>>,
    pub snapshot_window: Option<[[f64; 2]; 2]>,
    pub probes: Option<Vec<[f64; 2]>>,
    pub boundary: Option<RawBoundary>,
    pub paraview: Option<RawParaview>,
}

fn nan() -> f64 {
    f64::NAN
}

fn nan2() -> [f64; 2] {
    [f64::NAN; 2]
}

/// `[fem.mesh]`: a Gmsh mesh and the roles of its physical groups.
#[derive(Debug, Clone, Deserialize)]
pub(crate) struct RawMesh {
    /// Optional in the form so that a misspelt key is reported as unknown, next to this one missing.
    pub file: Option<String>,
    pub bulk: Option<Vec<String>>,
    pub pre_crack: Option<Vec<String>>,
    pub interface: Option<Vec<String>>,
    /// Length of one unit of the file's coordinates [m] (default 1; 1e-3 for millimetres).
    pub unit: Option<f64>,
    /// Per interface curve, by name: its own cohesive law.
    pub laws: Option<std::collections::BTreeMap<String, RawInterface>>,
    /// Per bulk surface, by name: its own material.
    pub materials: Option<std::collections::BTreeMap<String, RawMaterial>>,
}

/// `[fem.paraview]`: ParaView field snapshots.
#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawParaview {
    /// Optional in the form so that a misspelt key is reported as unknown, next to this one missing.
    pub interval: Option<f64>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawSine {
    pub amplitude: f64,
    pub half_period: f64,
    pub from: f64,
    pub to: f64,
}

/// `fem.interface_rough`: a self-affine profile (`scene/rough.rs`). The seed is read as a signed
/// TOML integer so that a negative one is reported naming its key, not as a type error.
#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawRough {
    pub hurst: f64,
    pub rms_slope: f64,
    pub seed: i64,
    pub from: f64,
    pub to: f64,
    pub wavelength_min: f64,
    pub wavelength_max: f64,
    pub taper: Option<f64>,
}

#[derive(Debug, Clone, Copy, Deserialize)]
pub(crate) struct RawZone {
    pub x_range: [f64; 2],
    pub sigma_c: f64,
    pub delta_c: f64,
    pub beta: f64,
    pub kappa: f64,
}
