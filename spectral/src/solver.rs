//! One time step (spectral-method.md §4): FFT → convolution → iFFT (in [`HalfSpaces`]) → interface
//! law (§5) → velocities and tractions; then `advance` updates the displacements. No I/O, no
//! allocation after `build`.

use crate::elastodynamics::{FaceFields, HalfSpaceParams, HalfSpaces};
use crate::error::BuildError;
use crate::law::PointState;
use crate::law::cohesive::{self, CohesiveParams, Strength};
use crate::law::contact::{self, NormalBranch, NormalInput};
use crate::law::friction;
use crate::loading;
use crate::scene::Scene;

/// Immutable model: grid, law parameters, loads.
pub(crate) struct Model {
    pub n: usize,
    pub dt: f64,
    pub x: Vec<f64>,
    pub center_index: usize,
    pub on_precrack: Vec<bool>,
    pub cohesive: CohesiveParams,
    pub z_shear: f64,
    pub z_normal: f64,
    pub v_limit: f64,
    pub friction_coeff: f64,
    pub relax: Option<f64>,
    pub contact: bool,
    pub nucleation: Vec<f64>,
    pub scene: Scene,
}

/// Evolving state (SoA over grid points).
pub(crate) struct State {
    pub u: FaceFields,
    pub v: FaceFields,
    pub strength: Vec<Strength>,
    pub reg_normal: Vec<f64>,
    pub in_contact: Vec<bool>,
    pub slipping: Vec<bool>,
    pub traction_x: Vec<f64>,
    pub traction_y: Vec<f64>,
}

/// Buffers and the elastodynamic operator.
pub(crate) struct Workspace {
    pub half: HalfSpaces,
    pub f: FaceFields,
}

/// Builds model, initial state (u = 0, pre-crack cut) and workspace; the only place that allocates.
pub(crate) fn build(scene: &Scene) -> Result<(Model, State, Workspace), BuildError> {
    let n = scene.grid_points;
    let dx = scene.grid_spacing();
    let w = scene.wave_speeds();
    let mu = scene.shear_modulus();
    let x: Vec<f64> = (0..n)
        .map(|m| scene.center_x - 0.5 * scene.length + m as f64 * dx)
        .collect();
    let on_precrack: Vec<bool> = x
        .iter()
        .map(|&x| (x - scene.center_x).abs() < scene.half_length)
        .collect();
    let cohesive = CohesiveParams::from_paper(scene.sigma_c, scene.delta_c, scene.beta, scene.kappa);
    let strength = on_precrack
        .iter()
        .map(|&c| {
            if c {
                Strength::precut(&cohesive)
            } else {
                Strength::intact(&cohesive)
            }
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
    let params = HalfSpaceParams {
        shear_modulus: mu,
        cs: w.cs,
        eta: scene.eta(),
        grid_points: n,
        length: scene.length,
        cs_dt_over_dx: scene.cs_dt_over_dx,
        kernel_cutoff: scene.kernel_cutoff,
        max_steps: scene.last_step() as usize + 1,
        convolution: scene.convolution,
        fast_tolerance: scene.fast_tolerance,
    };
    let model = Model {
        n,
        dt,
        x,
        center_index: n / 2,
        on_precrack,
        cohesive,
        z_shear: mu / w.cs,
        z_normal: scene.eta() * mu / w.cs,
        v_limit: {
            // Blow-up guard: 1e3 × the largest particle velocity the loads and strengths can drive (σ/Z).
            let peak = [
                scene.normal.initial,
                scene.normal.r#final,
                scene.shear.initial,
                scene.shear.r#final,
            ]
            .iter()
            .fold(
                scene.sigma_c.max(scene.beta * scene.sigma_c / scene.kappa),
                |a, b| a.max(b.abs()),
            );
            1e3 * (peak + scene.nucleation.map_or(0.0, |n| n.shear.abs())) * w.cs / mu
        },
        friction_coeff: scene.friction_coeff,
        relax: (scene.t_star > 0.0).then(|| dt / scene.t_star),
        contact: scene.contact,
        nucleation,
        scene: scene.clone(),
    };
    let state = State {
        u: FaceFields::zeros(n),
        v: FaceFields::zeros(n),
        strength,
        reg_normal: vec![0.0; n],
        in_contact: vec![false; n],
        slipping: vec![false; n],
        traction_x: vec![0.0; n],
        traction_y: vec![0.0; n],
    };
    let ws = Workspace {
        half: HalfSpaces::new(&params)?,
        f: FaceFields::zeros(n),
    };
    Ok((model, state, ws))
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
    let (sxy, syy) = far_field(model, t);
    ws.half.step(&st.u, &mut ws.f);
    let f = &ws.f;
    let mut bad = None;
    for m in 0..model.n {
        let t01 = sxy + model.nucleation[m];
        let (s1t, s1b) = (t01 + f.top_x[m], t01 + f.bottom_x[m]);
        let (s2t, s2b) = (syy + f.top_y[m], syy + f.bottom_y[m]);
        let opening = st.u.top_y[m] - st.u.bottom_y[m];
        let slip = st.u.top_x[m] - st.u.bottom_x[m];
        let mut s = cohesive::update(&model.cohesive, opening, slip, st.strength[m]);
        let normal = contact::solve(&NormalInput {
            s_top: s2t,
            s_bottom: s2b,
            strength: s.sigma,
            opening,
            impedance: model.z_normal,
            dt: model.dt,
            contact: model.contact,
        });
        let tau = if normal.branch == NormalBranch::Contact {
            s.state = PointState::Contact;
            let prev = st.in_contact[m].then_some(st.reg_normal[m]);
            st.reg_normal[m] = friction::regularized_normal(prev, normal.traction, model.relax);
            model.friction_coeff * st.reg_normal[m].abs()
        } else {
            s.tau
        };
        st.in_contact[m] = normal.branch == NormalBranch::Contact;
        let shear = friction::solve_shear(s1t, s1b, tau, model.z_shear);
        st.strength[m] = s;
        st.slipping[m] = shear.slipping;
        st.traction_x[m] = shear.traction;
        st.traction_y[m] = normal.traction;
        st.v.top_x[m] = shear.v_top;
        st.v.bottom_x[m] = shear.v_bottom;
        st.v.top_y[m] = normal.v_top;
        st.v.bottom_y[m] = normal.v_bottom;
        let vmax = shear
            .v_top
            .abs()
            .max(shear.v_bottom.abs())
            .max(normal.v_top.abs())
            .max(normal.v_bottom.abs());
        if bad.is_none() && (vmax.is_nan() || vmax > model.v_limit) {
            bad = Some(m);
        }
    }
    bad
}

/// u^{n+1} = u^n + Δt v^n (§4 step 7).
pub(crate) fn advance(model: &Model, st: &mut State) {
    let dt = model.dt;
    let (u, v) = (&mut st.u, &st.v);
    for m in 0..model.n {
        u.top_x[m] += dt * v.top_x[m];
        u.top_y[m] += dt * v.top_y[m];
        u.bottom_x[m] += dt * v.bottom_x[m];
        u.bottom_y[m] += dt * v.bottom_y[m];
    }
}
