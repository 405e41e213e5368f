//! Ipopt's return codes, one named variant each.

use ipopt_sys as sys;

/// How an Ipopt run ended (`ApplicationReturnStatus`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// Converged to the requested tolerances.
    SolveSucceeded,
    /// Converged only to the "acceptable" tolerances.
    SolvedToAcceptableLevel,
    /// The restoration phase converged to a point of minimal infeasibility that is not feasible.
    InfeasibleProblemDetected,
    SearchDirectionBecomesTooSmall,
    DivergingIterates,
    UserRequestedStop,
    FeasiblePointFound,
    MaximumIterationsExceeded,
    RestorationFailed,
    ErrorInStepComputation,
    MaximumCpuTimeExceeded,
    NotEnoughDegreesOfFreedom,
    InvalidProblemDefinition,
    InvalidOption,
    InvalidNumberDetected,
    UnrecoverableException,
    NonIpoptExceptionThrown,
    InsufficientMemory,
    InternalError,
    /// A code this wrapper does not know.
    Unknown(i32),
}

impl Status {
    pub(crate) fn from_code(code: sys::CNLP_ApplicationReturnStatus) -> Status {
        match code {
            sys::CNLP_ApplicationReturnStatus_CNLP_SOLVE_SUCCEEDED => Status::SolveSucceeded,
            sys::CNLP_ApplicationReturnStatus_CNLP_SOLVED_TO_ACCEPTABLE_LEVEL => Status::SolvedToAcceptableLevel,
            sys::CNLP_ApplicationReturnStatus_CNLP_INFEASIBLE_PROBLEM_DETECTED => Status::InfeasibleProblemDetected,
            sys::CNLP_ApplicationReturnStatus_CNLP_SEARCH_DIRECTION_BECOMES_TOO_SMALL => {
                Status::SearchDirectionBecomesTooSmall
            }
            sys::CNLP_ApplicationReturnStatus_CNLP_DIVERGING_ITERATES => Status::DivergingIterates,
            sys::CNLP_ApplicationReturnStatus_CNLP_USER_REQUESTED_STOP => Status::UserRequestedStop,
            sys::CNLP_ApplicationReturnStatus_CNLP_FEASIBLE_POINT_FOUND => Status::FeasiblePointFound,
            sys::CNLP_ApplicationReturnStatus_CNLP_MAXIMUM_ITERATIONS_EXCEEDED => Status::MaximumIterationsExceeded,
            sys::CNLP_ApplicationReturnStatus_CNLP_RESTORATION_FAILED => Status::RestorationFailed,
            sys::CNLP_ApplicationReturnStatus_CNLP_ERROR_IN_STEP_COMPUTATION => Status::ErrorInStepComputation,
            sys::CNLP_ApplicationReturnStatus_CNLP_MAXIMUM_CPUTIME_EXCEEDED => Status::MaximumCpuTimeExceeded,
            sys::CNLP_ApplicationReturnStatus_CNLP_NOT_ENOUGH_DEGREES_OF_FREEDOM => Status::NotEnoughDegreesOfFreedom,
            sys::CNLP_ApplicationReturnStatus_CNLP_INVALID_PROBLEM_DEFINITION => Status::InvalidProblemDefinition,
            sys::CNLP_ApplicationReturnStatus_CNLP_INVALID_OPTION => Status::InvalidOption,
            sys::CNLP_ApplicationReturnStatus_CNLP_INVALID_NUMBER_DETECTED => Status::InvalidNumberDetected,
            sys::CNLP_ApplicationReturnStatus_CNLP_UNRECOVERABLE_EXCEPTION => Status::UnrecoverableException,
            sys::CNLP_ApplicationReturnStatus_CNLP_NONIPOPT_EXCEPTION_THROWN => Status::NonIpoptExceptionThrown,
            sys::CNLP_ApplicationReturnStatus_CNLP_INSUFFICIENT_MEMORY => Status::InsufficientMemory,
            sys::CNLP_ApplicationReturnStatus_CNLP_INTERNAL_ERROR => Status::InternalError,
            other => Status::Unknown(other),
        }
    }

    /// Converged to the requested tolerances.
    pub fn is_optimal(self) -> bool {
        self == Status::SolveSucceeded
    }

    /// Converged to the requested or the acceptable tolerances.
    pub fn is_converged(self) -> bool {
        matches!(self, Status::SolveSucceeded | Status::SolvedToAcceptableLevel)
    }

    /// Ipopt concluded that the constraints cannot be satisfied.
    pub fn is_infeasible(self) -> bool {
        self == Status::InfeasibleProblemDetected
    }

    /// A short snake_case name, stable for result files.
    pub fn name(self) -> String {
        match self {
            Status::SolveSucceeded => "solve_succeeded".into(),
            Status::SolvedToAcceptableLevel => "solved_to_acceptable_level".into(),
            Status::InfeasibleProblemDetected => "infeasible_problem_detected".into(),
            Status::SearchDirectionBecomesTooSmall => "search_direction_becomes_too_small".into(),
            Status::DivergingIterates => "diverging_iterates".into(),
            Status::UserRequestedStop => "user_requested_stop".into(),
            Status::FeasiblePointFound => "feasible_point_found".into(),
            Status::MaximumIterationsExceeded => "maximum_iterations_exceeded".into(),
            Status::RestorationFailed => "restoration_failed".into(),
            Status::ErrorInStepComputation => "error_in_step_computation".into(),
            Status::MaximumCpuTimeExceeded => "maximum_cpu_time_exceeded".into(),
            Status::NotEnoughDegreesOfFreedom => "not_enough_degrees_of_freedom".into(),
            Status::InvalidProblemDefinition => "invalid_problem_definition".into(),
            Status::InvalidOption => "invalid_option".into(),
            Status::InvalidNumberDetected => "invalid_number_detected".into(),
            Status::UnrecoverableException => "unrecoverable_exception".into(),
            Status::NonIpoptExceptionThrown => "non_ipopt_exception_thrown".into(),
            Status::InsufficientMemory => "insufficient_memory".into(),
            Status::InternalError => "internal_error".into(),
            Status::Unknown(code) => format!("unknown_status_{code}"),
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name())
    }
}
