//! The one check a scene's physical quantities share (resolved, the drive and the slider's
//! shape): a value must be finite, > 0 and normal, or it is refused naming its scene key. Its
//! own module so that the files that resolve a scene use it without importing each other.

use super::SceneError;

/// A value that must be finite, > 0 and normal (a subnormal value loses precision and turns
/// its reciprocals, like the wave period, into infinity); refused naming `field`.
pub(super) fn positive(field: &str, value: f64) -> Result<f64, SceneError> {
    if value.is_finite() && value > 0.0 && value.is_normal() {
        Ok(value)
    } else {
        Err(SceneError::Invalid {
            field: field.to_owned(),
            message: format!("must be finite and > 0, got {value:e}"),
        })
    }
}
