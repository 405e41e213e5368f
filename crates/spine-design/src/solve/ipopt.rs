//! Stage 2 of a design run ([`crate::solve`]): Ipopt on one NLP of eq. (33), the linear solver it
//! names made ready first, and the full space's springs handed to Ipopt by their logarithm where
//! the settings ask for it.

use crate::full_space::FullSpaceNlp;
use crate::settings::LinearSolver;
use crate::variables::SpringVariables;
use spine_ipopt::{OptionValue, SetupError, Solution};

/// Why a design run could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// Ipopt rejected the problem or its options before iterating.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The workspace's linear solver could not be installed as Ipopt's Pardiso library.
    #[error("the linear solver could not be loaded: {0}")]
    LinearSolver(#[source] spine_kkt::KktError),
}

/// Ipopt on `nlp` with `options`, the linear solver they name made ready first: where they name
/// Pardiso, the workspace's own `LDLᵀ` is installed as Ipopt's Pardiso library
/// ([`LinearSolver::ready`]). Every eq. (33) solve goes through here.
pub fn ipopt_solve(
    nlp: &mut dyn spine_ipopt::Problem,
    options: &spine_ipopt::Options,
) -> Result<Solution, DesignError> {
    if options.get("linear_solver") == Some(&OptionValue::Str(spine_ipopt::LinearSolver::Pardiso.name().into())) {
        LinearSolver::Spine.ready().map_err(DesignError::LinearSolver)?;
    }
    Ok(spine_ipopt::solve(nlp, options)?)
}

/// [`ipopt_solve`] on the full space, the springs `k` handed to Ipopt by their logarithm
/// ([`crate::log_variables`]) when `springs` resolves to [`SpringVariables::Log`] for the NLP's
/// problem; the solution in `k` either way.
pub fn ipopt_solve_full(
    nlp: &mut FullSpaceNlp<'_>,
    options: &spine_ipopt::Options,
    springs: SpringVariables,
) -> Result<Solution, DesignError> {
    if springs.resolve(nlp.problem) != SpringVariables::Log {
        return ipopt_solve(nlp, options);
    }
    let logged: Vec<usize> = (0..=nlp.layout.n).map(|j| nlp.layout.stiffness(j)).collect();
    let mut wrapped = crate::log_variables::LogVariables::new(nlp, &logged);
    let options = crate::log_variables::relaxed_in_logs(&wrapped, options);
    let solution = ipopt_solve(&mut wrapped, &options)?;
    Ok(wrapped.solution_back(solution))
}
