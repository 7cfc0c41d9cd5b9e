//! Boundary loading: the Westergaard displacement field of paper App. C (eqs. C.8–C.9, with the
//! lateral-contraction term of docs/cases.md) on the whole outer boundary, or side-wise uniform
//! displacements/tractions (`[fem.boundary]`), all through the ramp of eq. (B.1).

use crate::law::elastic::PlaneStrain;
use crate::mesh::prepared::PreparedMesh;
use crate::mesh::structured::{Grid, LayerSide};
use crate::model::state::{BoundaryDof, BoundaryParts, Dashpot, FarFieldMotion};
use crate::scene::{BoundaryKind, BoundarySpec, GRID_SIDES, Ramp, Scene};
use nalgebra::{Complex, Vector2};
use std::collections::HashMap;

/// Boundary data: ramps, prescribed DOFs, Neumann DOFs (nodal forces [N/m]), the dashpots of
/// absorbing parts and, with `[fem.boundary]`, its parts (sides, curves, points) and which part
/// each DOF belongs to.
pub(crate) struct BoundaryData {
    pub ramps: Vec<Ramp>,
    pub prescribed: Vec<BoundaryDof>,
    pub neumann: Vec<BoundaryDof>,
    /// One per node of an absorbing part, by node id; held components are left out.
    pub dashpots: Vec<Dashpot>,
    /// The far field's motion when a part carries it.
    pub far_field: Option<FarFieldMotion>,
    pub parts: BoundaryParts,
}

/// Optional terms of the Westergaard boundary field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FieldTerms {
    /// u_x −= ν x σ_yy/(2G): the normal load becomes uniaxial stress (docs/cases.md, default on).
    pub lateral: bool,
    /// u_y += [(1 − 2ν) Im ψ − y Re ψ']/(2G): the mode-II part of u_y that (C.9) drops; with it
    /// the shear part is an exact elastic field (docs/fem-model.md §7; default off, as docs/cases.md).
    pub mode_ii_uy: bool,
}

/// Westergaard field per unit load, docs/fem-model.md §7: returns (u for σ_xy^∞ = 1, u for σ_yy^∞ = 1) [m/Pa]
/// at (x, y) relative to the crack centre, with r(z) = √(z − a)·√(z + a) (principal roots),
/// ψ = i σ_xy (z − r), ψ' = i σ_xy (1 − z/r),
/// 2G u_x = 2(1−ν) Re ψ − y Im ψ' + 2 y σ_xy − ν x σ_yy (last term if `lateral`),
/// 2G u_y = (1−ν) y σ_yy + [(1 − 2ν) Im ψ − y Re ψ'] (bracket if `mode_ii_uy`).
pub(crate) fn westergaard_unit(
    x: f64,
    y: f64,
    a: f64,
    nu: f64,
    g: f64,
    terms: FieldTerms,
) -> (Vector2<f64>, Vector2<f64>) {
    let z = Complex::new(x, y);
    let r = (z - a).sqrt() * (z + a).sqrt();
    let i = Complex::new(0.0, 1.0);
    let psi = i * (z - r);
    let dpsi = i * (Complex::new(1.0, 0.0) - z / r);
    let ux_shear = (2.0 * (1.0 - nu) * psi.re - y * dpsi.im + 2.0 * y) / (2.0 * g);
    let uy_shear = if terms.mode_ii_uy {
        ((1.0 - 2.0 * nu) * psi.im - y * dpsi.re) / (2.0 * g)
    } else {
        0.0
    };
    let ux_normal = if terms.lateral { -nu * x / (2.0 * g) } else { 0.0 };
    let uy_normal = (1.0 - nu) * y / (2.0 * g);
    (
        Vector2::new(ux_shear, uy_shear),
        Vector2::new(ux_normal, uy_normal),
    )
}

/// Builds the boundary data of a scene on a grid.
pub(crate) fn boundary(scene: &Scene, grid: &Grid) -> BoundaryData {
    match &scene.fem.boundary {
        Some(b) => sidewise_grid(scene, b, grid),
        None => westergaard(scene, grid),
    }
}

fn westergaard(scene: &Scene, grid: &Grid) -> BoundaryData {
    let nodes = (0..grid.num_nodes())
        .filter(|&n| grid.on_outer_boundary(n))
        .map(|n| {
            let minus = grid.layer_side[n / (grid.nx + 1)] == LayerSide::Minus;
            (n, grid.x0[n], minus)
        });
    westergaard_on(scene, nodes)
}

