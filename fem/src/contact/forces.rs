//! Contact forces, docs/fem-model.md §5 and §5.2–5.4: nodal areas and slave normals, the per-slave
//! normal penalty + friction return map, and the Algorithm 1 averaging as an action = reaction
//! force scatter with w = ½.

use nalgebra::Vector2;
use rayon::prelude::*;

use super::geometry::{Projection, SegmentFrame, point_at, segment_frame, shape};
use crate::law::friction::{Friction, FrictionInput, FrictionStep, regularized_normal, return_map};
use crate::law::penalty::normal_pressure;

/// Algorithm 1 averaging weight: each slave keeps ½ of its own force and ½ reaches it back as a
/// master through the slaves projecting onto its segments (docs/fem-model.md §5.4).
pub(crate) const AVERAGING_WEIGHT: f64 = 0.5;

/// Nodal areas A_i = |Σ_{e ∋ i} (L_e/2) n_e| [m] and slave normals n_i = normalise(Σ_{e ∋ i} n_e)
/// [-] of the nodes of Γ_det, in current positions (docs/fem-model.md §5).
///
/// Also refills `frames` with every segment's frame (`None` for a degenerate segment).
/// `area_sum` and `normal_sum` are per-node scratch; only entries of `nodes` are touched.
pub(crate) fn node_geometry(
    segments: &[[u32; 2]],
    nodes: &[u32],
    x: &[Vector2<f64>],
    frames: &mut Vec<Option<SegmentFrame>>,
    (area_sum, normal_sum): (&mut [Vector2<f64>], &mut [Vector2<f64>]),
) {
    for &i in nodes {
        area_sum[i as usize] = Vector2::zeros();
        normal_sum[i as usize] = Vector2::zeros();
    }
    // The frames (a square root and a division each) in parallel, one slot per segment; the
    // nodal sums below stay serial, in segment order, so their bits do not depend on the threads.
    // Chunks of at least 1024 segments: a short interface runs in one piece. `collect_into_vec`
    // keeps the capacity: no allocation within `max_segments`.
    segments
        .par_iter()
        .with_min_len(1024)
        .map(|&[j1, j2]| segment_frame(x[j1 as usize], x[j2 as usize]))
        .collect_into_vec(frames);
    for (&[j1, j2], frame) in segments.iter().zip(frames.iter()) {
        let Some(frame) = frame else {
            continue;
        };
        let half = frame.normal * (0.5 * frame.length);
        for j in [j1 as usize, j2 as usize] {
            area_sum[j] += half;
            normal_sum[j] += frame.normal;
        }
    }
    for &i in nodes {
        let n = normal_sum[i as usize];
        let norm = n.norm();
        normal_sum[i as usize] = if norm > 0.0 { n / norm } else { n };
    }
}

/// Friction history of one slave from the previous step (docs/fem-model.md §5.3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct SlaveHistory {
    /// Master segment nodes (k1, k2) of the previous step's contact element.
    pub segment: [u32; 2],
    /// ξ_prev: natural coordinate on that segment, unclamped (|ξ| ≤ 1 + ε_ext) [-].
    pub xi: f64,
    /// t_prev: that segment's tangent at the previous step [-].
    pub tangent: Vector2<f64>,
    /// T_prev [Pa] along t_prev.
    pub traction: f64,
}

/// One contact element (i, e, ξ_c) with its normal and tangential tractions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ContactResponse {
    /// Normal pressure p_N = ε_n p [Pa].
    pub normal_pressure: f64,
    /// Normal pressure σ̃ of the Coulomb strength μ σ̃ [Pa]: p_N regularised by eq. (14) where
    /// friction acts (μ > 0), relaxing towards 0 where it does not; exactly p_N with t* = 0.
    pub friction_pressure: f64,
    /// Friction result (T along t_e [Pa], stick/slip, plastic slip [m]).
    pub friction: FrictionStep,
    /// Total force on the slave before averaging, F = A_i (p_N n_e + T t_e) [N/m].
    pub force: Vector2<f64>,
    /// Relative slip of the slave over the master this step, Δs along t_e [m] (0 on the first
    /// contact step, which has no history).
    pub slip: f64,
}

