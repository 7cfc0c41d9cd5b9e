//! Per-point interface laws (docs/spectral-model.md §5): pure functions of (params, inputs, old state).
//!
//! Sign conventions (stated once, pinned by tests): opening δ_n = u^+_2 − u^-_2 (> 0 open, < 0
//! interpenetration); slip δ_t = u^+_1 − u^-_1; traction T_i = σ_i2 on y = 0 (T_2 > 0 tension);
//! if the top face slides in +x relative to the bottom, the resisting T_1 is positive.
//! S^± = T^0 + f^± is the "dynamic stress" of each face: T^± = S^± ∓ Z^± v^±, with each face's
//! own impedance Z^± (equal for identical half-spaces; docs/spectral-model.md §5.2).

#[cfg(target_arch = "x86_64")]
pub(crate) mod avx2;
pub mod cohesive;
pub mod contact;
pub mod friction;
pub mod point;

pub use point::Drives;
use point::{Drive, Point, PointLaw};

/// How [`solve_points`] runs the law over a run of points. Both give every point the same bits
/// (`law/avx2.rs`, docs/spectral-model.md §5.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LawBuild {
    /// Four points at once in AVX2 registers (the points left over one at a time), where the CPU
    /// has AVX2; the scalar law elsewhere.
    Avx2,
    /// One point at a time, [`point::step`].
    Scalar,
}

impl LawBuild {
    /// AVX2 where the CPU reports it, else the scalar law.
    pub fn detect() -> LawBuild {
        if avx2_available() {
            LawBuild::Avx2
        } else {
            LawBuild::Scalar
        }
    }
}

fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// One step of the law at every point of `points` (docs/spectral-model.md §5.4), with the loads
/// of `d` point for point ([`point::step`] at each): returns the index in `points` of the first
/// point whose face velocity is not finite or exceeds `v_limit` [m/s], if any. `build` chooses how
/// ([`LawBuild`]); every choice gives the same bits.
///
/// # Panics
/// If a slice of `d` is not as long as `points`.
pub fn solve_points(
    build: LawBuild,
    law: &PointLaw,
    v_limit: f64,
    d: &Drives<'_>,
    points: &mut [Point],
) -> Option<usize> {
    assert!(
        d.lengths().iter().all(|&l| l == points.len()),
        "the loads of {} points for {} points",
        d.lengths().iter().min().unwrap_or(&0),
        points.len()
    );
    let (done, blown) = match build {
        // SAFETY: the CPU reported AVX2 at run time (a cached check).
        #[cfg(target_arch = "x86_64")]
        LawBuild::Avx2 if avx2_available() => unsafe { avx2::solve(law, v_limit, d, points) },
        _ => (0, None),
    };
    // the four-point groups come first, so a blown point among them is the first
    let rest = one_by_one(law, v_limit, d, done, &mut points[done..]);
    blown.or(rest.map(|i| done + i))
}

/// [`point::step`] at each point of `points`, whose loads are those of `d` from `offset` on: the
/// index in `points` of the first point whose velocity blew up, if any.
fn one_by_one(
    law: &PointLaw,
    v_limit: f64,
    d: &Drives,
    offset: usize,
    points: &mut [Point],
) -> Option<usize> {
    let (sxy, syy) = d.load;
    let o = offset..;
    // the inputs as slices of the points' length: zipped, the loop checks no index
    let shear = d.f_top_x[o.clone()].iter().zip(&d.f_bottom_x[o.clone()]);
    let normal = d.f_top_y[o.clone()].iter().zip(&d.f_bottom_y[o.clone()]);
    let opening = d.u_top_y[o.clone()].iter().zip(&d.u_bottom_y[o.clone()]);
    let slip = d.u_top_x[o.clone()].iter().zip(&d.u_bottom_x[o.clone()]);
    let mut blown = None;
    let inputs = shear.zip(normal).zip(opening.zip(slip)).zip(&d.nucleation[o]);
    for (i, (p, (((fx, fy), (uy, ux)), &nucleation))) in points.iter_mut().zip(inputs).enumerate() {
        let t01 = sxy + nucleation;
        let drive = Drive {
            shear: (t01 + fx.0, t01 + fx.1),
            normal: (syy + fy.0, syy + fy.1),
            opening: uy.0 - uy.1,
            slip: ux.0 - ux.1,
        };
        // stored field by field: `*p = step(..)` copies the strength's padding bytes along,
        // through overlapping 4-byte moves that stall store forwarding at every point
        let Point {
            strength: cohesive::Strength { sigma, tau, state },
            reg_normal,
            in_contact,
            slipping,
            friction_on,
            traction,
            v,
        } = point::step(law, &drive, p);
        p.strength.sigma = sigma;
        p.strength.tau = tau;
        p.strength.state = state;
        (p.reg_normal, p.in_contact, p.slipping, p.friction_on) =
            (reg_normal, in_contact, slipping, friction_on);
        (p.traction, p.v) = (traction, v);
        // written so that NaN fails it (a fold with f64::max would drop a NaN)
        let within = p.v.iter().all(|v| v.abs() <= v_limit);
        if !within && blown.is_none() {
            blown = Some(i);
        }
    }
    blown
}

