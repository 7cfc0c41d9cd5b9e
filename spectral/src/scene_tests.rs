//! Unit tests of scene parsing and validation.
use super::*;

const SCENE: &str = include_str!("../../scenes/center-crack.toml");

#[test]
fn center_crack_parses_with_paper_numbers() {
    let s = Scene::from_toml_str(SCENE).unwrap();
    let w = s.wave_speeds();
    assert!((w.cs - 145.18).abs() < 0.01, "cs = {}", w.cs);
    assert!((w.cd - 302.22).abs() < 0.02, "cd = {}", w.cd);
    assert!((w.cr / w.cs - 0.9350131).abs() < 1e-7);
    assert!((s.eta() - 2.081665999).abs() < 1e-9);
}

#[test]
fn unstable_cfl_is_refused_with_range() {
    let text = SCENE.replace("cs_dt_over_dx = 0.2", "cs_dt_over_dx = 0.63");
    let err = Scene::from_toml_str(&text).unwrap_err().to_string();
    assert!(
        err.contains("spectral.cs_dt_over_dx") && err.contains("0.5"),
        "{err}"
    );
}

#[test]
fn both_or_neither_step_keys_refused() {
    let text = SCENE.replace("cs_dt_over_dx = 0.2", "cs_dt_over_dx = 0.2\ntime_step = 1e-6");
    assert!(Scene::from_toml_str(&text).is_err());
    let text = SCENE.replace("cs_dt_over_dx = 0.2", "");
    assert!(Scene::from_toml_str(&text).is_err());
}

#[test]
fn time_step_key_sets_cfl() {
    let text = SCENE.replace("cs_dt_over_dx = 0.2", "time_step = 1.53e-6");
    let s = Scene::from_toml_str(&text).unwrap();
    assert!((s.time_step() - 1.53e-6).abs() < 1e-15);
    assert!((s.cs_dt_over_dx - 0.2425).abs() < 1e-3, "{}", s.cs_dt_over_dx);
}

#[test]
fn unknown_key_is_refused() {
    let text = SCENE.replace("[crack]", "[crack]\nwidth = 1.0");
    assert!(Scene::from_toml_str(&text).is_err());
}

#[test]
fn variants_are_validated_like_the_file() {
    let s = Scene::from_toml_str(SCENE).unwrap();
    let v = s.with_friction_coeff(0.0).unwrap();
    assert_eq!(v.friction_coeff, 0.0);
    assert!(s.with_friction_coeff(-1.0).is_err());
    let dt = 1.53e-6;
    let v = s.with_time_step(dt).unwrap();
    assert!((v.time_step() - dt).abs() < 1e-18);
    let e = s.with_time_step(1e-4).unwrap_err().to_string();
    assert!(e.contains("spectral.time_step"), "{e}");
    let v = s.with_grid_points(2048).unwrap();
    assert_eq!(v.grid_points, 2048);
    assert!((v.grid_spacing() - 2.0 * s.grid_spacing()).abs() < 1e-15);
    assert!(s.with_grid_points(3).is_err());
}

/// A ramp that starts at or after T never reaches its final value and is refused naming the key;
/// a constant (initial = final) is no ramp, so its start may lie anywhere (the FE model's rule).
#[test]
fn a_ramp_after_the_run_is_refused_and_a_late_constant_is_not() {
    let ramp = "normal = { initial = 0.0, final = -0.05e6, ramp_start = 0.0, ramp_end = 0.004 }";
    assert!(SCENE.contains(ramp));
    let late = SCENE.replace(
        ramp,
        &ramp.replace(
            "ramp_start = 0.0, ramp_end = 0.004",
            "ramp_start = 0.03, ramp_end = 0.04",
        ),
    );
    let err = Scene::from_toml_str(&late).unwrap_err().to_string();
    assert!(
        err.contains("loading.normal.ramp_start") && err.contains("never reaches"),
        "{err}"
    );
    let constant = late.replace(
        "initial = 0.0, final = -0.05e6",
        "initial = -0.05e6, final = -0.05e6",
    );
    assert!(Scene::from_toml_str(&constant).is_ok());
}

