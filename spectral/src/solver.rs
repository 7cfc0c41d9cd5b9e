//! One time step (docs/spectral-model.md §4): FFT → convolution → iFFT (in [`HalfSpaces`]) → interface
//! law (§5) → velocities and tractions; then `advance` updates the displacements. No I/O, no
//! allocation after `build`.

use rayon::prelude::*;

use crate::elastodynamics::{FaceFields, HalfSpaceParams, HalfSpaces, Operator};
use crate::error::BuildError;
use crate::law::Impedances;
use crate::law::cohesive::{CohesiveParams, Strength};
use crate::law::point::{self, Drive, Point, PointLaw};
use crate::loading;
use crate::scene::{InitialInterface, Scene, Solid};

/// Immutable model: grid, law parameters, loads.
pub(crate) struct Model {
    pub n: usize,
    pub dt: f64,
    pub x: Vec<f64>,
    pub center_index: usize,
    pub on_precrack: Vec<bool>,
    /// The per-point law: cohesion, impedances, friction and its rule.
    pub law: PointLaw,
    pub v_limit: f64,
    pub nucleation: Vec<f64>,
    pub scene: Scene,
}

/// Evolving state: face displacements (SoA, the FFT input) and per-point records.
pub(crate) struct State {
    pub u: FaceFields,
    pub points: Vec<Point>,
}

/// Buffers and the elastodynamic operator.
pub(crate) struct Workspace {
    pub half: Operator,
    pub f: FaceFields,
}

/// Builds model, initial state (u = 0, pre-crack cut) and workspace; the only place that allocates.
pub(crate) fn build(scene: &Scene) -> Result<(Model, State, Workspace), BuildError> {
    let n = scene.grid_points;
    let dx = scene.grid_spacing();
    let x: Vec<f64> = (0..n)
        .map(|m| scene.center_x - 0.5 * scene.length + m as f64 * dx)
        .collect();
    let on_precrack: Vec<bool> = x
        .iter()
        .map(|&x| match scene.initial_interface {
            InitialInterface::PreCrack => (x - scene.center_x).abs() < scene.half_length,
            InitialInterface::Broken => true,
        })
        .collect();
    let cohesive = CohesiveParams::from_paper(scene.sigma_c, scene.delta_c, scene.beta, scene.kappa);
    let points = on_precrack
        .iter()
        .map(|&c| {
            Point::at_rest(if c {
                Strength::precut(&cohesive)
            } else {
                Strength::intact(&cohesive)
            })
        })
        .collect();
    let dt = scene.time_step();
    let nucleation = x
        .iter()
        .map(|&x| {
            scene
                .nucleation
                .map_or(0.0, |nu| loading::nucleation_shear(&nu, x))
        })
        .collect();
    let (top, bottom) = (scene.top(), scene.bottom());
    let half = if scene.is_split() {
        Operator::Split {
            top: Box::new(HalfSpaces::new(&half_space(scene, top))?),
            bottom: Box::new(HalfSpaces::new(&half_space(scene, bottom))?),
            scratch: Box::new(FaceFields::zeros(n)),
        }
    } else {
        Operator::Identical(Box::new(HalfSpaces::new(&half_space(scene, top))?))
    };
    let model = Model {
        n,
        dt,
        x,
        center_index: n / 2,
        on_precrack,
        law: PointLaw {
            cohesive,
            z_shear: Impedances {
                top: top.shear_impedance(),
                bottom: bottom.shear_impedance(),
            },
            z_normal: Impedances {
                top: top.normal_impedance(),
                bottom: bottom.normal_impedance(),
            },
            dt,
            friction_coeff: scene.friction_coeff,
            relax: (scene.t_star > 0.0).then(|| dt / scene.t_star),
            contact: scene.contact,
            rule: scene.contact_friction,
        },
        v_limit: {
            // Blow-up guard: 1e3 × the largest particle velocity the loads and strengths can drive (σ/Z).
            let peak = [
                scene.normal.initial,
                scene.normal.r#final,
                scene.shear.initial,
                scene.shear.r#final,
            ]
            .iter()
            .fold(scene.sigma_c.max(scene.beta * scene.sigma_c), |a, b| {
                a.max(b.abs())
            });
            let z = top.shear_impedance().min(bottom.shear_impedance());
            1e3 * (peak + scene.nucleation.map_or(0.0, |n| n.shear.abs())) / z
        },
        nucleation,
        scene: scene.clone(),
    };
    let state = State {
        u: FaceFields::zeros(n),
        points,
    };
    let ws = Workspace {
        half,
        f: FaceFields::zeros(n),
    };
    Ok((model, state, ws))
}

