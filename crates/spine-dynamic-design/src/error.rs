//! Why a dynamic design could not give a result.

use spine_dynamics::DynamicsError;

/// Why eq. (35) or eq. (37) could not give a result (a result that did not converge is not an
/// error: its status says so).
#[derive(Debug, thiserror::Error)]
pub enum DynamicDesignError {
    /// A static end of the start (the case's `design`) is not a stable equilibrium: nothing to
    /// move between.
    #[error("design: {0}")]
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
    /// The start design's periodic response does not move the end by more than the integrator
    /// resolves: the forcing is far faster than the chain can follow, and no search can read δ_d
    /// off such responses.
    #[error(
        "{field}: the start design's end swings {swing:.3e} m over a period, within what the integrator resolves ({resolution:.1e} m): a forcing of period {period} s is far faster than the chain can follow, so eq. (37) has nothing to design on; give a longer period"
    )]
    Unresolved { field: &'static str, period: f64, swing: f64, resolution: f64 },
    /// The search ended at springs whose static ends are not stable equilibria.
    #[error(
        "periodic_design.delta_d: eq. (37) ended at springs whose equilibria are not stable ({source}): δ_d = {delta_d} m asks more of the periodic motion than a stable design of this chain gives; give a smaller |δ_d|"
    )]
    FinalDesign {
        delta_d: f64,
        #[source]
        source: DynamicsError,
    },
}

impl DynamicDesignError {
    /// The case asked for something impossible (exit code 2), as opposed to a solver that could
    /// not start (exit code 1).
    pub fn is_input(&self) -> bool {
        !matches!(self, Self::Ipopt { .. })
    }
}
