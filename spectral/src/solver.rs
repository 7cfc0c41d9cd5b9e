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
use crate::profile::{Clock, Phase, StepWork, Work};
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

/// Buffers, the elastodynamic operator and the clock of the step's phases.
pub(crate) struct Workspace {
    pub half: Operator,
    pub f: FaceFields,
    /// Wall time per phase (this process's steps; never checkpointed).
    pub clock: Clock,
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
        clock: Clock::calibrated(),
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
    ws.half.step_timed(&st.u, &mut ws.f, &mut ws.clock);
    let (f, u) = (&ws.f, &st.u);
    let blown = st
        .points
        .par_iter_mut()
        .enumerate()
        .with_min_len(512)
        .filter_map(|(m, p)| solve_point(model, load, m, f, u, p).then_some(m))
        .min();
    ws.clock.lap(Phase::Law);
    blown
}

/// Flops of the law at one point, on its most common path (intact or cohesive, stuck): the
/// drive (7 adds), the strength update (damage ratio: 2 divisions, 2 squares, 1 add, 1 square
/// root; strengths: 6; 2 minima), the normal and shear stick solves (impedance-weighted mean 6,
/// common velocity 3: 9 each), the Prakash update (4), the friction strength (2) and the blow-up
/// guard (4 absolute values, 4 maxima). Comparisons and branches are not counted.
const LAW_FLOPS_PER_POINT: f64 = 7.0 + (6.0 + 6.0 + 2.0) + 2.0 * 9.0 + 4.0 + 2.0 + 8.0;

/// Work of one step by phase (docs/spectral-model.md §4.2): the operator's
/// ([`Operator::work`]), then per grid point the law's and the update's (records aside):
/// - law: f and u of the four face components read (64 B), the nucleation stress (8 B), the
///   point's state read and written (`size_of::<Point>()` each way), [`LAW_FLOPS_PER_POINT`];
/// - update: the four velocities of the point and u read, u written, 4 multiply-adds (8 flops).
pub(crate) fn work(model: &Model, ws: &Workspace) -> StepWork {
    let n = model.n as f64;
    let point = std::mem::size_of::<Point>() as f64;
    let mut w = ws.half.work();
    w.add(
        Phase::Law,
        Work {
            flops: n * LAW_FLOPS_PER_POINT,
            read: n * (64.0 + 8.0 + point),
            written: n * point,
        },
    );
    w.add(
        Phase::Update,
        Work {
            flops: n * 8.0,
            read: n * (32.0 + 32.0),
            written: n * 32.0,
        },
    );
    w
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