/// `[friction] contact_friction`, the FE model's key and meaning: all_faces by default,
/// failed_only on request, anything else refused naming the key; a variant changes the rule only.
#[test]
fn the_friction_rule_is_a_key_of_the_shared_problem() {
    let text = SCENE.to_string();
    let s = Scene::from_toml_str(&text).unwrap();
    assert_eq!(s.contact_friction, ContactFriction::AllFaces);
    let bad = text.replace("contact_friction = \"all_faces\"", "contact_friction = \"all\"");
    let e = Scene::from_toml_str(&bad).unwrap_err().to_string();
    assert!(
        e.contains("friction.contact_friction") && e.contains("failed_only"),
        "{e}"
    );
    let v = s.with_contact_friction(ContactFriction::FailedOnly).unwrap();
    assert_eq!(v.contact_friction, ContactFriction::FailedOnly);
    assert_eq!(
        v.with_friction_coeff(0.1).unwrap().contact_friction,
        ContactFriction::FailedOnly
    );
    let unset = text.replace("contact_friction = \"all_faces\"", "");
    assert_eq!(
        Scene::from_toml_str(&unset).unwrap().contact_friction,
        ContactFriction::AllFaces
    );
}

/// Every message about the geometry reads as one sentence: a line break in its source must not
/// leave a run of blanks in the text the user sees.
#[test]
fn geometry_messages_have_no_runs_of_blanks() {
    // a periodic length under 4a is refused; one under 20a, and a coarse grid, are warned about
    let short = SCENE.replace("length = 3.75 ", "length = 0.4 ");
    let err = Scene::from_toml_str(&short).unwrap_err().to_string();
    assert!(
        err.contains("spectral.length") && err.contains("at least 4a"),
        "{err}"
    );
    assert!(!message(&err, "spectral.length").contains("  "), "{err}");
    // two points per process zone over a length of 16a
    let lp = Scene::from_toml_str(SCENE).unwrap().process_zone();
    let n = 2 * ((2.0 * 2.0 / lp) / 2.0).round() as usize;
    let coarse = SCENE
        .replace("length = 3.75 ", "length = 2.0 ")
        .replace("grid_points = 4096 ", &format!("grid_points = {n} "));
    let warnings = Scene::from_toml_str(&coarse).unwrap().warnings();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    for w in &warnings {
        assert!(!w.contains("  "), "{w}");
    }
    let coarser = SCENE.replace("grid_points = 4096 ", "grid_points = 64 ");
    let err = Scene::from_toml_str(&coarser).unwrap_err().to_string();
    assert!(err.contains("falls between grid points"), "{err}");
    assert!(!message(&err, "spectral.grid_points").contains("  "), "{err}");
}

/// The line of a scene error that names `key`, without the indentation of the list.
fn message<'e>(err: &'e str, key: &str) -> &'e str {
    err.lines().find(|l| l.contains(key)).map_or("", str::trim_start)
}

/// The centre crack with `[material]` split into two tables of the given bodies.
fn split_scene(top: &str, bottom: &str) -> String {
    SCENE.replace(
        "[material]                      # bulk / both half-spaces, plane strain\nyoungs_modulus = 70e6           # Pa\npoisson_ratio = 0.35            # -\ndensity = 1230.0                # kg/m^3\n",
        &format!("[material.top]\n{top}\n[material.bottom]\n{bottom}\n"),
    )
}

const PAPER_BODY: &str = "youngs_modulus = 70e6\npoisson_ratio = 0.35\ndensity = 1230.0";
/// c_s 20 % above the paper material's (E × 1.44 at the same ρ and ν).
const FASTER_BODY: &str = "youngs_modulus = 100.8e6\npoisson_ratio = 0.35\ndensity = 1230.0";

