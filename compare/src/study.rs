//! The scene read once: the file is parsed into the FE scene, the spectral scene (when the file
//! has a `[spectral]` section) and the harness's own `[compare]` section. Every run of a study is
//! derived from these typed values (`fem::Scene::with_friction_coeff`, ...), never by rewriting
//! the TOML text, so errors quote the user's own lines.

use crate::series::Tip;
use anyhow::{Context, Result, anyhow, bail};
use preflight::Problem;
use serde::Deserialize;
use std::path::Path;

/// An FE model the Section 4 study runs (`[compare].models`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelName {
    /// Contact through the cohesive law (paper eq. 4).
    Standard,
    /// Node-to-segment contact (paper §2).
    Hybrid,
}

impl ModelName {
    /// The name as written in a scene and in file names.
    pub fn tag(self) -> &'static str {
        match self {
            ModelName::Standard => "standard",
            ModelName::Hybrid => "hybrid",
        }
    }

    /// The FE model kind.
    pub fn kind(self) -> fem::scene::ModelKind {
        match self {
            ModelName::Standard => fem::scene::ModelKind::Standard,
            ModelName::Hybrid => fem::scene::ModelKind::Hybrid,
        }
    }
}

/// Where contact friction acts, in both models (`[friction] contact_friction`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrictionRule {
    /// On every closed face, partly damaged cohesive ones included, on top of the cohesive
    /// shear: the hybrid model of the paper (§2.3, Fig. 4d).
    AllFaces,
    /// Only where the interface has fully failed.
    FailedOnly,
}

impl FrictionRule {
    /// The rule's name in a scene and in folder names.
    pub fn name(self) -> &'static str {
        match self {
            FrictionRule::AllFaces => "all_faces",
            FrictionRule::FailedOnly => "failed_only",
        }
    }

    fn fem(self) -> fem::scene::ContactFriction {
        match self {
            FrictionRule::AllFaces => fem::scene::ContactFriction::AllFaces,
            FrictionRule::FailedOnly => fem::scene::ContactFriction::FailedOnly,
        }
    }

    fn spectral(self) -> spectral::ContactFriction {
        match self {
            FrictionRule::AllFaces => spectral::ContactFriction::AllFaces,
            FrictionRule::FailedOnly => spectral::ContactFriction::FailedOnly,
        }
    }
}

/// The `[compare]` section: what the harness's jobs run. Unknown keys are refused (with the
/// other problems of the file).
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
pub struct CompareSection {
    /// Friction coefficients the FE-versus-spectral gate runs [-].
    pub friction_coeffs: Option<Vec<f64>>,
    /// FE models the Section 4 study runs, in order.
    pub models: Option<Vec<ModelName>>,
    /// Time of the Section 4 maps and profiles over T [-].
    #[serde(rename = "snapshot_t_over_T")]
    pub snapshot_t_over_t: Option<f64>,
}

/// The parts of the file the harness reads itself; everything else belongs to the models.
#[derive(Debug, Deserialize)]
struct HarnessPart {
    compare: Option<CompareSection>,
    spectral: Option<serde::de::IgnoredAny>,
}

/// Scale quantities of a scene, from its FE scene.
#[derive(Debug, Clone, Copy)]
pub struct Case {
    /// Pre-crack half-length a [m].
    pub half_length: f64,
    /// Pre-crack centre x [m].
    pub center_x: f64,
    /// Run duration T [s].
    pub duration: f64,
    /// Dilatational wave speed c_d [m/s].
    pub cd: f64,
    /// Rayleigh wave speed c_R [m/s].
    pub cr: f64,
    /// Far-field normal stress after its ramp, s_yy [Pa] (negative in compression).
    pub normal_stress: f64,
    /// Two different half-spaces (`[material.top]` and `[material.bottom]`); `None`: one material.
    pub bimaterial: Option<Pair>,
}

