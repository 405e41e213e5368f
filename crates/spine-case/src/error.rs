//! Errors in case files. Each is a [`FieldError`]: the field (a JSON path such as
//! `design.theta0[3]`) and what is allowed.

pub use spine_check::FieldError;

/// Why a case file was refused: the one field error of the workspace, marked by whether the file
/// could not be read as a case (parse) or holds a value that is not allowed (invalid).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CaseError {
    /// Not JSON, or JSON of the wrong shape (unknown field, wrong type, missing field).
    #[error(transparent)]
    Parse(FieldError),
    /// Well-formed but not allowed (wrong length, out of range, inconsistent).
    #[error(transparent)]
    Invalid(FieldError),
}

/// A case error as the field error it carries (for callers below spine-case, which take a
/// [`FieldError`]).
impl From<CaseError> for FieldError {
    fn from(e: CaseError) -> Self {
        match e {
            CaseError::Parse(e) | CaseError::Invalid(e) => e,
        }
    }
}

/// An options type's own check (`SolverSettings::validate`, `Forcing::validate`, …) as a case error.
impl From<FieldError> for CaseError {
    fn from(e: FieldError) -> Self {
        Self::Invalid(e)
    }
}

impl CaseError {
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Invalid(FieldError::new(field, message))
    }

    pub fn parse(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Parse(FieldError::new(field, message))
    }

    fn map(self, f: impl FnOnce(FieldError) -> FieldError) -> Self {
        match self {
            Self::Parse(e) => Self::Parse(f(e)),
            Self::Invalid(e) => Self::Invalid(f(e)),
        }
    }

    /// The same error inside `prefix`: `chain.links` becomes `runs[1].case.chain.links` (the
    /// whole file, `case file`, becomes `prefix` itself).
    pub fn under(self, prefix: &str) -> Self {
        self.map(
            |e| {
                if e.field == "case file" {
                    FieldError { field: prefix.to_string(), ..e }
                } else {
                    e.under(prefix)
                }
            },
        )
    }

    /// The field the error is about.
    pub fn field(&self) -> &str {
        match self {
            Self::Parse(e) | Self::Invalid(e) => &e.field,
        }
    }
}