/// The operator's parameters for one half-space of `scene`: its own μ, c_s and η, and its own
/// β = c_s Δt/Δx at the run's common Δt (the scene's β belongs to the faster half-space).
fn half_space(scene: &Scene, solid: Solid) -> HalfSpaceParams {
    let (cs, fastest) = (solid.wave_speeds().cs, scene.fastest_shear_speed());
    HalfSpaceParams {
        shear_modulus: solid.shear_modulus(),
        cs,
        eta: solid.eta(),
        grid_points: scene.grid_points,
        length: scene.length,
        // exactly the scene's β for the faster (or only) material
        cs_dt_over_dx: if cs == fastest {
            scene.cs_dt_over_dx
        } else {
            scene.cs_dt_over_dx * (cs / fastest)
        },
        kernel_cutoff: scene.kernel_cutoff,
        max_steps: scene.last_step() as usize + 1,
        convolution: scene.convolution,
        fast_tolerance: scene.fast_tolerance,
    }
}

/// Far-field (s_xy, s_yy) at t [s] [Pa].
pub(crate) fn far_field(model: &Model, t: f64) -> (f64, f64) {
    (
        loading::ramp_value(&model.scene.shear, t),
        loading::ramp_value(&model.scene.normal, t),
    )
}

/// Step n at t_n = n Δt: computes v^n and T^n from u^n. Returns the first grid point whose
/// velocity is non-finite or exceeds `v_limit` (blow-up), if any.
pub(crate) fn step(model: &Model, st: &mut State, ws: &mut Workspace, n: u64) -> Option<usize> {
    let t = n as f64 * model.dt;
    let load = far_field(model, t);
    ws.half.step(&st.u, &mut ws.f);
    let (f, u) = (&ws.f, &st.u);
    st.points
        .par_iter_mut()
        .enumerate()
        .with_min_len(512)
        .filter_map(|(m, p)| solve_point(model, load, m, f, u, p).then_some(m))
        .min()
}

/// Interface law at point m (§5.4): the dynamic stresses S^± = T^0 + f^± and the jumps δ^n of
/// the point, then [`point::step`]. Returns true if the velocity blew up.
fn solve_point(
    model: &Model,
    (sxy, syy): (f64, f64),
    m: usize,
    f: &FaceFields,
    u: &FaceFields,
    p: &mut Point,
) -> bool {
    let t01 = sxy + model.nucleation[m];
    let drive = Drive {
        shear: (t01 + f.top_x[m], t01 + f.bottom_x[m]),
        normal: (syy + f.top_y[m], syy + f.bottom_y[m]),
        opening: u.top_y[m] - u.bottom_y[m],
        slip: u.top_x[m] - u.bottom_x[m],
    };
    *p = point::step(&model.law, &drive, p);
    let vmax = p.v.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    vmax.is_nan() || vmax > model.v_limit
}

/// u^{n+1} = u^n + Δt v^n (§4.2 step 7).
pub(crate) fn advance(model: &Model, st: &mut State) {
    let dt = model.dt;
    let u = &mut st.u;
    for (m, p) in st.points.iter().enumerate() {
        u.top_x[m] += dt * p.v[0];
        u.top_y[m] += dt * p.v[1];
        u.bottom_x[m] += dt * p.v[2];
        u.bottom_y[m] += dt * p.v[3];
    }
}