/// Wave speeds of one half-space [m/s] and its shear modulus [Pa].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waves {
    /// Dilatational speed c_d [m/s].
    pub cd: f64,
    /// Shear speed c_s [m/s].
    pub cs: f64,
    /// Shear modulus μ [Pa].
    pub shear_modulus: f64,
}

/// The two half-spaces of a bimaterial scene and their generalized Rayleigh speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pair {
    /// The top half-space (y > 0).
    pub top: Waves,
    /// The bottom half-space (y < 0).
    pub bottom: Waves,
    /// c_GR [m/s]; `None` when the contrast is past the wave's existence limit.
    pub generalized_rayleigh: Option<f64>,
}

impl Pair {
    /// From the spectral scene's two solids (the FE scene reads the same `[material]` tables).
    pub fn new(top: spectral::Solid, bottom: spectral::Solid) -> Pair {
        let waves = |s: spectral::Solid| Waves {
            cd: s.wave_speeds().cd,
            cs: s.wave_speeds().cs,
            shear_modulus: s.shear_modulus(),
        };
        let half = |s: spectral::Solid| {
            crate::theory::bimaterial::HalfSpace::new(s.poisson_ratio, s.shear_modulus(), s.density)
        };
        let generalized_rayleigh = match (half(top), half(bottom)) {
            (Some(a), Some(b)) => crate::theory::bimaterial::generalized_rayleigh_speed(&a, &b),
            _ => None,
        };
        Pair {
            top: waves(top),
            bottom: waves(bottom),
            generalized_rayleigh,
        }
    }

    /// The slower shear speed [m/s].
    pub fn slower_cs(&self) -> f64 {
        self.top.cs.min(self.bottom.cs)
    }

    /// The tip that runs in the direction of slip of the more compliant body, the one with the
    /// lower shear-wave speed, under a far-field shear of sign `shear_sign`: with s_xy > 0 the
    /// top body slides in +x against the bottom one, so a compliant top makes it the right tip,
    /// a compliant bottom the left.
    pub fn positive_tip(&self, shear_sign: f64) -> Tip {
        let top_compliant = self.top.cs < self.bottom.cs;
        match (top_compliant, shear_sign > 0.0) {
            (true, true) | (false, false) => Tip::Right,
            _ => Tip::Left,
        }
    }
}

impl Case {
    /// The a/c_d time shift [s] applied to the spectral curves (paper Figure 7b): the time a
    /// dilatational wave needs from the FE model's top boundary (y = a) to the crack plane. With
    /// two materials the top and bottom boundaries' waves arrive at a/c_d⁺ and a/c_d⁻; the shift
    /// is their mean.
    pub fn shift(&self) -> f64 {
        match &self.bimaterial {
            None => self.half_length / self.cd,
            Some(p) => 0.5 * (self.half_length / p.top.cd + self.half_length / p.bottom.cd),
        }
    }
}

/// Every problem the harness found in a scene, each with its key and line; displayed as
/// [`preflight::problems_text`] words them. The error [`Study::from_toml_str_in`] returns when
/// the scene's values are refused (callers may downcast to it for the keys).
#[derive(Debug, Clone)]
pub struct Problems(pub Vec<Problem>);

impl std::fmt::Display for Problems {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&preflight::problems_text(&self.0))
    }
}

impl std::error::Error for Problems {}

/// A scene file, read once.
#[derive(Debug, Clone)]
pub struct Study {
    /// File name without extension: the default output folder's name.
    pub stem: String,
    /// The FE scene.
    pub fem: fem::Scene,
    /// The spectral scene (`None`: the file has no `[spectral]` section).
    pub spectral: Option<spectral::Scene>,
    /// The `[compare]` section (all keys absent when the file has none).
    pub compare: CompareSection,
    /// The most one run may cost (command-line flags; 8 GiB and 10⁸ steps by default).
    pub budget: preflight::Budget,
    /// How many runs go at once (command-line flag; `None`: one per core, see
    /// [`crate::concurrent::Lanes`]).
    pub concurrent_runs: Option<usize>,
}