#[test]
fn a_split_material_gives_each_half_space_its_own_and_the_faster_sets_the_step() {
    let s = Scene::from_toml_str(&split_scene(PAPER_BODY, FASTER_BODY)).unwrap();
    assert!(s.is_split());
    let (t, b) = (s.top().wave_speeds().cs, s.bottom().wave_speeds().cs);
    assert!((b / t - 1.2).abs() < 1e-12, "{t} {b}");
    assert_eq!(s.fastest_shear_speed(), b);
    let flat = Scene::from_toml_str(SCENE).unwrap();
    assert!((s.time_step() * 1.2 - flat.time_step()).abs() < 1e-15 * flat.time_step());
    // the softer half-space's process zone is the one the grid must resolve
    assert_eq!(s.process_zone(), flat.process_zone());
    // identical halves given apart: split, and the same step to the bit
    let same = Scene::from_toml_str(&split_scene(PAPER_BODY, PAPER_BODY)).unwrap();
    assert!(same.is_split());
    assert_eq!(same.time_step(), flat.time_step());
}

#[test]
fn a_split_material_is_checked_key_by_key() {
    let e = Scene::from_toml_str(&split_scene(
        PAPER_BODY,
        "youngs_modulus = 70e6\npoisson_ratio = 0.35\ndensity = -1.0",
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("material.bottom.density = -1"), "{e}");
    // one half only
    let only_top = SCENE.replace("[material]  ", "[material.top]");
    let e = Scene::from_toml_str(&only_top).unwrap_err().to_string();
    assert!(e.contains("material.bottom") && e.contains("missing"), "{e}");
    // flat keys beside the tables
    let mixed = split_scene(PAPER_BODY, PAPER_BODY)
        .replace("[material.top]", "[material]\ndensity = 1230.0\n[material.top]");
    let e = Scene::from_toml_str(&mixed).unwrap_err().to_string();
    assert!(e.contains("material.density") && e.contains("beside"), "{e}");
    // neither form
    let none = SCENE.replace("youngs_modulus = 70e6           # Pa\n", "");
    let e = Scene::from_toml_str(&none).unwrap_err().to_string();
    assert!(
        e.contains("material.youngs_modulus") && e.contains("missing"),
        "{e}"
    );
}

#[test]
fn coulomb_friction_between_two_materials_needs_t_star() {
    let text = split_scene(PAPER_BODY, FASTER_BODY);
    let text = text.replace("t_star = 2e-5 ", "t_star = 0.0 ");
    let e = Scene::from_toml_str(&text).unwrap_err().to_string();
    assert!(e.contains("spectral.t_star") && e.contains("ill-posed"), "{e}");
    // the same with μ = 0, or with identical halves, is well-posed
    assert!(Scene::from_toml_str(&text.replace("friction_coeff = 0.3 ", "friction_coeff = 0.0 ")).is_ok());
    let same = split_scene(PAPER_BODY, PAPER_BODY).replace("t_star = 2e-5 ", "t_star = 0.0 ");
    assert!(Scene::from_toml_str(&same).is_ok());
}

#[test]
fn a_contrast_past_the_generalized_rayleigh_limit_is_warned_about() {
    // c_s 20 % apart through μ: the wave exists; 30 %: it does not (0.9945 c_s and none, by the
    // independent form of compare's theory)
    let ok = Scene::from_toml_str(&split_scene(PAPER_BODY, FASTER_BODY)).unwrap();
    assert!(
        !ok.warnings().iter().any(|w| w.contains("generalized Rayleigh")),
        "{:?}",
        ok.warnings()
    );
    let far = "youngs_modulus = 118.3e6\npoisson_ratio = 0.35\ndensity = 1230.0";
    let s = Scene::from_toml_str(&split_scene(PAPER_BODY, far)).unwrap();
    assert!(
        s.warnings()
            .iter()
            .any(|w| w.starts_with("material: no generalized Rayleigh wave")),
        "{:?}",
        s.warnings()
    );
    assert!(slip_wave_exists(s.top(), s.top()));
}
