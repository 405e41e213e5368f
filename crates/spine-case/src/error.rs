//! Errors in case files. Each names the field (a JSON path such as `design.theta0[3]`).

/// Why a case file was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CaseError {
    /// Not JSON, or JSON of the wrong shape (unknown field, wrong type, missing field).
    #[error("{field}: {message}")]
    Parse { field: String, message: String },
    /// Well-formed but not allowed (wrong length, out of range, inconsistent).
    #[error("{field}: {message}")]
    Invalid { field: String, message: String },
}

impl CaseError {
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::Invalid { field: field.into(), message: message.into() }
    }

    /// The field the error is about.
    pub fn field(&self) -> &str {
        match self {
            Self::Parse { field, .. } | Self::Invalid { field, .. } => field,
        }
    }
}
