//! The records of the penalty study (paper Appendix D, Figure D.15), computed from one FE run:
//! the upper-face interpenetration profile at t/T = 0.6 (D.15a), the mean contact tractions
//! against time (D.15b, c), and their window means against |s_yy| and μ|s_yy|.

use super::windows::mean_tractions;
use serde::{Deserialize, Serialize};

/// Penalty factors f [-] of ε_n = ε_t = f · E per metre (paper Appendix D).
pub const EPS_FACTORS: [u32; 3] = [100, 200, 300];

/// Time of the interpenetration profile, t/T [-] (paper Figure D.15a).
pub const PROFILE_TIME_OVER_T: f64 = 0.6;

/// One upper-face node of the profile at t/T ≈ 0.6 (`penalty_faces.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FaceRow {
    /// Penalty factor f of ε_n = ε_t = f · E per metre [-].
    pub eps_factor: u32,
    /// Reference x of the node [m].
    pub x: f64,
    /// Penetration over the crack size, p/(2a) [-].
    pub penetration_over_2a: f64,
}

/// Mean contact tractions of one sample (`penalty_means.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeanRow {
    /// Penalty factor f [-].
    pub eps_factor: u32,
    /// Time [s].
    pub t: f64,
    /// t/T [-].
    #[serde(rename = "t_over_T")]
    pub t_over_t: f64,
    /// Area-weighted mean p_N over the contacting upper-face nodes [Pa].
    pub mean_normal_traction: f64,
    /// Area-weighted mean |T| over the contacting upper-face nodes [Pa].
    pub mean_tangential_traction: f64,
    /// Largest penetration on the upper face over the crack size [-].
    pub max_penetration_over_2a: f64,
}

/// One run's figures against the paper's expectations (`penalty_summary.csv`). Window means are
/// empty (`None`) when their window is empty; relative errors are signed: (measured − expected)/expected.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SummaryRow {
    /// Penalty factor f [-].
    pub eps_factor: u32,
    /// Largest upper-face penetration over 2a at the sample nearest t/T = 0.6 [-].
    #[serde(rename = "max_penetration_over_2a_at_0.6T")]
    pub max_penetration_over_2a_at_profile: f64,
    /// Mean normal traction from 0.2 T until the onset of insertion [Pa].
    pub mean_normal_before_onset: Option<f64>,
    /// (mean normal − |s_yy|)/|s_yy| [-].
    pub rel_error_normal: Option<f64>,
    /// Mean tangential traction from the stick → slip time + 0.05 T until onset [Pa].
    pub mean_tangential_while_slipping: Option<f64>,
    /// (mean tangential − μ|s_yy|)/(μ|s_yy|) [-].
    pub rel_error_tangential: Option<f64>,
}

/// The upper-face records of the sample nearest `t` [s] (empty when there are none).
pub fn profile_at(out: &fem::RunOutput, t: f64) -> Vec<fem::FaceRecord> {
    let nearest = out
        .faces
        .iter()
        .map(|f| f.t)
        .min_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs()));
    nearest.map_or_else(Vec::new, |tn| {
        out.faces.iter().filter(|f| f.t == tn).copied().collect()
    })
}

/// The D.15a profile rows of one run.
pub fn face_rows(factor: u32, scene: &fem::Scene, out: &fem::RunOutput) -> Vec<FaceRow> {
    let two_a = 2.0 * scene.half_length();
    profile_at(out, PROFILE_TIME_OVER_T * scene.duration())
        .iter()
        .map(|f| FaceRow {
            eps_factor: factor,
            x: f.x,
            penetration_over_2a: f.penetration / two_a,
        })
        .collect()
}

/// The D.15b–c rows of one run.
pub fn mean_rows(factor: u32, scene: &fem::Scene, out: &fem::RunOutput) -> Vec<MeanRow> {
    let (two_a, big_t) = (2.0 * scene.half_length(), scene.duration());
    out.contact
        .iter()
        .map(|c| MeanRow {
            eps_factor: factor,
            t: c.t,
            t_over_t: c.t / big_t,
            mean_normal_traction: c.mean_normal_traction,
            mean_tangential_traction: c.mean_tangential_traction,
            max_penetration_over_2a: c.max_penetration / two_a,
        })
        .collect()
}