impl Study {
    /// Reads and parses the scene file at `path`.
    pub fn load(path: &Path) -> Result<Study> {
        Study::read(path).map(|(study, _)| study)
    }

    /// Reads and parses the scene file at `path`, and returns its text too (read once, so the
    /// text is exactly the one the study was parsed from).
    pub fn read(path: &Path) -> Result<(Study, String)> {
        let text = preflight::input::Cap::scene()
            .and_then(|cap| preflight::input::read_text_capped(path, cap))
            .with_context(|| format!("reading {}", path.display()))?;
        let stem = path
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
        let dir = path.parent().unwrap_or(Path::new("."));
        let study = Study::from_toml_str_in(&text, &stem, Some(dir))
            .with_context(|| format!("scene {}", path.display()))?;
        Ok((study, text))
    }

    /// Parses scene `text`; `stem` names the default output folder. Every part the harness will
    /// run is validated here, before any work: the FE scene, the spectral scene (if the file has
    /// `[spectral]`), every `[compare]` key, and every friction value listed for both models. All
    /// problems are reported at once, each with its key and its line in `text`; a key both models
    /// read is reported once.
    pub fn from_toml_str(text: &str, stem: &str) -> Result<Study> {
        Study::from_toml_str_in(text, stem, None)
    }

    /// As [`Study::from_toml_str`], with relative paths in the scene (the FE mesh file) taken from
    /// `dir` (the scene file's folder; `None`: the working directory).
    pub fn from_toml_str_in(text: &str, stem: &str, dir: Option<&Path>) -> Result<Study> {
        let mut problems: Vec<Problem> = Vec::new();
        let fem = match dir {
            Some(d) => fem::Scene::from_toml_str_in(text, d),
            None => fem::Scene::from_toml_str(text),
        };
        let fem = match fem {
            Ok(s) => Some(s),
            Err(fem::SceneError::Parse(m)) => bail!("scene does not parse: {m}"),
            Err(e) => {
                problems.extend(e.problems());
                None
            }
        };
        if fem
            .as_ref()
            .is_some_and(|f| f.fem.mesh.as_ref().is_some_and(|m| !m.materials.is_empty()))
        {
            bail!(
                "fem.mesh.materials gives the bulk several materials, and the spectral model the \
                 harness compares with has one material per half-space ([material], or \
                 [material.top] and [material.bottom]): the comparison would not be of one problem \
                 (run the scene with the fem binary alone)"
            );
        }
        let (harness, unknown) =
            preflight::parse::<HarnessPart>(text).map_err(|m| anyhow!("[compare] does not parse: {m}"))?;
        // the harness reads only [compare]: keys it does not know elsewhere belong to the models
        problems.extend(preflight::unknown_keys(
            unknown
                .into_iter()
                .filter(|k| k.starts_with("compare."))
                .collect(),
        ));
        let spectral = match harness.spectral.map(|_| spectral::Scene::from_toml_str(text)) {
            None => None,
            Some(Ok(s)) => Some(s),
            Some(Err(e)) => {
                for p in e.problems() {
                    if !problems.iter().any(|q| q.key == p.key) {
                        problems.push(p);
                    }
                }
                None
            }
        };
        let compare = harness.compare.unwrap_or_default();
        // [compare]'s own problems are reported with the models' (each value's fit to the
        // models only once the FE scene is valid)
        problems.extend(compare_problems(&compare, fem.as_ref(), spectral.as_ref()));
        match (fem, problems.is_empty()) {
            (Some(fem), true) => Ok(Study {
                stem: stem.to_string(),
                fem,
                spectral,
                compare,
                budget: preflight::Budget::default(),
                concurrent_runs: None,
            }),
            _ => {
                preflight::locate(text, &mut problems);
                Err(Problems(problems).into())
            }
        }
    }

