//! One time step (docs/spectral-model.md §4): FFT → convolution → iFFT (in [`HalfSpaces`]) → interface
//! law (§5) → velocities and tractions; then `advance` updates the displacements. No I/O, no
//! allocation after `build`.

use rayon::prelude::*;

use crate::elastodynamics::{FaceFields, HalfSpaceParams, HalfSpaces, Operator};
use crate::error::BuildError;
use crate::law::cohesive::{CohesiveParams, Strength};
use crate::law::point::{Point, PointLaw};
use crate::law::{self, Drives, Impedances, LawBuild};
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
    /// How the law runs over the points (four at a time where the CPU allows; the same bits).
    pub law_build: LawBuild,
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
        law_build: LawBuild::detect(),
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
        fast_storage: scene.fast_storage,
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
/// velocity is non-finite or exceeds `v_limit` (blow-up), if any. With `then_advance`, each rayon
/// task of the law also updates its points' displacements to u^{n+1} right after their velocities
/// ([`advance_points`], so the bits of [`advance`]), while they are in its core's cache: for a
/// step whose records do not read u^n, in place of a pass of its own.
pub(crate) fn step(
    model: &Model,
    st: &mut State,
    ws: &mut Workspace,
    n: u64,
    then_advance: bool,
) -> Option<usize> {
    let t = n as f64 * model.dt;
    let load = far_field(model, t);
    ws.half.step_timed(&st.u, &mut ws.f, &mut ws.clock);
    let dt = then_advance.then_some(model.dt);
    let blown = solve_law(model, load, &ws.f, &mut st.u, &mut st.points, dt);
    ws.clock.lap(Phase::Law);
    blown
}

/// The interface law at every point, [`LAW_CHUNK`] points per rayon task: the first point whose
/// velocity blew up, if any. With `advance` = Some(Δt), each task then takes its points to
/// u^{n+1}.
fn solve_law(
    model: &Model,
    load: (f64, f64),
    f: &FaceFields,
    u: &mut FaceFields,
    points: &mut [Point],
    advance: Option<f64>,
) -> Option<usize> {
    points
        .par_chunks_mut(LAW_CHUNK)
        .zip(par_point_chunks(u, LAW_CHUNK))
        .enumerate()
        .filter_map(|(c, (chunk, [tx, ty, bx, by]))| {
            let blown = solve_points_with(model, load, c * LAW_CHUNK, f, [&*tx, &*ty, &*bx, &*by], chunk);
            if let Some(dt) = advance {
                advance_points(dt, chunk, [tx, ty, bx, by]);
            }
            blown
        })
        .min()
}

/// Grid points per rayon task of the law. Each point's result depends on that point alone, so
/// the chunking changes no bit of it (pinned by a test).
const LAW_CHUNK: usize = 512;

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
///   Counted with the law, in whose tasks it runs at every step whose records do not read u^n
///   ([`step`]); the others' update pass is booked to [`Phase::Update`], which counts no work.
pub(crate) fn work(model: &Model, ws: &Workspace) -> StepWork {
    let n = model.n as f64;
    let point = std::mem::size_of::<Point>() as f64;
    let mut w = ws.half.work();
    let law = Work {
        flops: n * LAW_FLOPS_PER_POINT,
        read: n * (64.0 + 8.0 + point),
        written: n * point,
    };
    let update = Work {
        flops: n * 8.0,
        read: n * (32.0 + 32.0),
        written: n * 32.0,
    };
    w.add(Phase::Law, law + update);
    w
}

/// Interface law at the points `first..first + points.len()` (§5.4), [`law::solve_points`] with
/// their loads: returns the first point whose velocity blew up, if any.
#[cfg(test)]
fn solve_points(
    model: &Model,
    load: (f64, f64),
    first: usize,
    f: &FaceFields,
    u: &FaceFields,
    points: &mut [Point],
) -> Option<usize> {
    let r = first..first + points.len();
    let u = [&u.top_x, &u.top_y, &u.bottom_x, &u.bottom_y].map(|u| &u[r.clone()]);
    solve_points_with(model, load, first, f, u, points)
}

