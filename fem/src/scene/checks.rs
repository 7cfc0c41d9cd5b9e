//! The two checks every scene key goes through: a number in its allowed range, a string among
//! its allowed options. Errors name the dotted key, the value and what is allowed.

use crate::error::SceneError;

/// `value` if it is finite and `ok`; otherwise an out-of-range error naming `field`.
pub(crate) fn check(field: &'static str, value: f64, ok: bool, allowed: &str) -> Result<f64, SceneError> {
    if ok && value.is_finite() {
        Ok(value)
    } else {
        Err(SceneError::OutOfRange {
            field,
            value,
            allowed: allowed.to_string(),
        })
    }
}

/// The option of `table` named by `value` (`default` when the key is absent); an unknown name is
/// refused with the allowed ones.
pub(crate) fn option<T: Copy>(
    field: &'static str,
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
            field,
            value: v.clone(),
            allowed,
        })
}
