//! The two checks every scene key goes through: a number in its allowed range, a string among
//! its allowed options. Errors name the dotted key, the value and what is allowed. And the checks
//! of the two tables a scene gives in several places: a plane-strain material (`[material]`,
//! `[fem.mesh.materials.NAME]`) and a linear cohesive law (`[interface]`,
//! `[[fem.interface_zones]]`, `[fem.mesh.laws.NAME]`).

use super::problem::Ramp;
use super::raw::{RawMaterial, RawRamp};
use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;
use crate::law::elastic::PlaneStrain;

/// The material of the table at `prefix` (`material`, `fem.mesh.materials.NAME`), each value in
/// its range.
pub(crate) fn material(prefix: &str, m: &RawMaterial) -> Result<PlaneStrain, SceneError> {
    let key = |field: &str| format!("{prefix}.{field}");
    let (e, nu, rho) = (m.youngs_modulus, m.poisson_ratio, m.density);
    let mut p = Problems::default();
    p.check(key("youngs_modulus"), e, e > 0.0, "> 0 Pa");
    p.check(key("poisson_ratio"), nu, (0.0..0.5).contains(&nu), "[0, 0.5)");
    p.check(key("density"), rho, rho > 0.0, "> 0 kg/m^3");
    p.done()?;
    Ok(PlaneStrain::new(e, nu, rho))
}

/// A ramp of eq. (B.1) under `field` (`loading.normal`, `fem.boundary.top.y`): finite values, a
/// start in [0, T) where T = `duration` [s], an end after the start. A ramp from `initial` to a
/// different `final` that starts at or after T is refused (its `final` would never be reached);
/// one whose two values are equal is a constant and may start anywhere.
pub(crate) fn ramp(field: &str, r: &RawRamp, duration: f64) -> Result<Ramp, SceneError> {
    let mut p = Problems::default();
    p.check(format!("{field}.initial"), r.initial, true, "a finite number");
    p.check(format!("{field}.final"), r.final_, true, "a finite number");
    p.check(
        format!("{field}.ramp_start"),
        r.ramp_start,
        r.ramp_start >= 0.0 && (r.ramp_start < duration || r.final_ == r.initial),
        "[0, loading.duration) s: a ramp starting at or after T never reaches its final value",
    );
    p.check(
        format!("{field}.ramp_end"),
        r.ramp_end,
        r.ramp_end >= r.ramp_start,
        ">= ramp_start",
    );
    p.done()?;
    Ok(Ramp {
        initial: r.initial,
        final_value: r.final_,
        ramp_start: r.ramp_start,
        ramp_end: r.ramp_end,
    })
}

/// The cohesive law σ_c [Pa], δ_c [m], β, κ [-] of the table at `prefix` (`interface`,
/// `fem.interface_zones[k]`, `fem.mesh.laws.NAME`), each value > 0.
pub(crate) fn cohesive_law(
    prefix: &str,
    [sigma_c, delta_c, beta, kappa]: [f64; 4],
) -> Result<LinearCohesive, SceneError> {
    let key = |field: &str| format!("{prefix}.{field}");
    let mut p = Problems::default();
    p.check(key("sigma_c"), sigma_c, sigma_c > 0.0, "> 0 Pa");
    p.check(key("delta_c"), delta_c, delta_c > 0.0, "> 0 m");
    p.check(key("beta"), beta, beta > 0.0, "> 0");
    p.check(key("kappa"), kappa, kappa > 0.0, "> 0");
    p.done()?;
    Ok(LinearCohesive {
        sigma_c,
        delta_c,
        beta,
        kappa,
    })
}

/// `value` if it is finite and `ok`; otherwise an out-of-range error naming `field`.
pub(crate) fn check(
    field: impl Into<String>,
    value: f64,
    ok: bool,
    allowed: &str,
) -> Result<f64, SceneError> {
    if ok && value.is_finite() {
        Ok(value)
    } else {
        Err(SceneError::OutOfRange {
            field: field.into(),
            value,
            allowed: allowed.to_string(),
        })
    }
}

/// The option of `table` named by `value` (`default` when the key is absent); an unknown name is
/// refused with the allowed ones.
pub(crate) fn option<T: Copy>(
    field: impl Into<String>,
    value: Option<&String>,
    default: T,
    table: &[(&str, T)],
    allowed: &'static str,
) -> Result<T, SceneError> {
    let Some(v) = value else { return Ok(default) };
    table
        .iter()
        .find(|(k, _)| *k == v.as_str())
        .map(|(_, t)| *t)
        .ok_or_else(|| SceneError::BadOption {
            field: field.into(),
            value: v.clone(),
            allowed,
        })
}

/// Keys that do not fit together: `key` is the one to change.
pub(crate) fn inconsistent(key: impl Into<String>, message: impl Into<String>) -> SceneError {
    SceneError::Inconsistent {
        key: key.into(),
        message: message.into(),
    }
}

/// Every problem of one table, not only the first: each check records its problem and the
/// validation goes on to the next key, so one run of a scene reports every bad value at once.
#[derive(Debug, Default)]
pub(crate) struct Problems(Vec<SceneError>);

impl Problems {
    /// `value`, checked as [`check`] checks it: a problem is recorded, and the value is returned
    /// either way (a table with a problem is refused as a whole by [`Problems::done`]).
    pub(crate) fn check(&mut self, field: impl Into<String>, value: f64, ok: bool, allowed: &str) -> f64 {
        if let Err(e) = check(field, value, ok, allowed) {
            self.0.push(e);
        }
        value
    }

    /// The value of `r`, or `None` with its problem recorded.
    pub(crate) fn keep<T>(&mut self, r: Result<T, SceneError>) -> Option<T> {
        keep(&mut self.0, r)
    }

    /// Records a problem.
    pub(crate) fn push(&mut self, e: SceneError) {
        self.0.push(e);
    }

    /// `Ok` when no problem was recorded; otherwise all of them in one error.
    pub(crate) fn done(self) -> Result<(), SceneError> {
        if self.0.is_empty() {
            Ok(())
        } else {
            Err(collected(self.0))
        }
    }
}

/// Several problems as one error (one problem stays itself).
pub(crate) fn collected(mut errors: Vec<SceneError>) -> SceneError {
    if errors.len() == 1 {
        return errors.pop().expect("invariant: one error");
    }
    SceneError::Invalid {
        problems: errors.iter().flat_map(SceneError::problems).collect(),
    }
}

/// The value of `r`, or `None` with its error added to `errors`: validation goes on past a bad
/// key, so one run of a scene reports all its problems.
pub(crate) fn keep<T>(errors: &mut Vec<SceneError>, r: Result<T, SceneError>) -> Option<T> {
    match r {
        Ok(v) => Some(v),
        Err(e) => {
            errors.push(e);
            None
        }
    }
}
