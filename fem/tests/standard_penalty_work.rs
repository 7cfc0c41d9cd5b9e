//! The standard model's compression penalty (paper eq. 4) acts along the current mid-line normal of
//! a facet pair frozen at insertion. Once the pair has slid, that force has no potential: a closed
//! path of the + nodes returns net work, which is how the standard run creates energy after large
//! slips (README, "Sinusoidal interface"). This test measures the loop work with the pure element.

use fem::law::cohesive::{ClosingTreatment, CohesiveState, LinearCohesive};
use fem::model::cohesive::{FacetGeometry, element_forces};
use fem::nalgebra::Vector2;

const L: f64 = 1e-3; // facet length [m]
const EPS_N: f64 = 2.1e9; // penalty [Pa/m] (300 E of the Section 4 scene)

/// Work [J/m] done on the + nodes along a closed loop in (slip s, penetrations p_a, p_b),
/// midpoint rule with `steps` steps per leg; − nodes fixed, the element fully failed (penalty only).
fn loop_work(steps: usize) -> f64 {
    let law = LinearCohesive {
        sigma_c: 0.04e6,
        delta_c: 1e-3,
        beta: 1.0,
        kappa: 1.0,
    };
    let failed = CohesiveState {
        sigma_c_eff: 0.04e6,
        delta_c_eff: 1e-3,
        delta_max: 1e-3,
        damage: 1.0,
        t_ins: Vector2::zeros(),
    };
    let geometry = FacetGeometry { length: L, sign: 1.0 };
    let x0 = [
        Vector2::new(0.0, 0.0),
        Vector2::new(L, 0.0),
        Vector2::new(0.0, 0.0),
        Vector2::new(L, 0.0),
    ];
    // + node displacements for loop parameters (s, p_a, p_b)
    let disp = |s: f64, pa: f64, pb: f64| [Vector2::new(s, -pa), Vector2::new(s, -pb)];
    let force = |d: [Vector2<f64>; 2]| {
        let u = [d[0], d[1], Vector2::zeros(), Vector2::zeros()];
        let x = [x0[0] + u[0], x0[1] + u[1], x0[2], x0[3]];
        let mut states = [failed; 2];
        let f = element_forces(
            &law,
            ClosingTreatment::Standard { eps_n: EPS_N },
            &geometry,
            &x,
            &u,
            &mut states,
        )
        .force;
        [f[0], f[1]]
    };
    let (s1, p, dp) = (5.0 * L, 0.05 * L, 0.05 * L);
    let corners = [
        (0.0, p, p),
        (s1, p, p),
        (s1, p, p + dp),
        (0.0, p, p + dp),
        (0.0, p, p),
    ];
    let mut work = 0.0;
    for leg in corners.windows(2) {
        let (a, b) = (leg[0], leg[1]);
        let at = |k: f64| {
            let t = k / steps as f64;
            disp(
                a.0 + t * (b.0 - a.0),
                a.1 + t * (b.1 - a.1),
                a.2 + t * (b.2 - a.2),
            )
        };
        for k in 0..steps {
            let (d0, d1, dm) = (at(k as f64), at(k as f64 + 1.0), at(k as f64 + 0.5));
            let f = force(dm);
            work += f[0].dot(&(d1[0] - d0[0])) + f[1].dot(&(d1[1] - d0[1]));
        }
    }
    work
}

#[test]
fn the_penalty_of_a_slid_frozen_pair_does_net_work_around_a_closed_loop() {
    let (w1, w2) = (loop_work(2000), loop_work(4000));
    // scale: the penalty energy stored at the loop's deepest point, ½ ε_n (p + dp)² L
    let scale = 0.5 * EPS_N * (0.1 * L).powi(2) * L;
    println!(
        "loop work {w1:.6e} J/m (2000 steps/leg), {w2:.6e} J/m (4000); stored-energy scale {scale:.3e} J/m"
    );
    // converged in the step count (midpoint rule, second order) ...
    assert!((w1 - w2).abs() <= 1e-6 * w2.abs(), "{w1} vs {w2}");
    // ... and not zero: a conservative force would give 0 to round-off
    assert!(w2.abs() > 0.1 * scale, "loop work {w2} vs scale {scale}");
}