/// The impedances of the two faces in one direction [Pa s/m]: ρc_s of each half-space in shear,
/// ρc_d in the normal direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impedances {
    /// Z^+ of the top half-space [Pa s/m].
    pub top: f64,
    /// Z^- of the bottom half-space [Pa s/m].
    pub bottom: f64,
}

impl Impedances {
    /// The same impedance Z [Pa s/m] on both faces (identical half-spaces).
    pub fn equal(z: f64) -> Impedances {
        Impedances { top: z, bottom: z }
    }

    /// Z^+ + Z^- [Pa s/m].
    pub fn sum(&self) -> f64 {
        self.top + self.bottom
    }

    /// The traction both faces carry when they move together (stick), T = (Z^- S^+ + Z^+ S^-)/(Z^+ + Z^-)
    /// [Pa], from S^+ − Z^+ v = S^- + Z^- v. With equal impedances the weights are exactly 1/2, so
    /// this is (S^+ + S^-)/2 to the bit.
    pub fn stick_traction(&self, s_top: f64, s_bottom: f64) -> f64 {
        let (w_top, w_bottom) = self.stick_weights();
        w_top * s_top + w_bottom * s_bottom
    }

    /// The weights of [`stick_traction`](Impedances::stick_traction): (Z^-/(Z^+ + Z^-),
    /// Z^+/(Z^+ + Z^-)) [-], for S^+ and S^- (the four-point law takes them from here too).
    pub fn stick_weights(&self) -> (f64, f64) {
        let sum = self.sum();
        (self.bottom / sum, self.top / sum)
    }

    /// The common velocity of two stuck faces, v = (S^+ − S^-)/(Z^+ + Z^-) [m/s].
    pub fn stick_velocity(&self, s_top: f64, s_bottom: f64) -> f64 {
        (s_top - s_bottom) / self.sum()
    }
}

/// State of an interface point (cRacklet's `ind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
#[repr(u8)]
pub enum PointState {
    /// Untouched: full strength.
    Intact = 0,
    /// In the process zone: 0 < a < 1.
    Cohesive = 1,
    /// Fully broken (a ≥ 1 at some time, or pre-cut).
    Broken = 2,
    /// Broken and in contact this step.
    Contact = 3,
}

impl PointState {
    /// Fully broken (ind ∈ {2, 3}).
    pub fn is_broken(self) -> bool {
        self >= PointState::Broken
    }
}

#[cfg(test)]
mod tests {
    use super::cohesive::{CohesiveParams, Strength};
    use super::point::ContactFriction;
    use super::*;

    /// Loads for fewer points than given are refused, not read short.
    #[test]
    #[should_panic(expected = "the loads of 3 points for 4 points")]
    fn loads_shorter_than_the_points_are_refused() {
        let cohesive = CohesiveParams::from_paper(0.4e6, 1e-4, 1.0, 1.0);
        let law = PointLaw {
            cohesive,
            z_shear: Impedances::equal(1.8e5),
            z_normal: Impedances::equal(3.7e5),
            dt: 1e-6,
            friction_coeff: 0.3,
            relax: None,
            contact: true,
            rule: ContactFriction::AllFaces,
        };
        let (short, full) = ([0.0; 3], [0.0; 4]);
        let d = Drives {
            load: (0.0, 0.0),
            nucleation: &full,
            f_top_x: &full,
            f_bottom_x: &full,
            f_top_y: &full,
            f_bottom_y: &full,
            u_top_x: &full,
            u_bottom_x: &full,
            u_top_y: &short,
            u_bottom_y: &full,
        };
        let mut points = [Point::at_rest(Strength::intact(&cohesive)); 4];
        solve_points(LawBuild::detect(), &law, 1e3, &d, &mut points);
    }
}
