//! Boundary loading: the Westergaard displacement field of paper App. C (eqs. C.8–C.9, with the
//! lateral-contraction term of cases.md) on the whole outer boundary, or side-wise uniform
//! displacements/tractions (`[fem.boundary]`), all through the ramp of eq. (B.1).

use crate::mesh::structured::{Grid, LayerSide};
use crate::model::state::BoundaryDof;
use crate::scene::{BoundaryKind, BoundarySpec, Ramp, Scene};
use nalgebra::{Complex, Vector2};
use std::collections::HashMap;

/// Boundary data: ramps, prescribed DOFs, Neumann DOFs (nodal forces [N/m]).
pub(crate) struct BoundaryData {
    pub ramps: Vec<Ramp>,
    pub prescribed: Vec<BoundaryDof>,
    pub neumann: Vec<BoundaryDof>,
}

/// Westergaard field per unit load, fem-method §7: returns (u for σ_xy^∞ = 1, u for σ_yy^∞ = 1) [m/Pa]
/// at (x, y) relative to the crack centre, with r(z) = √(z − a)·√(z + a) (principal roots),
/// ψ = i σ_xy (z − r), ψ' = i σ_xy (1 − z/r),
/// 2G u_x = 2(1−ν) Re ψ − y Im ψ' + 2 y σ_xy − ν x σ_yy (last term if `lateral`), 2G u_y = (1−ν) y σ_yy.
pub(crate) fn westergaard_unit(
    x: f64,
    y: f64,
    a: f64,
    nu: f64,
    g: f64,
    lateral: bool,
) -> (Vector2<f64>, Vector2<f64>) {
    let z = Complex::new(x, y);
    let r = (z - a).sqrt() * (z + a).sqrt();
    let i = Complex::new(0.0, 1.0);
    let psi = i * (z - r);
    let dpsi = i * (Complex::new(1.0, 0.0) - z / r);
    let ux_shear = (2.0 * (1.0 - nu) * psi.re - y * dpsi.im + 2.0 * y) / (2.0 * g);
    let ux_normal = if lateral { -nu * x / (2.0 * g) } else { 0.0 };
    let uy_normal = (1.0 - nu) * y / (2.0 * g);
    (Vector2::new(ux_shear, 0.0), Vector2::new(ux_normal, uy_normal))
}

/// Builds the boundary data of a scene on a grid.
pub(crate) fn boundary(scene: &Scene, grid: &Grid) -> BoundaryData {
    match &scene.fem.boundary {
        Some(b) => sidewise(b, grid),
        None => westergaard(scene, grid),
    }
}

fn westergaard(scene: &Scene, grid: &Grid) -> BoundaryData {
    let (xc, a) = scene.crack.map_or((0.0, 0.0), |c| (c.center_x, c.half_length));
    let nu = scene.material.poisson_ratio;
    let g = scene.material.shear_modulus;
    let ramps = vec![scene.loading.normal, scene.loading.shear];
    let mut prescribed = Vec::new();
    for n in 0..grid.num_nodes() {
        if !grid.on_outer_boundary(n) {
            continue;
        }
        let layer = n / (grid.nx + 1);
        let x = grid.x0[n].x - xc;
        let mut y = grid.x0[n].y;
        if y == 0.0 && x.abs() < a {
            y = match grid.layer_side[layer] {
                LayerSide::Minus => -1e-12 * a,
                _ => 1e-12 * a,
            };
        }
        let (us, un) = westergaard_unit(x, y, a, nu, g, scene.fem.lateral_contraction);
        for dof in 0..2u8 {
            let d = dof as usize;
            prescribed.push(BoundaryDof {
                node: n as u32,
                dof,
                terms: [(0, un[d]), (1, us[d])],
            });
        }
    }
    BoundaryData {
        ramps,
        prescribed,
        neumann: Vec::new(),
    }
}

