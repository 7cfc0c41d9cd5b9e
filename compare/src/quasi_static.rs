//! Paper Appendix B: is the loading quasi-static? The measured ratio E_kin/E_int (kinetic over
//! strain energy) against time, next to the ratio the imposed quasi-static motion carries by
//! itself, and its largest value over the phases the paper's figures treat as quasi-static.
//!
//! The estimate moves the uncracked FE box with the far field of the case: u_x = γ(t) y +
//! ε_xx(t) (x − x_c), u_y = ε_yy(t) y, with γ = s_xy/G, ε_yy = (1 − ν) s_yy/(2G), ε_xx =
//! −ν s_yy/(2G) with the lateral contraction (0 without). Its kinetic energy over its strain
//! energy, ≈ (a²/3c²)(σ̇/σ)², grows without bound as t → 0 for any load starting from rest, so
//! the paper's "below 5 % during the simulation" cannot hold from t = 0; the claim is tested in
//! the quasi-static phases instead (docs/cases.md).

use serde::Serialize;

/// The Appendix B limit: E_kin/E_int ≤ 5 % [-].
pub const LIMIT: f64 = 0.05;

/// The y range of the Appendix B figures [-]: the estimate of the imposed motion falls to 0 where
/// the ramps end, and values above 100 occur only in the first steps.
pub const RATIO_AXIS: (f64, f64) = (1e-4, 1e2);

/// One sample of the ratio (the CSV next to each Appendix B figure).
#[derive(Debug, Clone, Serialize)]
pub struct RatioRow {
    /// Which run (model or friction value).
    pub run: String,
    /// t/T [-].
    #[serde(rename = "t_over_T")]
    pub t_over_t: f64,
    /// Measured E_kin/E_int [-].
    pub kinetic_over_internal: f64,
    /// E_kin/E_int of the imposed quasi-static motion alone [-] (NaN without the far-field
    /// boundary displacements).
    pub quasi_static_estimate: f64,
}

/// E_kin/E_int [-] of the uncracked FE box of `scene` moved quasi-statically by its far field at
/// time t [s]; NaN when the box is loaded otherwise (`[fem.boundary]`) or is unloaded.
pub fn estimate(scene: &fem::Scene, t: f64) -> f64 {
    if scene.fem.boundary.is_some() {
        return f64::NAN;
    }
    let m = &scene.material;
    let (e, nu, rho) = (m.youngs_modulus, m.poisson_ratio, m.density);
    let g = e / (2.0 * (1.0 + nu));
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let contraction = if scene.fem.lateral_contraction { 1.0 } else { 0.0 };
    let strains = |s_yy: f64, s_xy: f64| {
        let eyy = (1.0 - nu) * s_yy / (2.0 * g);
        (contraction * -nu * s_yy / (2.0 * g), eyy, s_xy / g)
    };
    let l = &scene.loading;
    let (exx, eyy, gamma) = strains(l.normal.value(t), l.shear.value(t));
    let (dxx, dyy, dgamma) = strains(l.normal.rate(t), l.shear.rate(t));
    let [x0, x1] = scene.fem.x_range;
    let [y0, y1] = scene.fem.y_range;
    let xc = scene.center_x();
    let (xa, xb) = (x0 - xc, x1 - xc);
    let (w, h) = (x1 - x0, y1 - y0);
    // ∫∫ y², ∫∫ x'², ∫∫ x'y over the box [m⁴]
    let iyy = w * (y1.powi(3) - y0.powi(3)) / 3.0;
    let ixx = h * (xb.powi(3) - xa.powi(3)) / 3.0;
    let ixy = 0.25 * (xb * xb - xa * xa) * (y1 * y1 - y0 * y0);
    let kinetic =
        0.5 * rho * ((dgamma * dgamma + dyy * dyy) * iyy + dxx * dxx * ixx + 2.0 * dgamma * dxx * ixy);
    let density =
        0.5 * (lambda * (exx + eyy).powi(2) + 2.0 * g * (exx * exx + eyy * eyy) + g * gamma * gamma);
    let internal = density * w * h;
    if internal > 0.0 {
        kinetic / internal
    } else {
        f64::NAN
    }
}

/// The ratio rows of one run (samples with E_int > 0).
pub fn ratio_rows(run: &str, scene: &fem::Scene, out: &fem::RunOutput) -> Vec<RatioRow> {
    let big_t = scene.duration();
    out.energy
        .iter()
        .filter(|e| e.strain > 0.0)
        .map(|e| RatioRow {
            run: run.to_string(),
            t_over_t: e.t / big_t,
            kinetic_over_internal: e.kinetic / e.strain,
            quasi_static_estimate: estimate(scene, e.t),
        })
        .collect()
}

/// The largest E_kin/E_int [-] over the samples with t0 ≤ t ≤ t1 [s] and E_int > 0, with its
/// time [s]; `None` for an empty window.
pub fn max_ratio(out: &fem::RunOutput, t0: f64, t1: f64) -> Option<(f64, f64)> {
    out.energy
        .iter()
        .filter(|e| e.t >= t0 && e.t <= t1 && e.strain > 0.0)
        .map(|e| (e.kinetic / e.strain, e.t))
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> fem::Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
        fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    #[test]
    fn estimate_of_pure_shear_is_a_squared_over_3_cs_squared_times_the_rate_squared() {
        // once the normal ramp is over, only the shear moves: E_kin/E_int =
        // ρ γ̇² ∫∫y² / (G γ² + strain energy of s_yy) ... checked against that formula
        let s = scene();
        let t = 0.5 * s.duration();
        let m = &s.material;
        let g = m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
        let (syy, sxy, dsxy) = (
            s.loading.normal.value(t),
            s.loading.shear.value(t),
            s.loading.shear.rate(t),
        );
        let a = 0.125;
        let kinetic_density = 0.5 * m.density * (dsxy / g).powi(2) * a * a / 3.0;
        let internal_density = 0.5 * ((1.0 - m.poisson_ratio) * syy * syy / (2.0 * g) + sxy * sxy / g);
        let want = kinetic_density / internal_density;
        let got = estimate(&s, t);
        assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
        assert!(got < 0.01, "a slow ramp is quasi-static: {got}");
    }

    #[test]
    fn estimate_diverges_at_the_start_of_a_ramp() {
        let s = scene();
        assert!(estimate(&s, 1e-3 * s.duration()) > 1.0);
        assert!(estimate(&s, 0.0).is_nan(), "unloaded");
    }

    #[test]
    fn max_ratio_looks_only_inside_the_window() {
        let rec = |t: f64, kinetic: f64| fem::EnergyRecord {
            t,
            kinetic,
            strain: 1.0,
            ..Default::default()
        };
        let out = fem::RunOutput {
            energy: vec![rec(0.0, 9.0), rec(1.0, 0.02), rec(2.0, 0.04), rec(3.0, 9.0)],
            ..Default::default()
        };
        assert_eq!(max_ratio(&out, 0.5, 2.5), Some((0.04, 2.0)));
        assert_eq!(max_ratio(&out, 5.0, 6.0), None);
    }
}