/// As `solve_points`, given the points' own displacements u (top x, top y, bottom x, bottom y).
fn solve_points_with(
    model: &Model,
    load: (f64, f64),
    first: usize,
    f: &FaceFields,
    [u_top_x, u_top_y, u_bottom_x, u_bottom_y]: [&[f64]; 4],
    points: &mut [Point],
) -> Option<usize> {
    let r = first..first + points.len();
    let d = Drives {
        load,
        nucleation: &model.nucleation[r.clone()],
        f_top_x: &f.top_x[r.clone()],
        f_bottom_x: &f.bottom_x[r.clone()],
        f_top_y: &f.top_y[r.clone()],
        f_bottom_y: &f.bottom_y[r],
        u_top_x,
        u_bottom_x,
        u_top_y,
        u_bottom_y,
    };
    law::solve_points(model.law_build, &model.law, model.v_limit, &d, points).map(|i| first + i)
}

/// u^{n+1} = u^n + Δt v^n (§4.2 step 7), one rayon task a thread, each of at least [`LAW_CHUNK`]
/// points: the work is the same at every point, so more tasks than threads only add their hand-outs.
pub(crate) fn advance(model: &Model, st: &mut State) {
    let dt = model.dt;
    let chunk = st
        .points
        .len()
        .div_ceil(rayon::current_num_threads())
        .max(LAW_CHUNK);
    st.points
        .par_chunks(chunk)
        .zip(par_point_chunks(&mut st.u, chunk))
        .for_each(|(points, u)| advance_points(dt, points, u));
}

/// The four components of `u` (top x, top y, bottom x, bottom y) in chunks of `chunk` points,
/// one item a chunk, to zip with the points' own chunks.
fn par_point_chunks(
    u: &mut FaceFields,
    chunk: usize,
) -> impl IndexedParallelIterator<Item = [&mut [f64]; 4]> {
    let FaceFields {
        top_x,
        top_y,
        bottom_x,
        bottom_y,
    } = u;
    let top = top_x.par_chunks_mut(chunk).zip(top_y.par_chunks_mut(chunk));
    let bottom = bottom_x.par_chunks_mut(chunk).zip(bottom_y.par_chunks_mut(chunk));
    top.zip(bottom).map(|((tx, ty), (bx, by))| [tx, ty, bx, by])
}

