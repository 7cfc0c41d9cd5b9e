//! The two checks every scene key goes through: a number in its allowed range, a string among
//! its allowed options. Errors name the dotted key, the value and what is allowed. And the checks
//! of the two tables a scene gives in several places: a plane-strain material (`[material]`,
//! `[fem.mesh.materials.NAME]`) and a linear cohesive law (`[interface]`,
//! `[[fem.interface_zones]]`, `[fem.mesh.laws.NAME]`).

use super::raw::RawMaterial;
use crate::error::SceneError;
use crate::law::cohesive::LinearCohesive;
use crate::law::elastic::PlaneStrain;

/// The material of the table at `prefix` (`material`, `fem.mesh.materials.NAME`), each value in
/// its range.
pub(crate) fn material(prefix: &str, m: &RawMaterial) -> Result<PlaneStrain, SceneError> {
    let key = |field: &str| format!("{prefix}.{field}");
    let (e, nu, rho) = (m.youngs_modulus, m.poisson_ratio, m.density);
    check(key("youngs_modulus"), e, e > 0.0, "> 0 Pa")?;
    check(key("poisson_ratio"), nu, (0.0..0.5).contains(&nu), "[0, 0.5)")?;
    check(key("density"), rho, rho > 0.0, "> 0 kg/m^3")?;
    Ok(PlaneStrain::new(e, nu, rho))
}

/// The cohesive law σ_c [Pa], δ_c [m], β, κ [-] of the table at `prefix` (`interface`,
/// `fem.interface_zones[k]`, `fem.mesh.laws.NAME`), each value > 0.
pub(crate) fn cohesive_law(
    prefix: &str,
    [sigma_c, delta_c, beta, kappa]: [f64; 4],
) -> Result<LinearCohesive, SceneError> {
    let key = |field: &str| format!("{prefix}.{field}");
    check(key("sigma_c"), sigma_c, sigma_c > 0.0, "> 0 Pa")?;
    check(key("delta_c"), delta_c, delta_c > 0.0, "> 0 m")?;
    check(key("beta"), beta, beta > 0.0, "> 0")?;
    check(key("kappa"), kappa, kappa > 0.0, "> 0")?;
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