    /// The same study at nominal element size h [m]: the FE model at h = a/round(a/h) (the
    /// pre-crack tips stay on nodes), the spectral model (if any) on the power-of-two grid
    /// nearest its periodic length over h. Both are validated again.
    pub fn at_resolution(&self, nominal: f64) -> Result<Study> {
        let h = fem_size(self.fem.half_length(), nominal);
        let fem = self
            .fem
            .with_element_size(h)
            .with_context(|| format!("the FE model at h = {h:e} m"))?;
        let spectral = self
            .spectral
            .as_ref()
            .map(|s| {
                let n = spectral_points(s.length, nominal);
                s.with_grid_points(n)
                    .with_context(|| format!("the spectral model on N = {n} points"))
            })
            .transpose()?;
        Ok(Study {
            fem,
            spectral,
            ..self.clone()
        })
    }

    /// The same study with friction acting where `rule` says, in both models (`[friction]
    /// contact_friction`, which both read). Both scenes are validated again.
    pub fn with_friction_rule(&self, rule: FrictionRule) -> Result<Study> {
        let fem = self.fem.with_contact_friction(rule.fem())?;
        let spectral = self
            .spectral
            .as_ref()
            .map(|s| s.with_contact_friction(rule.spectral()))
            .transpose()?;
        Ok(Study {
            fem,
            spectral,
            ..self.clone()
        })
    }

    /// The spectral scene, which jobs comparing the two models need.
    pub fn spectral(&self) -> Result<&spectral::Scene> {
        self.spectral
            .as_ref()
            .ok_or_else(|| anyhow!("[spectral]: missing; this job runs the spectral model"))
    }

    /// Scale quantities of the case.
    pub fn case(&self) -> Case {
        let w = self.fem.wave_speeds();
        Case {
            half_length: self.fem.half_length(),
            center_x: self.fem.center_x(),
            duration: self.fem.duration(),
            cd: w.cd,
            cr: w.cr,
            normal_stress: self.fem.loading.normal.final_value,
            bimaterial: self
                .spectral
                .as_ref()
                .filter(|s| s.is_split())
                .map(|s| Pair::new(s.top(), s.bottom())),
        }
    }

    /// `[compare].friction_coeffs` [-] (validated for both models when the study was read).
    pub fn friction_coeffs(&self) -> Result<Vec<f64>> {
        self.compare
            .friction_coeffs
            .clone()
            .ok_or_else(|| anyhow!("compare.friction_coeffs: missing; expected a list such as [0, 0.3]"))
    }

    /// `[compare].models` (validated when the study was read).
    pub fn models(&self) -> Result<Vec<ModelName>> {
        self.compare.models.clone().ok_or_else(|| {
            anyhow!("compare.models: missing; expected a list such as [\"standard\", \"hybrid\"]")
        })
    }

    /// `[compare].snapshot_t_over_T` [-], in (0, 1] (validated when the study was read).
    pub fn snapshot_t_over_t(&self) -> Result<f64> {
        self.compare
            .snapshot_t_over_t
            .ok_or_else(|| anyhow!("compare.snapshot_t_over_T: missing; expected a number in (0, 1]"))
    }
}