/// u += Δt v at each of `points`, u given as its (top x, top y, bottom x, bottom y) slices.
fn advance_points(dt: f64, points: &[Point], [tx, ty, bx, by]: [&mut [f64]; 4]) {
    let u = tx
        .iter_mut()
        .zip(ty.iter_mut())
        .zip(bx.iter_mut().zip(by.iter_mut()));
    for (p, ((tx, ty), (bx, by))) in points.iter().zip(u) {
        *tx += dt * p.v[0];
        *ty += dt * p.v[1];
        *bx += dt * p.v[2];
        *by += dt * p.v[3];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::PointState;
    use crate::law::point::ContactFriction;

    /// The centre crack's model with a nucleation stress that differs at every point, and face
    /// fields that differ at every point and drive every branch of the law: stuck, slipping,
    /// open, in contact; intact, cohesive, broken.
    fn model_and_fields() -> (Model, Vec<Point>, FaceFields, FaceFields) {
        let scene = Scene::from_toml_str(include_str!("../../scenes/center-crack.toml")).unwrap();
        let (mut model, st, _) = build(&scene).unwrap();
        let n = model.n;
        model.nucleation = (0..n).map(|m| 20.0 * m as f64).collect();
        let (mut f, mut u) = (FaceFields::zeros(n), FaceFields::zeros(n));
        for m in 0..n {
            let x = m as f64;
            f.top_x[m] = 0.6e6 * (0.37 * x).sin();
            f.bottom_x[m] = 0.3e6 * (0.11 * x).cos();
            f.top_y[m] = 0.5e6 * (0.23 * x).sin();
            f.bottom_y[m] = -0.4e6 * (0.05 * x).cos();
            // every fourth point keeps zero jumps (and its strength, if intact)
            if m % 4 != 0 {
                u.top_x[m] = 0.6e-4 * (0.013 * x).sin();
                u.top_y[m] = 0.6e-4 * (0.017 * x).cos();
            }
        }
        (model, st.points, f, u)
    }

    #[test]
    fn the_law_in_chunks_is_the_law_in_one_pass_to_the_bit() {
        let (model, points, f, u) = model_and_fields();
        assert!(model.n >= 4 * LAW_CHUNK, "several chunks");
        let load = (0.1e6, -0.05e6);
        let mut serial = points.clone();
        assert_eq!(solve_points(&model, load, 0, &f, &u, &mut serial), None);
        let mut chunked = points;
        assert_eq!(
            solve_law(&model, load, &f, &mut u.clone(), &mut chunked, None),
            None
        );
        // every branch taken, so that equality is not that of a uniform interface
        let states = |s: PointState| serial.iter().filter(|p| p.strength.state == s).count();
        for s in [
            PointState::Intact,
            PointState::Cohesive,
            PointState::Broken,
            PointState::Contact,
        ] {
            assert!(states(s) > 0, "{s:?}");
        }
        assert!(serial.iter().any(|p| p.slipping) && serial.iter().any(|p| !p.slipping));
        for (m, (a, b)) in serial.iter().zip(&chunked).enumerate() {
            assert_eq!(bits(a), bits(b), "point {m}");
            assert_eq!(a, b, "point {m}");
        }
    }

    /// Every field of a point, as bits.
    fn bits(p: &Point) -> ([u64; 9], PointState, [bool; 3]) {
        let v = [
            p.strength.sigma,
            p.strength.tau,
            p.reg_normal,
            p.traction[0],
            p.traction[1],
            p.v[0],
            p.v[1],
            p.v[2],
            p.v[3],
        ];
        (
            v.map(f64::to_bits),
            p.strength.state,
            [p.in_contact, p.slipping, p.friction_on],
        )
    }

    /// The law four points at a time (AVX2) gives every point the bits of the scalar law, for both
    /// friction rules, with and without the Prakash regularisation and contact, on groups of four
    /// whose points take different branches (broken and intact ones among them) and on groups
    /// whose points all take the same one (the groups where a branch is skipped), over a run of
    /// points that starts and ends inside a group (the rest goes one by one), with NaN and
    /// infinite loads at some points.
    #[test]
    fn the_law_on_four_lanes_gives_the_bits_of_the_scalar_law() {
        if LawBuild::detect() != LawBuild::Avx2 {
            eprintln!("no AVX2 on this CPU: nothing to compare");
            return;
        }
        let (mut model, points, mut f, mut u) = model_and_fields();
        // the second half in blocks of eight equal points: whole groups on one branch
        let n = model.n;
        for m in n / 2..n {
            let b = m - m % 8;
            for x in [&mut f.top_x, &mut f.bottom_x, &mut f.top_y, &mut f.bottom_y] {
                x[m] = x[b];
            }
            for x in [&mut u.top_x, &mut u.bottom_x, &mut u.top_y, &mut u.bottom_y] {
                x[m] = x[b];
            }
            model.nucleation[m] = model.nucleation[b];
        }
        let mut points = points;
        // broken and intact points alternate in one stretch: groups whose strengths differ
        for p in points[n / 8..n / 4].iter_mut().step_by(3) {
            p.strength = Strength::precut(&model.law.cohesive);
        }
        for (m, p) in points.iter_mut().enumerate().skip(n / 2) {
            // precut and intact blocks of eight alternate
            p.strength = if (m / 8) % 2 == 0 {
                Strength::precut(&model.law.cohesive)
            } else {
                Strength::intact(&model.law.cohesive)
            };
        }
        f.top_x[101] = f64::NAN;
        f.bottom_y[202] = f64::INFINITY;
        u.top_y[303] = f64::NEG_INFINITY;
        u.bottom_x[3003] = f64::NAN;
        let run = 5..n - 6;
        let mut seen = [0usize; 8];
        for rule in [ContactFriction::AllFaces, ContactFriction::FailedOnly] {
            for relax in [None, Some(0.05)] {
                for contact in [true, false] {
                    model.law.rule = rule;
                    model.law.relax = relax;
                    model.law.contact = contact;
                    // two steps, so that the second starts from states the first left
                    let (mut scalar, mut lanes) = (points.clone(), points.clone());
                    for load in [(0.1e6, -0.05e6), (0.02e6, 0.3e6)] {
                        model.law_build = LawBuild::Scalar;
                        let a = solve_points(&model, load, run.start, &f, &u, &mut scalar[run.clone()]);
                        model.law_build = LawBuild::Avx2;
                        let b = solve_points(&model, load, run.start, &f, &u, &mut lanes[run.clone()]);
                        assert_eq!(a, b, "{rule:?} {relax:?} {contact}: the first blown point");
                        for (m, (a, b)) in scalar.iter().zip(&lanes).enumerate() {
                            assert_eq!(
                                bits(a),
                                bits(b),
                                "point {m}, {rule:?}, {relax:?}, contact {contact}"
                            );
                        }
                    }
                    for p in &scalar[run.clone()] {
                        seen[p.strength.state as usize] += 1;
                        seen[4] += p.slipping as usize;
                        seen[5] += !p.slipping as usize;
                        seen[6] += p.friction_on as usize;
                        seen[7] += !p.friction_on as usize;
                    }
                }
            }
        }
        // every state, slip and stick, friction on and off were met
        assert!(seen.iter().all(|&c| c > 0), "{seen:?}");
    }

    /// The first point that blows up is reported by its index on the interface, whichever chunk
    /// holds it and whatever the later chunks hold.
    #[test]
    fn the_first_blown_point_is_found_across_chunks() {
        let (model, points, mut f, u) = model_and_fields();
        let (late, early) = (3 * LAW_CHUNK + 7, LAW_CHUNK + 5);
        f.top_x[late] = f64::NAN;
        f.bottom_y[early] = 1e30;
        let mut p = points.clone();
        assert_eq!(
            solve_law(&model, (0.0, 0.0), &f, &mut u.clone(), &mut p, None),
            Some(early)
        );
        f.bottom_y[early] = 0.0;
        let mut p = points;
        assert_eq!(
            solve_law(&model, (0.0, 0.0), &f, &mut u.clone(), &mut p, None),
            Some(late)
        );
    }

    /// The law's tasks that also take their points to u^{n+1} leave the velocities, tractions
    /// and states of the law alone and the displacements of the update pass after it, bit for bit.
    #[test]
    fn the_law_tasks_advance_u_as_the_update_pass_does() {
        let (model, points, f, u) = model_and_fields();
        let load = (0.1e6, -0.05e6);
        let mut apart = State {
            u: u.clone(),
            points: points.clone(),
        };
        assert_eq!(
            solve_law(&model, load, &f, &mut apart.u, &mut apart.points, None),
            None
        );
        assert_eq!(apart.u, u, "the law alone leaves u^n");
        advance(&model, &mut apart);
        let mut fused = State { u, points };
        assert_eq!(
            solve_law(&model, load, &f, &mut fused.u, &mut fused.points, Some(model.dt)),
            None
        );
        for (m, (a, b)) in apart.points.iter().zip(&fused.points).enumerate() {
            assert_eq!(bits(a), bits(b), "point {m}");
        }
        let fields = |u: &FaceFields| {
            [&u.top_x, &u.top_y, &u.bottom_x, &u.bottom_y]
                .map(|c| c.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
        };
        assert_eq!(fields(&apart.u), fields(&fused.u));
        assert!(
            apart.points.iter().any(|p| p.v.iter().any(|&v| v != 0.0)),
            "some point moves"
        );
    }
}
