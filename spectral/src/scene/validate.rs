//! The checks of a spectral scene, section by section, each problem naming its key: the material,
//! the interface, crack and friction, the loading, the grid and the step, the solver's options,
//! and the geometry (the crack against the periodic length, the process zone against the grid).

use super::*;

/// Collects every problem of a scene instead of stopping at the first.
#[derive(Default)]
struct Problems(Vec<SceneError>);

impl Problems {
    /// `value` if finite and `ok`; otherwise records an out-of-range error for `key`.
    fn num(&mut self, key: &str, value: f64, ok: bool, allowed: &str) -> Option<f64> {
        if ok && value.is_finite() {
            Some(value)
        } else {
            self.0.push(SceneError::OutOfRange {
                field: key.to_string(),
                value,
                allowed: allowed.to_string(),
            });
            None
        }
    }

    /// Records that `key` does not fit with the rest of the scene.
    fn inconsistent(&mut self, key: &str, message: String) {
        self.0.push(SceneError::Inconsistent {
            key: key.to_string(),
            message,
        });
    }

    fn ramp(&mut self, key: &str, r: &Ramp, duration: f64) {
        self.num(&format!("{key}.initial"), r.initial, true, "a finite stress [Pa]");
        self.num(&format!("{key}.final"), r.r#final, true, "a finite stress [Pa]");
        self.num(
            &format!("{key}.ramp_start"),
            r.ramp_start,
            // equal values are a constant, which may start anywhere
            r.ramp_start >= 0.0 && (r.ramp_start < duration || r.r#final == r.initial),
            "[0, loading.duration) s: a ramp starting at or after T never reaches its final value",
        );
        self.num(
            &format!("{key}.ramp_end"),
            r.ramp_end,
            r.ramp_end >= r.ramp_start,
            ">= ramp_start [s]",
        );
    }
}

/// Validates every section, collecting the problems of each (one invalid key does not hide the
/// next); returns them all, or the scene.
pub(super) fn validate(r: RawScene) -> Result<Scene, SceneError> {
    let raw = r.clone();
    let mut p = Problems::default();
    let m = &r.material;
    let (top, bottom) = material(&mut p, m);
    let halves = top.zip(bottom).map(|(t, b)| (t, b.unwrap_or(t)));
    let i = &r.interface;
    let (sigma_c, delta_c, a, contact_friction) = interface_crack_friction(&mut p, &r);
    let mu_f = r.friction.friction_coeff;
    let l = &r.loading;
    let duration = p.num("loading.duration", l.duration, l.duration > 0.0, "> 0 s");
    let t_end = duration.unwrap_or(f64::INFINITY);
    p.ramp("loading.normal", &l.normal, t_end);
    p.ramp("loading.shear", &l.shear, t_end);
    let s = &r.spectral;
    let n = s.grid_points;
    let cs = halves.map(|(t, b)| t.wave_speeds().cs.max(b.wave_speeds().cs));
    let (length, dx, cfl) = grid_and_step(&mut p, s, cs);
    let (fast_tolerance, fast_storage, initial_interface) = options(&mut p, s, t_end);
    geometry(&mut p, &r, length, a, initial_interface);
    if let Some((t, b)) = halves {
        well_posed(&mut p, &r, t, b);
    }
    let youngs = halves.map(|(t, b)| t.youngs_modulus.min(b.youngs_modulus));
    if let (Some(e), Some(sc), Some(dc), Some(dx)) = (youngs, sigma_c, delta_c, dx) {
        zone_resolution(&mut p, s, e, sc, dc, dx);
    }
    let errors = p.0;
    let (Some(cfl), Some(top), Some(bottom), true) = (cfl, top, bottom, errors.is_empty()) else {
        return Err(collected(errors));
    };
    Ok(Scene {
        youngs_modulus: top.youngs_modulus,
        poisson_ratio: top.poisson_ratio,
        density: top.density,
        bottom,
        sigma_c: i.sigma_c,
        delta_c: i.delta_c,
        beta: i.beta,
        kappa: i.kappa,
        half_length: r.crack.half_length,
        center_x: r.crack.center_x,
        friction_coeff: mu_f,
        contact_friction,
        duration: l.duration,
        normal: l.normal,
        shear: l.shear,
        length: s.length,
        grid_points: n as usize,
        cs_dt_over_dx: cfl,
        kernel_cutoff: s.kernel_cutoff,
        t_star: s.t_star,
        output_interval: s.output_interval,
        field_output_interval: s.field_output_interval,
        convolution: s.convolution.unwrap_or(Convolution::Fast),
        fast_tolerance,
        fast_storage,
        contact: s.contact.unwrap_or(true),
        nucleation: s.nucleation,
        initial_interface,
        raw,
    })
}

/// `[material]`: the top half-space and, when the table is split, the bottom one, each `None`
/// if refused. The flat keys give two identical half-spaces; `top` and `bottom` give two
/// materials (docs/spectral-model.md §2.1). Either form, not both.
fn material(p: &mut Problems, m: &RawMaterial) -> (Option<Solid>, Option<Option<Solid>>) {
    let flat = [m.youngs_modulus, m.poisson_ratio, m.density];
    match (&m.top, &m.bottom) {
        (None, None) => {
            let keys = ["youngs_modulus", "poisson_ratio", "density"];
            let mut missing = false;
            for (key, v) in keys.iter().zip(flat) {
                if v.is_none() {
                    missing = true;
                    p.inconsistent(
                        &format!("material.{key}"),
                        "missing: give youngs_modulus [Pa], poisson_ratio [-] and density \
                         [kg/m^3], or split [material] into [material.top] and [material.bottom]"
                            .to_string(),
                    );
                }
            }
            let [e, nu, rho] = flat;
            let solid = RawSolid {
                youngs_modulus: e.unwrap_or(f64::NAN),
                poisson_ratio: nu.unwrap_or(f64::NAN),
                density: rho.unwrap_or(f64::NAN),
            };
            let top = if missing {
                None
            } else {
                solid_of(p, "material", &solid)
            };
            (top, Some(None))
        }
        (Some(top), Some(bottom)) => {
            let keys = ["youngs_modulus", "poisson_ratio", "density"];
            let mut mixed = false;
            for (key, v) in keys.iter().zip(flat) {
                if v.is_some() {
                    mixed = true;
                    p.inconsistent(
                        &format!("material.{key}"),
                        "given beside [material.top] and [material.bottom]: with two materials, \
                         every key belongs to one of them"
                            .to_string(),
                    );
                }
            }
            let top = solid_of(p, "material.top", top);
            let bottom = solid_of(p, "material.bottom", bottom);
            if mixed {
                return (None, None);
            }
            (top, bottom.map(Some))
        }
        (Some(_), None) | (None, Some(_)) => {
            let missing = if m.top.is_none() { "top" } else { "bottom" };
            p.inconsistent(
                &format!("material.{missing}"),
                "missing: a split [material] needs both [material.top] and [material.bottom]".to_string(),
            );
            (None, None)
        }
    }
}

/// Coulomb friction between two different materials with no regularisation is ill-posed (Adams
/// 1995; Ranjith & Rice 2001): steady sliding is unstable at every wavelength, with growth rates
/// that grow without bound as the wavelength falls, so the answer depends on the grid and not on
/// the physics. The Prakash law (paper eq. 14) with t* > 0 is what makes the problem well-posed,
/// so μ > 0 between different halves needs t* > 0 (docs/spectral-model.md §5.3).
fn well_posed(p: &mut Problems, r: &RawScene, top: Solid, bottom: Solid) {
    if top != bottom && r.friction.friction_coeff > 0.0 && r.spectral.t_star == 0.0 {
        p.inconsistent(
            "spectral.t_star",
            format!(
                "0 with friction.friction_coeff = {} between two different materials: Coulomb \
                 friction on a bimaterial interface is ill-posed without regularisation (Adams \
                 1995; Ranjith & Rice 2001), so the result would depend on the grid; give t* > 0 \
                 [s] (a few steps or more, docs/spectral-model.md §5.3)",
                r.friction.friction_coeff
            ),
        );
    }
}

/// One half-space under `key`: E [Pa], ν [-] and ρ [kg/m³] checked, or `None` if any is refused.
fn solid_of(p: &mut Problems, key: &str, m: &RawSolid) -> Option<Solid> {
    let youngs = p.num(
        &format!("{key}.youngs_modulus"),
        m.youngs_modulus,
        m.youngs_modulus > 0.0,
        "> 0 Pa",
    );
    let nu = p.num(
        &format!("{key}.poisson_ratio"),
        m.poisson_ratio,
        m.poisson_ratio > 0.0 && m.poisson_ratio < 0.5,
        "(0, 0.5) (the kernels of the spectral model need ν > 0)",
    );
    let density = p.num(
        &format!("{key}.density"),
        m.density,
        m.density > 0.0,
        "> 0 kg/m^3",
    );
    Some(Solid {
        youngs_modulus: youngs?,
        poisson_ratio: nu?,
        density: density?,
    })
}

/// `[interface]`, `[crack]` and `[friction]`: σ_c [Pa], δ_c [m], the half-length a [m] (each
/// `None` if refused) and the friction rule.
fn interface_crack_friction(
    p: &mut Problems,
    r: &RawScene,
) -> (Option<f64>, Option<f64>, Option<f64>, ContactFriction) {
    let i = &r.interface;
    let sigma_c = p.num("interface.sigma_c", i.sigma_c, i.sigma_c > 0.0, "> 0 Pa");
    let delta_c = p.num("interface.delta_c", i.delta_c, i.delta_c > 0.0, "> 0 m");
    p.num("interface.beta", i.beta, i.beta > 0.0, "> 0");
    p.num("interface.kappa", i.kappa, i.kappa > 0.0, "> 0");
    let a = p.num(
        "crack.half_length",
        r.crack.half_length,
        r.crack.half_length >= 0.0,
        ">= 0 m",
    );
    p.num("crack.center_x", r.crack.center_x, true, "a finite position [m]");
    let mu_f = r.friction.friction_coeff;
    p.num(
        "friction.friction_coeff",
        mu_f,
        (0.0..=10.0).contains(&mu_f),
        "[0, 10]",
    );
    let contact_friction = match r.friction.contact_friction.as_deref() {
        None | Some("all_faces") => ContactFriction::AllFaces,
        Some("failed_only") => ContactFriction::FailedOnly,
        Some(other) => {
            p.inconsistent(
                "friction.contact_friction",
                format!("\"{other}\" is not allowed; allowed \"all_faces\" (default) or \"failed_only\""),
            );
            ContactFriction::AllFaces
        }
    };
    (sigma_c, delta_c, a, contact_friction)
}

/// The grid and the step: the periodic length X [m], Δx [m] and c_s Δt/Δx [-] (each `None` if
/// refused), from `cs_dt_over_dx` or from `time_step` with c_s of the material `[E, ν, ρ]`.
fn grid_and_step(
    p: &mut Problems,
    s: &RawSpectral,
    cs: Option<f64>,
) -> (Option<f64>, Option<f64>, Option<f64>) {
    let length = p.num("spectral.length", s.length, s.length > 0.0, "> 0 m");
    let n = s.grid_points;
    let grid = p.num(
        "spectral.grid_points",
        n as f64,
        (4..=(1 << 24)).contains(&n) && n % 2 == 0,
        "an even integer in [4, 2^24]",
    );
    // c_s (of the faster half-space) from the material, Δx from the grid: both needed by the
    // step and the geometry checks
    let dx = length.zip(grid).map(|(x, n)| x / n);
    let cfl = match (s.cs_dt_over_dx, s.time_step) {
        (Some(b), None) => p.num(
            "spectral.cs_dt_over_dx",
            b,
            b > 0.0 && b <= 0.5,
            "(0, 0.5] (docs/spectral-model.md §7.8)",
        ),
        (None, Some(dt)) => match cs.zip(dx) {
            Some((cs, dx)) => {
                let b = dt * cs / dx;
                p.num(
                    "spectral.time_step",
                    dt,
                    b > 0.0 && b <= 0.5,
                    &format!(
                        "(0, {:e}] s, i.e. c_s dt/dx in (0, 0.5] (docs/spectral-model.md §7.8)",
                        0.5 * dx / cs
                    ),
                )
                .map(|_| b)
            }
            None => None,
        },
        (Some(_), Some(_)) => {
            p.inconsistent(
                "spectral.time_step",
                "give cs_dt_over_dx [-] or time_step [s], not both".to_string(),
            );
            None
        }
        (None, None) => {
            p.inconsistent(
                "spectral",
                "needs one of cs_dt_over_dx [-] or time_step [s]".to_string(),
            );
            None
        }
    };
    (length, dx, cfl)
}

/// The solver's options: the kernel cut-off, t* [s], the output intervals [s] (within the
/// duration `t_end` [s]), the fast convolution's tolerance [-] and state storage, and the initial
/// interface.
fn options(p: &mut Problems, s: &RawSpectral, t_end: f64) -> (f64, FastStorage, InitialInterface) {
    p.num(
        "spectral.kernel_cutoff",
        s.kernel_cutoff,
        s.kernel_cutoff > 0.0 && s.kernel_cutoff <= 1000.0,
        "(0, 1000]",
    );
    p.num(
        "spectral.t_star",
        s.t_star,
        s.t_star >= 0.0,
        ">= 0 s (0: plain Coulomb)",
    );
    p.num(
        "spectral.output_interval",
        s.output_interval,
        s.output_interval > 0.0 && s.output_interval <= t_end,
        "(0, loading.duration] s",
    );
    if let Some(fi) = s.field_output_interval {
        p.num(
            "spectral.field_output_interval",
            fi,
            fi > 0.0 && fi <= t_end,
            "(0, loading.duration] s",
        );
    }
    let fast_tolerance = s.fast_tolerance.unwrap_or(DEFAULT_FAST_TOLERANCE);
    p.num(
        "spectral.fast_tolerance",
        fast_tolerance,
        (1e-10..=1e-2).contains(&fast_tolerance),
        "[1e-10, 1e-2]",
    );
    let fast_storage = match s.fast_storage.as_deref().map(|w| (w, FastStorage::from_name(w))) {
        None => FastStorage::F64,
        Some((_, Some(storage))) => storage,
        Some((other, None)) => {
            p.inconsistent(
                "spectral.fast_storage",
                format!("\"{other}\" is not allowed; allowed \"f64\" (default) or \"f32\""),
            );
            FastStorage::F64
        }
    };
    if fast_storage != FastStorage::F64 && s.convolution == Some(Convolution::Direct) {
        p.inconsistent(
            "spectral.fast_storage",
            "stores the states of the fast convolution; the direct one (spectral.convolution = \
             \"direct\") keeps its history in double precision: remove the key or use the fast path"
                .to_string(),
        );
    }
    let initial_interface = match s.initial_interface.as_deref() {
        None | Some("pre_crack") => InitialInterface::PreCrack,
        Some("broken") => InitialInterface::Broken,
        Some(other) => {
            p.inconsistent(
                "spectral.initial_interface",
                format!("\"{other}\" is not allowed; allowed \"pre_crack\" (default) or \"broken\""),
            );
            InitialInterface::PreCrack
        }
    };
    (fast_tolerance, fast_storage, initial_interface)
}

/// The crack against the periodic length X [m] (`length`), and the nucleation patch inside it.
fn geometry(
    p: &mut Problems,
    r: &RawScene,
    length: Option<f64>,
    a: Option<f64>,
    initial_interface: InitialInterface,
) {
    let s = &r.spectral;
    if let (Some(x), Some(a), InitialInterface::PreCrack) = (length, a, initial_interface)
        && 4.0 * a >= x
    {
        p.inconsistent(
            "spectral.length",
            format!(
                "{x} m is at most twice the crack length 2a = {} m: the crack's periodic images \
                 would be closer than its own length; use a length of at least 4a (the \
                 centre-crack case uses 30a = {} m)",
                2.0 * a,
                30.0 * a
            ),
        );
    }
    if let (Some(nu), Some(x)) = (&s.nucleation, length) {
        p.num(
            "spectral.nucleation.shear",
            nu.shear,
            true,
            "a finite stress [Pa]",
        );
        let hw = p.num(
            "spectral.nucleation.half_width",
            nu.half_width,
            nu.half_width > 0.0,
            "> 0 m",
        );
        let centre = r.crack.center_x;
        p.num(
            "spectral.nucleation.center",
            nu.center,
            (nu.center - centre).abs() + hw.unwrap_or(0.0) <= 0.5 * x,
            &format!(
                "within the periodic length: |center − crack.center_x| + half_width <= {} m",
                0.5 * x
            ),
        );
    }
}

/// The process zone l_p = E δ_c/(2σ_c) [m] against the grid spacing `dx` [m] (E [Pa], σ_c [Pa],
/// δ_c [m]): a zone narrower than one grid point is refused.
fn zone_resolution(p: &mut Problems, s: &RawSpectral, e: f64, sc: f64, dc: f64, dx: f64) {
    let n = s.grid_points;
    let lp = process_zone(e, sc, dc);
    if lp / dx < MIN_POINTS_PER_ZONE {
        p.inconsistent(
            "spectral.grid_points",
            format!(
                "{n} points give dx = {dx:e} m, larger than the process zone l_p = E δ_c/(2σ_c) \
                 = {lp:e} m: the cohesive zone falls between grid points; use at least {} points \
                 (l_p/dx >= {WARN_POINTS_PER_ZONE} is advised)",
                (WARN_POINTS_PER_ZONE * s.length / lp).ceil()
            ),
        );
    }
}