/// The problems of the `[compare]` keys present: friction values each model accepts, listed once;
/// models listed once; a snapshot time inside the run.
fn compare_problems(
    c: &CompareSection,
    fem: Option<&fem::Scene>,
    spectral: Option<&spectral::Scene>,
) -> Vec<Problem> {
    let mut problems = Vec::new();
    if let Some(mus) = &c.friction_coeffs {
        let key = "compare.friction_coeffs";
        if mus.is_empty() {
            problems.push(Problem::new(
                key,
                format!("{key} = []: give at least one friction coefficient"),
            ));
        }
        for (k, &mu) in mus.iter().enumerate() {
            if mus[..k].contains(&mu) {
                problems.push(Problem::new(
                    key,
                    format!("{key}: {mu} is listed twice (each run writes its own folder)"),
                ));
                continue;
            }
            let Some(fem) = fem else { continue };
            let fem_error = fem.with_friction_coeff(mu).err().map(|e| e.to_string());
            let spectral_error = spectral
                .and_then(|s| s.with_friction_coeff(mu).err())
                .map(|e| e.to_string());
            if let Some(e) = fem_error.or(spectral_error) {
                problems.push(Problem::new(key, format!("{key}: {mu} is refused: {e}")));
            }
        }
    }
    if let Some(models) = &c.models {
        let key = "compare.models";
        if models.is_empty() {
            problems.push(Problem::new(key, format!("{key} = []: give at least one model")));
        }
        for (k, m) in models.iter().enumerate() {
            if models[..k].contains(m) {
                problems.push(Problem::new(
                    key,
                    format!(
                        "{key}: \"{}\" is listed twice (each run writes its own folder)",
                        m.tag()
                    ),
                ));
            }
        }
    }
    if let Some(t) = c.snapshot_t_over_t
        && !(t > 0.0 && t <= 1.0)
    {
        problems.push(Problem::new(
            "compare.snapshot_t_over_T",
            format!("compare.snapshot_t_over_T = {t} out of range; allowed (0, 1]"),
        ));
    }
    problems
}

/// FE element size [m] for a nominal one: a/round(a/h), so the pre-crack tips stay on nodes
/// (the nominal h when there is no pre-crack).
pub fn fem_size(a: f64, nominal: f64) -> f64 {
    if a > 0.0 {
        a / (a / nominal).round().max(1.0)
    } else {
        nominal
    }
}