/// Nodes of each side in order along it: [bottom, right, top, left].
fn side_nodes(grid: &Grid) -> [Vec<u32>; 4] {
    let nx = grid.nx;
    let last = grid.layer_row.len() - 1;
    let bottom = (0..=nx).map(|i| grid.node(0, i)).collect();
    let top = (0..=nx).map(|i| grid.node(last, i)).collect();
    let column = |i: usize| (0..=last).map(|l| grid.node(l, i)).collect::<Vec<u32>>();
    [bottom, column(nx), top, column(0)]
}

/// Tributary lengths of a side's nodes [m]: half of each adjacent side edge (twins split the side).
fn tributary(grid: &Grid, nodes: &[u32]) -> Vec<f64> {
    let mut w = vec![0.0; nodes.len()];
    for k in 0..nodes.len() - 1 {
        let (p, q) = (grid.x0[nodes[k] as usize], grid.x0[nodes[k + 1] as usize]);
        let half = 0.5 * (q - p).norm();
        w[k] += half;
        w[k + 1] += half;
    }
    w
}

fn sidewise(b: &BoundarySpec, grid: &Grid) -> BoundaryData {
    let sides = side_nodes(grid);
    let mut ramps = Vec::new();
    let mut presc_index: HashMap<(u32, u8), usize> = HashMap::new();
    let mut prescribed: Vec<BoundaryDof> = Vec::new();
    for (s, nodes) in sides.iter().enumerate() {
        for dof in 0..2u8 {
            let Some(c) = b.sides[s][dof as usize] else {
                continue;
            };
            if c.kind != BoundaryKind::Displacement {
                continue;
            }
            ramps.push(c.ramp);
            let k = (ramps.len() - 1) as u8;
            for &n in nodes {
                let entry = BoundaryDof {
                    node: n,
                    dof,
                    terms: [(k, 1.0), (k, 0.0)],
                };
                match presc_index.get(&(n, dof)) {
                    Some(&i) => prescribed[i] = entry,
                    None => {
                        presc_index.insert((n, dof), prescribed.len());
                        prescribed.push(entry);
                    }
                }
            }
        }
    }
    let mut neumann = Vec::new();
    for (s, nodes) in sides.iter().enumerate() {
        let w = tributary(grid, nodes);
        for dof in 0..2u8 {
            let Some(c) = b.sides[s][dof as usize] else {
                continue;
            };
            if c.kind != BoundaryKind::Traction {
                continue;
            }
            ramps.push(c.ramp);
            let k = (ramps.len() - 1) as u8;
            for (&n, &wn) in nodes.iter().zip(&w) {
                if wn > 0.0 && !presc_index.contains_key(&(n, dof)) {
                    neumann.push(BoundaryDof {
                        node: n,
                        dof,
                        terms: [(k, wn), (k, 0.0)],
                    });
                }
            }
        }
    }
    BoundaryData {
        ramps,
        prescribed,
        neumann,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_field_is_simple_shear_and_uniaxial_stress() {
        let (nu, g) = (0.35, 25.926e6);
        let (us, un) = westergaard_unit(1e4, 2e3, 0.125, nu, g, true);
        assert!((us.x - 2e3 / g).abs() < 1e-6 * 2e3 / g);
        assert!((un.x + nu * 1e4 / (2.0 * g)).abs() < 1e-12);
    }

    #[test]
    fn crack_face_slip_is_mode_two_solution() {
        let (nu, g, a, x) = (0.35, 25.926e6, 0.125, 0.05);
        let (up, _) = westergaard_unit(x, 1e-12 * a, a, nu, g, true);
        let (um, _) = westergaard_unit(x, -1e-12 * a, a, nu, g, true);
        let expect = 2.0 * (1.0 - nu) * (a * a - x * x).sqrt() / g;
        assert!(
            ((up.x - um.x) - expect).abs() < 1e-9 * expect,
            "{} vs {expect}",
            up.x - um.x
        );
    }
}
