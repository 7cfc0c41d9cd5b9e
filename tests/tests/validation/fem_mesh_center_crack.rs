//! The paper's centre crack on an unstructured triangle mesh (`scenes/center-crack-tri.toml`,
//! `meshes/center-crack-tri.msh`): the Gmsh path runs the whole hybrid model (pre-crack contact
//! with friction, insertion on the triangles' facets, the Westergaard field on the mesh's outer
//! boundary) and closes the energy balance as the built-in grid does.

use validation::repo_root;

// The energy residual of the built-in grid's test, < 1 % of the boundary work: the balance holds
// whatever the mesh (a mass, a stiffness or a boundary term wrong on triangles would break it).
const TOL_BALANCE_REL: f64 = 0.01;

#[test]
fn the_centre_crack_on_triangles_runs_and_balances_its_energy() {
    let scene = fem::Scene::from_file(&repo_root().join("scenes/center-crack-tri.toml")).unwrap();
    assert!(scene.fem.mesh.is_some());
    let out = fem::run(&scene).unwrap();
    let (worst, w_final) = validation::worst_energy_residual(&out);
    assert!(
        worst < TOL_BALANCE_REL,
        "energy residual: worst |residual| / W_ext = {worst:.2e} (tol {TOL_BALANCE_REL}); W_ext(T) = {w_final:.4} J/m"
    );
    // the crack runs through the interface: both tips past 1.9 a (the end of the gate's speed
    // window), as on the built-in grid
    let a = scene.half_length();
    let last = out.tips.last().unwrap();
    assert!(
        last.tip_right > 1.9 * a && -last.tip_left > 1.9 * a,
        "tips at {} and {} m",
        last.tip_right,
        last.tip_left
    );
}
