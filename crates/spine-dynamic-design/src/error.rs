//! Why a dynamic design could not give a result.

use spine_dynamics::DynamicsError;

/// Why eq. (35) or eq. (37) could not give a result (a result that did not converge is not an
/// error: its status says so).
#[derive(Debug, thiserror::Error)]
pub enum DynamicDesignError {
    /// A static end of the start is not a stable equilibrium: nothing to move between.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    /// Ipopt refused the problem before its first iteration.
    #[error("eq. ({equation}): Ipopt could not start: {source}")]
    Ipopt {
        equation: &'static str,
        #[source]
        source: spine_ipopt::SetupError,
    },
    /// The settings of the search are out of range (the error names the field).
    #[error("search settings: {0}")]
    SearchSettings(#[from] spine_check::FieldError),
}

impl DynamicDesignError {
    /// The case asked for something impossible (exit code 2), as opposed to a solver that could
    /// not start (exit code 1).
    pub fn is_input(&self) -> bool {
        !matches!(self, Self::Ipopt { .. })
    }
}
