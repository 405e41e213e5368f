//! # spine-check: the one shape of a validation error
//!
//! Every options type of the workspace checks itself where it is defined (`validate`) and says
//! what is wrong as a [`FieldError`]: the field's path as a case file spells it and a message
//! saying what is allowed and what was given. A section checked by shared code is placed under its
//! section with [`FieldError::under`], so that the user reads the full path
//! (`simulation.integrator.rtol`), whatever crate found the fault.
//!
//! ```
//! use spine_check::{require, FieldError};
//!
//! fn check_rtol(rtol: f64) -> Result<(), FieldError> {
//!     require(rtol > 0.0 && rtol < 1.0, "rtol", || format!("must be in (0, 1), got {rtol}"))
//! }
//! let e = check_rtol(2.0).unwrap_err().under("simulation.integrator");
//! assert_eq!(e.to_string(), "simulation.integrator.rtol: must be in (0, 1), got 2");
//! ```
#![forbid(unsafe_code)]

/// A value outside what is allowed: the field's path (`chain.links`, `runs[1].case.delta_d`) and
/// what is allowed, with what was given.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct FieldError {
    /// The field's path as a case file spells it (empty: the whole object).
    pub field: String,
    pub message: String,
}

impl FieldError {
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self { field: field.into(), message: message.into() }
    }

    /// The same error inside the section `prefix`: `rtol` becomes `simulation.integrator.rtol`,
    /// `[2]` becomes `damping[2]`, an empty field becomes `prefix` itself.
    pub fn under(self, prefix: &str) -> Self {
        let field = if self.field.is_empty() {
            prefix.to_string()
        } else if prefix.is_empty() || self.field.starts_with('[') {
            format!("{prefix}{}", self.field)
        } else {
            format!("{prefix}.{}", self.field)
        };
        Self { field, ..self }
    }
}

/// `Ok` when `ok`, else the error of `field` with the message `message()` (built only then).
pub fn require(ok: bool, field: &str, message: impl FnOnce() -> String) -> Result<(), FieldError> {
    if ok {
        Ok(())
    } else {
        Err(FieldError::new(field, message()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn under_places_the_field_in_its_section() {
        let e = FieldError::new("rtol", "must be > 0");
        assert_eq!(e.clone().under("simulation.integrator").field, "simulation.integrator.rtol");
        assert_eq!(FieldError::new("[2]", "m").under("damping").field, "damping[2]");
        assert_eq!(FieldError::new("", "m").under("forcing").field, "forcing");
        assert_eq!(e.under("").field, "rtol");
        assert!(require(true, "x", || unreachable!()).is_ok());
    }
}
