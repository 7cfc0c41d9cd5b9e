//! The two checks every scene key goes through: a number in its allowed range, a string among
//! its allowed options. Errors name the dotted key, the value and what is allowed.

use crate::error::SceneError;

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
