//! `[material]`: one bulk material everywhere (the three flat keys), or a split one, `[material.top]`
//! for the body above the interface row (y > 0) and `[material.bottom]` for the body below
//! (docs/scenes.md, "[material]"). The spectral model reads the same table by the same rules.

use super::boundary::BoundarySpec;
use super::checks::{check, inconsistent};
use super::raw::{RawMaterialHalf, RawMaterialTable};
use crate::error::SceneError;
use crate::law::elastic::PlaneStrain;

/// The bulk materials of `[material]`: (top, `Some(bottom)`) for a split table, (the material,
/// `None`) for the flat one. Every problem found is added to `errors` (then `None`): a flat key
/// next to a subtable, a missing half or key, a value out of range, and a split table on a Gmsh
/// mesh (`on_mesh`), whose bulk surfaces take their materials from `[fem.mesh.materials]`.
pub(crate) fn materials(
    raw: &RawMaterialTable,
    on_mesh: bool,
    errors: &mut Vec<SceneError>,
) -> Option<(PlaneStrain, Option<PlaneStrain>)> {
    let before = errors.len();
    let flat = RawMaterialHalf {
        youngs_modulus: raw.youngs_modulus,
        poisson_ratio: raw.poisson_ratio,
        density: raw.density,
    };
    if raw.top.is_none() && raw.bottom.is_none() {
        let m = half("material", &flat, errors);
        return m.filter(|_| errors.len() == before).map(|m| (m, None));
    }
    let given = if raw.top.is_some() {
        "material.top"
    } else {
        "material.bottom"
    };
    for (key, value) in flat_keys(&flat) {
        if value.is_some() {
            errors.push(inconsistent(
                format!("material.{key}"),
                format!(
                    "given together with {given}: give either the three flat keys (one material \
                     everywhere) or both subtables [material.top] and [material.bottom], not both"
                ),
            ));
        }
    }
    for (name, table, other) in [("top", &raw.top, "bottom"), ("bottom", &raw.bottom, "top")] {
        if table.is_none() {
            errors.push(inconsistent(
                format!("material.{name}"),
                format!(
                    "missing: material.{other} is given, and a split material needs both \
                     [material.top] (y > 0) and [material.bottom] (y < 0)"
                ),
            ));
        }
    }
    if on_mesh {
        errors.push(inconsistent(
            given,
            "a split [material] applies to the built-in grid only; on a Gmsh mesh give the flat \
             [material] and each other bulk surface its own in [fem.mesh.materials]",
        ));
    }
    let top = raw.top.as_ref().and_then(|t| half("material.top", t, errors));
    let bottom = raw
        .bottom
        .as_ref()
        .and_then(|b| half("material.bottom", b, errors));
    match (top, bottom) {
        (Some(t), Some(b)) if errors.len() == before => Some((t, Some(b))),
        _ => None,
    }
}

/// The boundary a split `[material]` needs: `[fem.boundary]` (the default Westergaard field is
/// the field of one homogeneous material) without a far-field part (the far field of `[loading]`,
/// its motion and body load are those of one material, docs/fem-model.md §7), as on a mesh with
/// `[fem.mesh.materials]`.
pub(crate) fn split_boundary(boundary: Option<&BoundarySpec>) -> Result<(), SceneError> {
    let Some(b) = boundary else {
        return Err(inconsistent(
            "fem.boundary",
            "missing: the Westergaard boundary field is the field of one material everywhere, and \
             [material] is split into top and bottom; give [fem.boundary]",
        ));
    };
    match b.curves.iter().find(|c| c.far_field) {
        Some(f) => Err(inconsistent(
            format!("fem.boundary.{}.far_field", f.name),
            "the far field of [loading] is the uniform stress of one material, and [material] is \
             split into top and bottom; load the side by its own traction",
        )),
        None => Ok(()),
    }
}

/// Coulomb friction between two different materials with σ̃ = σ is ill-posed (Adams 1995; Ranjith
/// & Rice 2001): steady sliding is unstable at every wavelength, with growth rates that rise
/// without bound as the wavelength falls, so the answer would follow the mesh. The Prakash law
/// (paper eq. 14) with t* > 0 makes it well-posed: μ > 0 between different halves needs
/// `fem.t_star` > 0 (docs/fem-model.md, "Prakash regularisation").
pub(crate) fn well_posed(
    top: &PlaneStrain,
    bottom: &PlaneStrain,
    friction_coeff: f64,
    t_star: f64,
) -> Result<(), SceneError> {
    if top != bottom && friction_coeff > 0.0 && t_star == 0.0 {
        return Err(inconsistent(
            "fem.t_star",
            format!(
                "0 with friction.friction_coeff = {friction_coeff} between two different \
                 materials: Coulomb friction on a bimaterial interface is ill-posed without \
                 regularisation (Adams 1995; Ranjith & Rice 2001), so the result would depend on \
                 the mesh; give t* > 0 [s] (a few steps or more)"
            ),
        ));
    }
    Ok(())
}