/// Spectral grid points for a nominal spacing [m] over a periodic length [m]: the power of two
/// nearest to length/nominal.
pub fn spectral_points(length: f64, nominal: f64) -> usize {
    let n = (length / nominal).log2().round().clamp(2.0, 30.0) as u32;
    1usize << n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(name: &str) -> String {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"));
        std::fs::read_to_string(path).unwrap()
    }

    /// The harness reports every problem of the scene at once: the shared tables', each model's
    /// own section's and `[compare]`'s, even while the FE scene is refused (whose problems used
    /// to hide `[compare]`'s). Each problem keeps its key (`Problems`).
    #[test]
    fn every_table_is_checked_at_once_with_each_key() {
        let s = text("center-crack")
            .replace("density = 1230.0 ", "density = -1.0 ")
            .replace("half_length = 0.125 ", "half_length = -0.125 ")
            .replace("element_size = 1e-3 ", "element_size = -1e-3 ")
            .replace("grid_points = 4096 ", "grid_points = 3 ")
            .replace("friction_coeffs = [0.0, 0.3]", "friction_coeffs = [0.3, 0.3]");
        let e = Study::from_toml_str(&s, "c").unwrap_err();
        let keys: Vec<String> = e
            .downcast_ref::<Problems>()
            .expect("the problems, typed")
            .0
            .iter()
            .map(|p| p.key.clone())
            .collect();
        for k in [
            "material.density",
            "crack.half_length",
            "fem.element_size",
            "spectral.grid_points",
            "compare.friction_coeffs",
        ] {
            assert!(keys.iter().any(|x| x == k), "{k} not in {keys:?}");
        }
        assert!(
            e.to_string()
                .starts_with(&format!("{} problems in the scene", keys.len()))
        );
    }

    #[test]
    fn the_center_crack_has_both_models_and_two_friction_values() {
        let s = Study::from_toml_str(&text("center-crack"), "center-crack").unwrap();
        assert!(s.spectral.is_some());
        assert_eq!(s.friction_coeffs().unwrap(), vec![0.0, 0.3]);
        let c = s.case();
        assert!(
            (c.shift() / c.duration - 0.02068).abs() < 1e-4,
            "a/c_d = 0.0207 T"
        );
    }

    /// A mesh with several bulk materials is refused: the spectral model has one material per
    /// half-space, so the comparison would not be of one problem. A split `[material]` is taken
    /// by both models, and its case carries the pair.
    #[test]
    fn mesh_materials_are_refused_and_a_split_material_is_compared() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let e = Study::from_toml_str_in(&text("tiny-fem-bimaterial"), "b", Some(&dir)).unwrap_err();
        let e = format!("{e:#}");
        assert!(
            e.contains("fem.mesh.materials") && e.contains("one material per half-space"),
            "{e}"
        );
        let s = Study::from_toml_str(&text("bimaterial-crack"), "b").unwrap();
        let c = s.case();
        let pair = c.bimaterial.expect("a split scene carries its pair");
        assert!((pair.bottom.cs / pair.top.cs - 1.2).abs() < 1e-12);
        // the shift is the mean of the two boundaries' P-wave times
        let expected = 0.5 * (c.half_length / pair.top.cd + c.half_length / pair.bottom.cd);
        assert!((c.shift() - expected).abs() < 1e-15, "{} {expected}", c.shift());
        assert!(c.shift() < c.half_length / c.cd);
    }

    #[test]
    fn the_sinusoid_has_no_spectral_part_and_two_models() {
        let s = Study::from_toml_str(&text("sinusoidal-interface"), "s").unwrap();
        assert!(s.spectral.is_none());
        assert!(s.spectral().unwrap_err().to_string().contains("[spectral]"));
        assert_eq!(s.models().unwrap(), [ModelName::Standard, ModelName::Hybrid]);
        assert!(s.snapshot_t_over_t().unwrap() > 0.0);
    }

    #[test]
    fn bad_compare_keys_are_refused_with_the_users_line() {
        let base = text("center-crack");
        let typo = base.replace("friction_coeffs =", "friction_coefs =");
        let e = format!("{:#}", Study::from_toml_str(&typo, "x").unwrap_err());
        let line = typo.lines().position(|l| l.contains("friction_coefs")).unwrap() + 1;
        assert!(
            e.contains("friction_coefs") && e.contains(&format!("line {line}")),
            "{e}"
        );
        let dup = base.replace("friction_coeffs = [0.0, 0.3]", "friction_coeffs = [0.3, 0.3]");
        let e = Study::from_toml_str(&dup, "x").unwrap_err();
        assert!(e.to_string().contains("twice"), "{e}");
        let big = base.replace("friction_coeffs = [0.0, 0.3]", "friction_coeffs = [0.0, 100.0]");
        let e = format!("{:#}", Study::from_toml_str(&big, "x").unwrap_err());
        assert!(
            e.contains("compare.friction_coeffs: 100") && e.contains("[0, 10]"),
            "{e}"
        );
        let s = text("sinusoidal-interface").replace("\"hybrid\"]", "\"hybird\"]");
        let e = format!("{:#}", Study::from_toml_str(&s, "x").unwrap_err());
        assert!(e.contains("hybird"), "{e}");
    }

    #[test]
    fn sizes_keep_the_crack_tip_on_a_node_and_grids_are_powers_of_two() {
        let a = 0.125;
        assert!((fem_size(a, 4e-3) - a / 31.0).abs() < 1e-15);
        assert!((fem_size(a, 1e-3) - 1e-3).abs() < 1e-15);
        assert_eq!(spectral_points(3.75, 4e-3), 1024);
        assert_eq!(spectral_points(3.75, 1e-3), 4096);
        assert_eq!(spectral_points(3.75, 0.5e-3), 8192);
    }

    #[test]
    fn a_finer_study_refines_both_models() {
        let s = Study::from_toml_str(&text("center-crack"), "c").unwrap();
        let fine = s.at_resolution(0.5e-3).unwrap();
        assert!((fine.fem.fem.element_size - 0.5e-3).abs() < 1e-15);
        assert_eq!(fine.spectral.unwrap().grid_points, 8192);
        assert_eq!(fine.compare, s.compare);
    }
}