/// The summary row of one run: profile maximum and claim-3.6 window means against the far field.
pub fn summary(factor: u32, scene: &fem::Scene, out: &fem::RunOutput) -> SummaryRow {
    let s_yy = scene.loading.normal.final_value.abs();
    let expect_t = scene.friction_coeff * s_yy;
    let m = mean_tractions(scene, out);
    let rel = |v: f64, e: f64| (e > 0.0).then(|| (v - e) / e);
    let max_pen = face_rows(factor, scene, out)
        .iter()
        .map(|r| r.penetration_over_2a)
        .fold(0.0, f64::max);
    SummaryRow {
        eps_factor: factor,
        max_penetration_over_2a_at_profile: max_pen,
        mean_normal_before_onset: m.normal,
        rel_error_normal: m.normal.and_then(|v| rel(v, s_yy)),
        mean_tangential_while_slipping: m.tangential,
        rel_error_tangential: m.tangential.and_then(|v| rel(v, expect_t)),
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use fem::{ArrivalRecord, ContactMeanRecord, FaceRecord, RunOutput};

    const MS: f64 = 1e-3;

    pub(crate) fn scene() -> fem::Scene {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/center-crack.toml");
        let s = fem::Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        s.with_penalties(300.0 * 70e6, 300.0 * 70e6).unwrap()
    }

    fn face(t: f64, x: f64, penetration: f64, normal: f64, tangential: f64) -> FaceRecord {
        FaceRecord {
            t,
            x,
            penetration,
            normal_traction: normal,
            tangential_traction: tangential,
            chain: None,
        }
    }

    /// Centre-crack scales (a = 0.125 m, T = 0.02 s, |s_yy| = 50 kPa, μ = 0.3). Samples at
    /// t = (k + ½) ms; insertion at 12 ms; the pre-crack nodes stick at 5.5 ms and slip at 6.2 ms.
    pub(crate) fn synthetic() -> RunOutput {
        let contact = (0..20)
            .map(|k| {
                let (n, tt) = match k {
                    0..=3 => (1e3, 0.0),
                    4..=6 => (4.8e4 + 100.0 * (k - 4) as f64, 1e3),
                    7..=11 => (4.8e4 + 100.0 * (k - 4) as f64, 1.44e4 + 60.0 * (k - 7) as f64),
                    _ => (0.0, 0.0),
                };
                ContactMeanRecord {
                    t: (k as f64 + 0.5) * MS,
                    mean_normal_traction: n,
                    mean_tangential_traction: tt,
                    max_penetration: 2.5e-6,
                    dropped_contacts_step: 0,
                    dropped_contacts_total: 0,
                }
            })
            .collect();
        let faces = vec![
            face(5.5 * MS, -0.05, 1e-6, 5e4, 1e4),
            face(5.5 * MS, 0.05, 1e-6, 5e4, 1e4),
            face(6.2 * MS, -0.05, 1e-6, 5e4, 1.5e4),
            face(6.2 * MS, 0.05, 1e-6, 5e4, 1.5e4),
            face(11.9 * MS, -0.1, 5e-6, 5e4, 1.5e4),
            face(11.9 * MS, 0.0, 1e-5, 5e4, 1.5e4),
            face(11.9 * MS, 0.2, 0.0, 0.0, 0.0),
            face(12.5 * MS, 0.0, 9e-5, 5e4, 1.5e4),
        ];
        let arrival = |t: f64| ArrivalRecord {
            x: 0.13,
            insertion_time: t,
            failure_time: f64::NAN,
            work_density: 0.0,
            chain: None,
        };
        RunOutput {
            faces,
            contact,
            arrivals: vec![arrival(f64::NAN), arrival(12.0 * MS), arrival(15.0 * MS)],
            ..RunOutput::default()
        }
    }

    #[test]
    fn penalties_are_factors_of_youngs_modulus() {
        let s = scene();
        assert_eq!(s.fem.eps_n, 300.0 * 70e6);
        assert_eq!(s.fem.eps_t, 300.0 * 70e6);
        assert_eq!(s.friction_coeff, 0.3);
    }

    #[test]
    fn profile_is_the_sample_nearest_0_6_t_normalised_by_2a() {
        let rows = face_rows(100, &scene(), &synthetic());
        let want = [(-0.1, 2e-5), (0.0, 4e-5), (0.2, 0.0)];
        assert_eq!(rows.len(), want.len());
        for (r, (x, p)) in rows.iter().zip(want) {
            assert_eq!((r.eps_factor, r.x), (100, x));
            assert!((r.penetration_over_2a - p).abs() < 1e-15, "{r:?}");
        }
        assert!(profile_at(&RunOutput::default(), 0.012).is_empty());
    }

    #[test]
    fn summary_uses_the_claim_3_6_windows() {
        let r = summary(200, &scene(), &synthetic());
        assert_eq!(r.eps_factor, 200);
        assert!((r.max_penetration_over_2a_at_profile - 4e-5).abs() < 1e-15);
        // normal: samples 4.5..11.5 ms (0.2 T = 4 ms to onset 12 ms) -> 48 350 Pa, −3.3 %
        assert!((r.mean_normal_before_onset.unwrap() - 48_350.0).abs() < 1e-9);
        assert!((r.rel_error_normal.unwrap() + 0.033).abs() < 1e-12);
        // tangential: from slip (6.2 ms) + 0.05 T = 7.2 ms to 12 ms -> 14 520 Pa, −3.2 %
        assert!((r.mean_tangential_while_slipping.unwrap() - 14_520.0).abs() < 1e-9);
        assert!((r.rel_error_tangential.unwrap() + 0.032).abs() < 1e-12);
        let m = &mean_rows(200, &scene(), &synthetic())[5];
        assert!((m.t_over_t - 0.275).abs() < 1e-12 && (m.max_penetration_over_2a - 1e-5).abs() < 1e-15);
    }

    #[test]
    fn no_slip_before_onset_leaves_the_tangential_window_empty() {
        let mut out = synthetic();
        out.faces.iter_mut().for_each(|f| f.tangential_traction = 0.0);
        let r = summary(100, &scene(), &out);
        assert_eq!(r.mean_tangential_while_slipping, None);
        assert_eq!(r.rel_error_tangential, None);
        assert!(r.mean_normal_before_onset.is_some());
    }
}