/// The three keys of a material table with their values.
fn flat_keys(m: &RawMaterialHalf) -> [(&'static str, Option<f64>); 3] {
    [
        ("youngs_modulus", m.youngs_modulus),
        ("poisson_ratio", m.poisson_ratio),
        ("density", m.density),
    ]
}

/// The material of the table at `prefix`, each key present and in its range (the ranges of
/// `checks::material`); every problem is added to `errors`.
fn half(prefix: &str, m: &RawMaterialHalf, errors: &mut Vec<SceneError>) -> Option<PlaneStrain> {
    let key = |field: &str| format!("{prefix}.{field}");
    let mut value = |field: &str, v: Option<f64>, ok: fn(f64) -> bool, allowed: &str| match v {
        None => {
            errors.push(inconsistent(key(field), "missing"));
            None
        }
        Some(v) => check(key(field), v, ok(v), allowed)
            .map_err(|e| errors.push(e))
            .ok(),
    };
    let e = value("youngs_modulus", m.youngs_modulus, |e| e > 0.0, "> 0 Pa");
    let nu = value(
        "poisson_ratio",
        m.poisson_ratio,
        |nu| (0.0..0.5).contains(&nu),
        "[0, 0.5)",
    );
    let rho = value("density", m.density, |rho| rho > 0.0, "> 0 kg/m^3");
    Some(PlaneStrain::new(e?, nu?, rho?))
}

#[cfg(test)]
mod tests {
    use crate::scene::Scene;
    use crate::test_scenes::scene_text;

    /// `[material]` of `scenes/tiny-fem-bimaterial-grid.toml`, without its comments.
    const SPLIT: &str = "[material.top]
youngs_modulus = 560e6
poisson_ratio = 0.35
density = 2460.0
[material.bottom]
youngs_modulus = 70e6
poisson_ratio = 0.35
density = 1230.0
";

    /// The split grid scene with `[material]` replaced by `table`.
    fn with_material(table: &str) -> String {
        let text = scene_text("tiny-fem-bimaterial-grid");
        let (start, end) = (
            text.find("\n[material.top]").unwrap(),
            text.find("\n[interface]").unwrap(),
        );
        format!("{}\n{table}\n{}", &text[..start], &text[end..])
    }

    /// The split table gives `material` = top and `bottom_material` = bottom, listed in that
    /// order by `materials()`; the flat table one material, as before.
    #[test]
    fn a_split_table_gives_top_and_bottom() {
        let s = Scene::from_toml_str(&with_material(SPLIT)).unwrap();
        assert_eq!(s.material.youngs_modulus, 560e6);
        assert_eq!(s.material_below().youngs_modulus, 70e6);
        assert_eq!(s.materials().len(), 2);
        assert!(s.has_several_materials());
        let flat = with_material("[material]\nyoungs_modulus = 70e6\npoisson_ratio = 0.35\ndensity = 1230.0");
        let f = Scene::from_toml_str(&flat).unwrap();
        assert!(!f.has_several_materials());
        assert_eq!(f.material_below(), f.material);
    }

    /// Every refusal at once, each naming its key: a flat key next to a subtable, a value out of
    /// range in a half, a missing key in a half.
    #[test]
    fn mixed_keys_and_bad_halves_are_refused_by_name() {
        let table = SPLIT
            .replace(
                "[material.top]",
                "[material]\nyoungs_modulus = 1e6\n[material.top]",
            )
            .replace("density = 2460.0", "density = -1.0")
            .replace("poisson_ratio = 0.35\ndensity = 1230.0", "density = 1230.0");
        let e = Scene::from_toml_str(&with_material(&table)).unwrap_err();
        let keys: Vec<String> = e.problems().into_iter().map(|p| p.key).collect();
        for key in [
            "material.youngs_modulus",
            "material.top.density",
            "material.bottom.poisson_ratio",
        ] {
            assert!(keys.iter().any(|k| k == key), "{key} missing from {keys:?}");
        }
        let msg = e.to_string();
        assert!(
            msg.contains("together with material.top") && msg.contains("-1"),
            "{msg}"
        );
    }

    /// Only one half: refused naming the missing one; a flat table missing a key names it.
    #[test]
    fn one_half_alone_is_refused_naming_the_other() {
        let top_only = SPLIT.split("[material.bottom]").next().unwrap();
        let e = Scene::from_toml_str(&with_material(top_only))
            .unwrap_err()
            .to_string();
        assert!(e.contains("material.bottom: missing"), "{e}");
        let no_density = with_material("[material]\nyoungs_modulus = 70e6\npoisson_ratio = 0.35");
        let e = Scene::from_toml_str(&no_density).unwrap_err().to_string();
        assert!(e.contains("material.density: missing"), "{e}");
    }

    /// A split table is refused on a Gmsh mesh (pointing to `[fem.mesh.materials]`), with the
    /// default Westergaard boundary, and with a far-field side.
    #[test]
    fn a_split_table_is_refused_where_one_material_is_assumed() {
        let text = scene_text("tiny-fem-bimaterial");
        let (start, end) = (
            text.find("\n[material]").unwrap(),
            text.find("\n[loading]").unwrap(),
        );
        let on_mesh = format!("{}\n{SPLIT}\n{}", &text[..start], &text[end..]);
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let e = Scene::from_toml_str_in(&on_mesh, &dir).unwrap_err().to_string();
        assert!(
            e.contains("material.top") && e.contains("fem.mesh.materials"),
            "{e}"
        );
        let text = scene_text("tiny-fem-center-crack");
        let (start, end) = (
            text.find("\n[material]").unwrap(),
            text.find("\n[interface]").unwrap(),
        );
        let westergaard = format!("{}\n{SPLIT}\n{}", &text[..start], &text[end..]);
        let e = Scene::from_toml_str(&westergaard).unwrap_err().to_string();
        assert!(e.contains("fem.boundary: missing"), "{e}");
        let far = with_material(SPLIT).replace(
            "\n[fem.boundary.bottom]",
            "\n[fem.boundary.top]\nfar_field = true\n[fem.boundary.bottom]",
        );
        let e = Scene::from_toml_str(&far).unwrap_err().to_string();
        assert!(e.contains("fem.boundary.top.far_field"), "{e}");
    }

    /// Halves that differ in ρ only keep the Westergaard field (it depends on E and ν alone);
    /// friction between them needs t* > 0 (ill-posed otherwise), as between any two materials.
    #[test]
    fn a_density_contrast_keeps_the_westergaard_field_and_friction_needs_t_star() {
        let text = scene_text("tiny-fem-center-crack");
        let (start, end) = (
            text.find("\n[material]").unwrap(),
            text.find("\n[interface]").unwrap(),
        );
        let light = "[material.top]\nyoungs_modulus = 70e6\npoisson_ratio = 0.35\ndensity = 1230.0\n\
                     [material.bottom]\nyoungs_modulus = 70e6\npoisson_ratio = 0.35\ndensity = 854.0\n";
        let scene = format!("{}\n{light}\n{}", &text[..start], &text[end..]);
        // μ = 0.3 and no t*: refused, naming fem.t_star and why
        let e = Scene::from_toml_str(&scene).unwrap_err().to_string();
        assert!(e.contains("fem.t_star") && e.contains("ill-posed"), "{e}");
        assert!(!e.contains("fem.boundary"), "{e}");
        let with_t = scene.replace("\n[fem]\n", "\n[fem]\nt_star = 2e-5\n");
        let s = Scene::from_toml_str(&with_t).unwrap();
        assert!(s.bottom_material.is_some() && s.fem.boundary.is_none());
        assert!(s.warnings().is_empty(), "{:?}", s.warnings());
        // identical halves given apart: no refusal
        let same = scene.replace("density = 854.0", "density = 1230.0");
        assert!(Scene::from_toml_str(&same).is_ok());
    }

    /// A contrast past the generalized Rayleigh wave's existence limit runs with a warning.
    #[test]
    fn two_halves_with_no_generalized_rayleigh_wave_are_warned_about() {
        let far = SPLIT.replace("youngs_modulus = 560e6", "youngs_modulus = 70e6");
        let s = Scene::from_toml_str(&with_material(&far)).unwrap();
        let rayleigh = |w: &String| w.contains("no generalized Rayleigh wave");
        assert!(!s.warnings().iter().any(rayleigh), "ρ × 2: {:?}", s.warnings());
        let s = Scene::from_toml_str(&with_material(SPLIT)).unwrap();
        assert!(
            s.warnings()
                .iter()
                .any(|w| w.contains("no generalized Rayleigh wave")),
            "{:?}",
            s.warnings()
        );
    }
}
