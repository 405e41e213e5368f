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

    /// The same error with its field placed under `prefix` (for a section checked by shared code:
    /// `solver.residual_tolerance` becomes `solver.continuation.residual_tolerance`).
    pub fn with_prefix(self, prefix: &str) -> Self {
        let rename = |field: String| match field.split_once('.') {
            Some((_, rest)) => format!("{prefix}.{rest}"),
            None => format!("{prefix}.{field}"),
        };
        match self {
            Self::Parse { field, message } => Self::Parse { field: rename(field), message },
            Self::Invalid { field, message } => Self::Invalid { field: rename(field), message },
        }
    }

    /// The field the error is about.
    /// The same error inside `prefix`: `chain.links` becomes `runs[1].case.chain.links`.
    pub fn under(self, prefix: &str) -> Self {
        let put = |field: String| if field == "case file" { prefix.to_string() } else { format!("{prefix}.{field}") };
        match self {
            Self::Parse { field, message } => Self::Parse { field: put(field), message },
            Self::Invalid { field, message } => Self::Invalid { field: put(field), message },
        }
    }

    pub fn field(&self) -> &str {
        match self {
            Self::Parse { field, .. } | Self::Invalid { field, .. } => field,
        }
    }
}
