//! Patch test of the Q4 bulk (docs/fem-model.md §1): a linear displacement field gives zero internal
//! force at interior nodes, on a rectangular grid (shared K_e) and on a mapped (distorted) grid (one
//! K_e per element).

use validation::{scene_text, with_overrides};

const TOL_PATCH_REL: f64 = 1e-10; // patch test: interior force / boundary force <= 1e-10; not tuned

fn plate() -> fem::Scene {
    let text = with_overrides(
        &scene_text("tiny-fem-plate"),
        &[
            ("fem.x_range", Some(toml::Value::try_from([0.0, 0.02]).unwrap())),
            ("fem.probes", None),
        ],
    );
    fem::Scene::from_toml_str(&text).expect("tiny plate scene")
}

/// max |f| over interior nodes divided by max |f| over boundary nodes.
fn interior_ratio(model: &fem::Model) -> f64 {
    let field = |x: fem::nalgebra::Vector2<f64>| {
        fem::nalgebra::Vector2::new(
            1e-4 + 2e-3 * x.x - 1.5e-3 * x.y,
            -3e-4 + 0.7e-3 * x.x + 2.5e-3 * x.y,
        )
    };
    let forces = fem::probe::internal_forces_for(model, &field);
    let (mut interior, mut boundary) = (0.0f64, 0.0f64);
    for (_, on_boundary, f) in &forces {
        if *on_boundary {
            boundary = boundary.max(f.norm());
        } else {
            interior = interior.max(f.norm());
        }
    }
    interior / boundary
}

#[test]
fn linear_field_gives_zero_interior_force_on_rectangles() {
    let (model, _, _) = fem::build(&plate()).unwrap();
    assert!(fem::probe::shares_stiffness(&model));
    let r = interior_ratio(&model);
    println!("patch test, rectangles: max interior / max boundary force = {r:.3e} (tol {TOL_PATCH_REL:e})");
    assert!(r <= TOL_PATCH_REL);
}

#[test]
fn linear_field_gives_zero_interior_force_on_mapped_mesh() {
    // the y = 0 node row follows y = 0.3 h sin(2π x / 10 mm); rows in between are interpolated
    let curve = |x: f64| 0.3e-3 * (2.0 * std::f64::consts::PI * x / 0.01).sin();
    let (model, _, _) = fem::build_with_row_map(&plate(), Some(&curve)).unwrap();
    assert!(
        !fem::probe::shares_stiffness(&model),
        "a mapped mesh needs one K_e per element"
    );
    let r = interior_ratio(&model);
    println!("patch test, mapped quads: max interior / max boundary force = {r:.3e} (tol {TOL_PATCH_REL:e})");
    assert!(r <= TOL_PATCH_REL);
}