/// The Westergaard field on `nodes`: (node, reference position [m], it is the − copy of a twin).
fn westergaard_on(scene: &Scene, nodes: impl Iterator<Item = (usize, Vector2<f64>, bool)>) -> BoundaryData {
    let (xc, a) = scene.crack.map_or((0.0, 0.0), |c| (c.center_x, c.half_length));
    let nu = scene.material.poisson_ratio;
    let g = scene.material.shear_modulus;
    let ramps = vec![scene.loading.normal, scene.loading.shear];
    let mut prescribed = Vec::new();
    for (n, p, minus) in nodes {
        let x = p.x - xc;
        let mut y = p.y;
        if y == 0.0 && x.abs() < a {
            y = if minus { -1e-12 * a } else { 1e-12 * a };
        }
        let terms = FieldTerms {
            lateral: scene.fem.lateral_contraction,
            mode_ii_uy: scene.fem.mode_ii_uy,
        };
        let (us, un) = westergaard_unit(x, y, a, nu, g, terms);
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
        dashpots: Vec::new(),
        far_field: None,
        parts: BoundaryParts::default(),
    }
}

/// Boundary data on a Gmsh mesh: the Westergaard field on every node of the outer boundary, or
/// `[fem.boundary]` with each side on the physical curve of its name (checked at validation).
pub(crate) fn boundary_on_mesh(scene: &Scene, mesh: &PreparedMesh) -> BoundaryData {
    match &scene.fem.boundary {
        Some(b) => {
            const CHECKED: &str = "invariant: the scene's boundary curves were checked against the mesh";
            let materials = scene.materials();
            let element_material = scene
                .fem
                .mesh
                .as_ref()
                .map_or(&[][..], |m| &m.element_material[..]);
            let impedance =
                |e: usize| impedance(&materials[element_material.get(e).copied().unwrap_or(0) as usize]);
            let curves: Vec<_> = b
                .curves
                .iter()
                .map(|c| {
                    let part = mesh.boundary_nodes(&c.name).expect(CHECKED);
                    let pressure = match c.pressure.is_some() || c.far_field {
                        true => mesh.mesh.pressure_weights(&c.name).expect(CHECKED).1,
                        false => Vec::new(),
                    };
                    let dashpots = match c.absorbing {
                        true => mesh.mesh.dashpot_weights(&c.name, &impedance).expect(CHECKED).1,
                        false => Vec::new(),
                    };
                    CurveNodes {
                        positions: part_positions(&part.nodes, &mesh.mesh.positions),
                        nodes: part.nodes,
                        tributary: part.weight,
                        pressure: pressure.iter().map(|w| [w.x, w.y]).collect(),
                        dashpots,
                    }
                })
                .collect();
            sidewise(scene, b, &curves)
        }
        None => westergaard_on(
            scene,
            (0..mesh.outer.len())
                .filter(|&n| mesh.outer[n])
                .map(|n| (n, mesh.mesh.positions[n], !mesh.plus[n])),
        ),
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

/// (ρc_d, ρc_s) [kg/(m²·s)]: the normal and tangential impedances of a material.
fn impedance(m: &PlaneStrain) -> (f64, f64) {
    let c = m.wave_speeds();
    (m.density * c.cd, m.density * c.cs)
}

/// The dashpots (C_xx, C_xy, C_yy) [N·s/m²] of a side's `nodes` on a grid with a split
/// `[material]`: each half of each side edge adds its length times the impedances of the material
/// of the element it bounds (ρc_d on the side's normal, ρc_s along it; `horizontal`: the bottom or
/// top side, whose normal is y).
fn split_dashpots(scene: &Scene, grid: &Grid, nodes: &[u32], horizontal: bool) -> Vec<[f64; 3]> {
    let jc = scene.interface_row();
    let z = [scene.material, scene.material_below()].map(|m| {
        let (zd, zs) = impedance(&m);
        if horizontal { (zs, zd) } else { (zd, zs) }
    });
    let mut c = vec![[0.0; 3]; nodes.len()];
    for k in 0..nodes.len() - 1 {
        let (p, q) = (nodes[k] as usize, nodes[k + 1] as usize);
        let half = 0.5 * (grid.x0[q] - grid.x0[p]).norm();
        // the element row an edge bounds: the row of its lower node's layer on a vertical side
        // (a zero-length edge between twins adds nothing), the side's own row on a horizontal one
        let row = grid.layer_row[p / (grid.nx + 1)].min(grid.ny - 1);
        let (zx, zy) = z[usize::from(row < jc)];
        for n in [k, k + 1] {
            c[n][0] += half * zx;
            c[n][2] += half * zy;
        }
    }
    c
}

fn sidewise_grid(scene: &Scene, b: &BoundarySpec, grid: &Grid) -> BoundaryData {
    let (zd, zs) = impedance(&scene.material);
    let nodes = side_nodes(grid);
    let sides: Vec<_> = b
        .curves
        .iter()
        .map(|c| {
            let k = GRID_SIDES
                .iter()
                .position(|&s| s == c.name)
                .expect("invariant: a grid scene's boundary names its sides only");
            let tributary = tributary(grid, &nodes[k]);
            // −∫ N_a n ds on a straight side: its inward normal times the tributary length
            let inward = [[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]][k];
            let pressure = match c.pressure.is_some() || c.far_field {
                true => tributary.iter().map(|&w| inward.map(|i| i * w)).collect(),
                false => Vec::new(),
            };
            // a straight side: ρc_d on its normal, ρc_s along it, times the tributary length
            let (zx, zy) = if inward[0] == 0.0 { (zs, zd) } else { (zd, zs) };
            let dashpots = match (c.absorbing, scene.bottom_material) {
                (true, None) => tributary.iter().map(|&w| [w * zx, 0.0, w * zy]).collect(),
                (true, Some(_)) => split_dashpots(scene, grid, &nodes[k], inward[0] == 0.0),
                (false, _) => Vec::new(),
            };
            CurveNodes {
                positions: part_positions(&nodes[k], &grid.x0),
                nodes: nodes[k].clone(),
                tributary,
                pressure,
                dashpots,
            }
        })
        .collect();
    sidewise(scene, b, &sides)
}

/// A side or curve's nodes, their reference positions [m] and tributary lengths [m], with a
/// pressure or the far field their weights w_a = −∫ N_a n ds [m] (empty without), and when it
/// absorbs their dashpots (C_xx, C_xy, C_yy) [N·s/m²] (empty otherwise); a point's nodes with
/// weight 1.
struct CurveNodes {
    nodes: Vec<u32>,
    positions: Vec<Vector2<f64>>,
    tributary: Vec<f64>,
    pressure: Vec<[f64; 2]>,
    dashpots: Vec<[f64; 3]>,
}

/// The conditions of `b` on its curves' nodes, one per entry of `b.curves` and in that order: a
/// later displacement replaces an earlier one at a shared node, and a traction or a pressure does
/// not act on a component a displacement holds.
fn sidewise(scene: &Scene, b: &BoundarySpec, sides: &[CurveNodes]) -> BoundaryData {
    let mut ramps = Vec::new();
    let mut presc_index: HashMap<(u32, u8), usize> = HashMap::new();
    let mut prescribed: Vec<BoundaryDof> = Vec::new();
    let mut parts = BoundaryParts {
        names: b.curves.iter().map(|c| c.name.clone()).collect(),
        nodes: sides.iter().map(|s| s.nodes.clone()).collect(),
        ..BoundaryParts::default()
    };
    // at most MAX_CURVES parts (checked at validation)
    for (part, (curve, side)) in b.curves.iter().zip(sides).enumerate() {
        let part = part as u16;
        for dof in 0..2u8 {
            let Some(c) = curve.components[dof as usize] else {
                continue;
            };
            if c.kind != BoundaryKind::Displacement {
                continue;
            }
            ramps.push(c.ramp);
            let k = (ramps.len() - 1) as u8;
            for &n in &side.nodes {
                let entry = BoundaryDof {
                    node: n,
                    dof,
                    terms: [(k, 1.0), (k, 0.0)],
                };
                match presc_index.get(&(n, dof)) {
                    Some(&i) => {
                        prescribed[i] = entry;
                        parts.prescribed[i] = part;
                    }
                    None => {
                        presc_index.insert((n, dof), prescribed.len());
                        prescribed.push(entry);
                        parts.prescribed.push(part);
                    }
                }
            }
        }
    }
    let mut neumann = Vec::new();
    for (part, (curve, side)) in b.curves.iter().zip(sides).enumerate() {
        for dof in 0..2u8 {
            let Some(c) = curve.components[dof as usize] else {
                continue;
            };
            // a traction along a side or curve (weight: tributary length), a force on a point
            // (weight 1); validation keeps each to its kind of part
            if c.kind == BoundaryKind::Displacement {
                continue;
            }
            ramps.push(c.ramp);
            let k = (ramps.len() - 1) as u8;
            for (&n, &wn) in side.nodes.iter().zip(&side.tributary) {
                if wn > 0.0 && !presc_index.contains_key(&(n, dof)) {
                    neumann.push(BoundaryDof {
                        node: n,
                        dof,
                        terms: [(k, wn), (k, 0.0)],
                    });
                    parts.neumann.push(part as u16);
                }
            }
        }
    }
    // pressures after the tractions, so that the tractions' forces keep their order
    for (part, (curve, side)) in b.curves.iter().zip(sides).enumerate() {
        let Some(ramp) = curve.pressure else { continue };
        ramps.push(ramp);
        let k = (ramps.len() - 1) as u8;
        for (&n, w) in side.nodes.iter().zip(&side.pressure) {
            for dof in 0..2u8 {
                let wn = w[dof as usize];
                if wn != 0.0 && !presc_index.contains_key(&(n, dof)) {
                    neumann.push(BoundaryDof {
                        node: n,
                        dof,
                        terms: [(k, wn), (k, 0.0)],
                    });
                    parts.neumann.push(part as u16);
                }
            }
        }
    }
    // the far field's traction σ∞ n, f_a = σ∞ ∫ N_a n ds = −σ∞ w_a with σ_xx = 0:
    // f_x = −σ_xy w_y, f_y = −σ_xy w_x − σ_yy w_y
    if b.curves.iter().any(|c| c.far_field) {
        ramps.push(scene.loading.normal);
        ramps.push(scene.loading.shear);
        let (kn, ks) = ((ramps.len() - 2) as u8, (ramps.len() - 1) as u8);
        for (part, (curve, side)) in b.curves.iter().zip(sides).enumerate() {
            if !curve.far_field {
                continue;
            }
            for (&n, w) in side.nodes.iter().zip(&side.pressure) {
                let terms = [[(ks, -w[1]), (ks, 0.0)], [(kn, -w[1]), (ks, -w[0])]];
                for (dof, terms) in terms.into_iter().enumerate() {
                    if terms.iter().any(|t| t.1 != 0.0) && !presc_index.contains_key(&(n, dof as u8)) {
                        neumann.push(BoundaryDof {
                            node: n,
                            dof: dof as u8,
                            terms,
                        });
                        parts.neumann.push(part as u16);
                    }
                }
            }
        }
    }
    let dashpots = dashpots(b, sides, &presc_index);
    let far_field = far_field_motion(scene, b, sides);
    BoundaryData {
        ramps,
        prescribed,
        neumann,
        dashpots,
        far_field,
        parts,
    }
}

/// The reference positions [m] of `nodes`.
fn part_positions(nodes: &[u32], x0: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
    nodes.iter().map(|&n| x0[n as usize]).collect()
}

/// The far field's motion when a part carries it: the plane-strain compliance of `[material]`
/// (σ_xx = 0, σ_zz = ν σ_yy: ε_xx = −ν(1 + ν) σ_yy/E, ε_yy = (1 − ν²) σ_yy/E, γ = σ_xy/G) about
/// the centroid of the far-field parts' nodes, weighted by their tributary lengths.
fn far_field_motion(scene: &Scene, b: &BoundarySpec, sides: &[CurveNodes]) -> Option<FarFieldMotion> {
    let (mut sum, mut weight) = (Vector2::zeros(), 0.0);
    for (curve, side) in b.curves.iter().zip(sides) {
        if curve.far_field {
            for (x, &w) in side.positions.iter().zip(&side.tributary) {
                sum += x * w;
                weight += w;
            }
        }
    }
    if weight == 0.0 {
        return None;
    }
    let m = &scene.material;
    let (e, nu) = (m.youngs_modulus, m.poisson_ratio);
    Some(FarFieldMotion {
        normal: scene.loading.normal,
        shear: scene.loading.shear,
        compliance: [-nu * (1.0 + nu) / e, (1.0 - nu * nu) / e, 1.0 / m.shear_modulus],
        center: sum / weight,
    })
}

/// The dashpots of the absorbing parts, one per node (a node on two parts, a corner, gets the
/// sum), by node id; a component a displacement holds has none (its row and column are zero).
fn dashpots(b: &BoundarySpec, sides: &[CurveNodes], presc_index: &HashMap<(u32, u8), usize>) -> Vec<Dashpot> {
    let mut per_node: std::collections::BTreeMap<u32, ([f64; 3], u16, bool)> =
        std::collections::BTreeMap::new();
    for (part, (curve, side)) in b.curves.iter().zip(sides).enumerate() {
        for (&n, c) in side.nodes.iter().zip(&side.dashpots) {
            let (sum, last, relative) = per_node.entry(n).or_default();
            for (s, c) in sum.iter_mut().zip(c) {
                *s += c;
            }
            *last = part as u16;
            // a node on a far-field part follows the far field (a corner with a plain absorbing
            // part too: the far field is the motion the whole boundary is loaded with)
            *relative |= curve.far_field;
        }
    }
    per_node
        .into_iter()
        .map(|(node, (mut c, part, relative))| {
            let held = |d: u8| presc_index.contains_key(&(node, d));
            if held(0) {
                c[0] = 0.0;
                c[1] = 0.0;
            }
            if held(1) {
                c[1] = 0.0;
                c[2] = 0.0;
            }
            Dashpot {
                node,
                c,
                part,
                relative,
            }
        })
        .filter(|d| d.c != [0.0; 3])
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const CASES_MD: FieldTerms = FieldTerms {
        lateral: true,
        mode_ii_uy: false,
    };

    #[test]
    fn far_field_is_simple_shear_and_uniaxial_stress() {
        let (nu, g) = (0.35, 25.926e6);
        let (us, un) = westergaard_unit(1e4, 2e3, 0.125, nu, g, CASES_MD);
        assert!((us.x - 2e3 / g).abs() < 1e-6 * 2e3 / g);
        assert!((un.x + nu * 1e4 / (2.0 * g)).abs() < 1e-12);
    }

    #[test]
    fn crack_face_slip_is_mode_two_solution() {
        let (nu, g, a, x) = (0.35, 25.926e6, 0.125, 0.05);
        let (up, _) = westergaard_unit(x, 1e-12 * a, a, nu, g, CASES_MD);
        let (um, _) = westergaard_unit(x, -1e-12 * a, a, nu, g, CASES_MD);
        let expect = 2.0 * (1.0 - nu) * (a * a - x * x).sqrt() / g;
        assert!(
            ((up.x - um.x) - expect).abs() < 1e-9 * expect,
            "{} vs {expect}",
            up.x - um.x
        );
    }

    /// Navier residual |(λ+G)∇(∇·u) + G∇²u| of the shear part at (x, y), relative to the size of
    /// its two terms, by central differences of step δ.
    fn navier_residual(x: f64, y: f64, terms: FieldTerms) -> f64 {
        let (nu, g, a) = (0.35, 25.926e6, 0.125);
        let lambda = 2.0 * g * nu / (1.0 - 2.0 * nu);
        let d = 1e-3 * a;
        let u = |dx: f64, dy: f64| westergaard_unit(x + dx, y + dy, a, nu, g, terms).0;
        let lap = (u(d, 0.0) + u(-d, 0.0) + u(0.0, d) + u(0.0, -d) - 4.0 * u(0.0, 0.0)) / (d * d);
        let uxx = (u(d, 0.0) - 2.0 * u(0.0, 0.0) + u(-d, 0.0)) / (d * d);
        let uyy = (u(0.0, d) - 2.0 * u(0.0, 0.0) + u(0.0, -d)) / (d * d);
        let uxy = (u(d, d) - u(d, -d) - u(-d, d) + u(-d, -d)) / (4.0 * d * d);
        // ∇(∇·u) = (∂xx u_x + ∂xy u_y, ∂xy u_x + ∂yy u_y)
        let grad_div = Vector2::new(uxx.x + uxy.y, uxy.x + uyy.y);
        let (p, q) = ((lambda + g) * grad_div, g * lap);
        (p + q).norm() / (p.norm() + q.norm())
    }

    #[test]
    fn the_shear_field_is_elastic_only_with_its_mode_two_uy() {
        let full = FieldTerms {
            lateral: true,
            mode_ii_uy: true,
        };
        for (x, y) in [(0.2, 0.05), (-0.15, -0.08), (0.05, 0.1)] {
            let (with, without) = (navier_residual(x, y, full), navier_residual(x, y, CASES_MD));
            // central differences: O(δ²) truncation, δ = 1e-3 a
            assert!(with < 1e-4, "({x}, {y}): residual {with} with the mode-II u_y");
            assert!(without > 0.05, "({x}, {y}): residual {without} without it");
        }
    }
}