/// Normal penalty (eq. 8 left, §5.2) and friction return map (§5.3) for slave `node` of area
/// `area` [m] projected onto master `segment` with `proj`. `history` is `None` when the slave had
/// no contact element in the previous step: then T = 0 (friction starts one step after first
/// contact, as in Akantu). `regularized_prev` is the slave's σ̃ [Pa] of the previous step
/// (eq. 14; unused with t* = 0), `None` for a slave that has never touched: its σ̃ starts at the
/// pressure it meets. A facet inserted under compression has carried that compression, tied,
/// since long before (the spectral model's σ̃ follows the normal stress of every closed point,
/// intact ones included, docs/spectral-model.md §5.3); starting it from 0 would take friction
/// away from the process zone for a time t* after each insertion.
///
/// x_ρ,prev is rebuilt on the **previous** segment with ξ_prev at current positions, so moving
/// onto a neighbouring segment gives no spurious slip (docs/fem-model.md §10.17).
///
/// # Deviation
/// The plain reading evaluates x_ρ and x_ρ,prev at the clamped ξ_c. Here both use the unclamped ξ
/// (|ξ| ≤ 1 + ε_ext, so the point stays within ε_ext L/2 of the segment): a slave accepted just
/// beyond a segment end would otherwise lose the part of its slip past the end for one step and
/// get it back the next, a dip of the stick traction at every junction. Forces still use ξ_c
/// (docs/fem-model.md §5.3).
#[inline(always)]
pub(crate) fn respond(
    eps_n: f64,
    law: &Friction,
    area: f64,
    (segment, proj): ([u32; 2], &Projection),
    (history, regularized_prev): (Option<&SlaveHistory>, Option<f64>),
    x: &[Vector2<f64>],
) -> ContactResponse {
    let p_n = normal_pressure(eps_n, -proj.gap);
    // σ of eq. (14): the pressure where friction acts, none where it does not
    let sigma = if law.friction_coeff > 0.0 { p_n } else { 0.0 };
    let friction_pressure = match regularized_prev {
        Some(prev) => regularized_normal(prev, sigma, law.prakash_ratio),
        None => sigma,
    };
    let t_e = proj.frame.tangent;
    let (friction, slip) = match history {
        Some(h) if law.friction_coeff > 0.0 => {
            let x_rho = point_at(x[segment[0] as usize], x[segment[1] as usize], proj.xi);
            let [k1, k2] = h.segment;
            let x_rho_prev = point_at(x[k1 as usize], x[k2 as usize], h.xi);
            let input = FrictionInput {
                traction_prev: h.traction,
                transport: h.tangent.dot(&t_e),
                slip: (x_rho - x_rho_prev).dot(&t_e),
                normal_pressure: friction_pressure,
            };
            (return_map(law, &input), input.slip)
        }
        _ => (
            FrictionStep {
                traction: 0.0,
                slipping: law.friction_coeff == 0.0,
                plastic_slip: 0.0,
            },
            0.0,
        ),
    };
    ContactResponse {
        normal_pressure: p_n,
        friction_pressure,
        friction,
        force: (proj.frame.normal * p_n + t_e * friction.traction) * area,
        slip,
    }
}

/// Algorithm 1 as force averaging (docs/fem-model.md §5.4), action = reaction:
///
/// ```text
/// f_i += w F,   f_j1 −= w N₁(ξ_c) F,   f_j2 −= w N₂(ξ_c) F
/// ```
///
/// The master share is split as a and (wF − a) so that the three contributions cancel exactly
/// up to the round-off of the accumulation.
pub(crate) fn scatter(
    f: &mut [Vector2<f64>],
    slave: u32,
    segment: [u32; 2],
    xi_clamped: f64,
    force: Vector2<f64>,
) {
    let wf = force * AVERAGING_WEIGHT;
    let (n1, _) = shape(xi_clamped);
    let to_j1 = wf * n1;
    let to_j2 = wf - to_j1;
    f[slave as usize] += wf;
    f[segment[0] as usize] -= to_j1;
    f[segment[1] as usize] -= to_j2;
}
