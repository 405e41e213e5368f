//! Ipopt's return codes, one named variant each.

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
    /// The problem's intermediate callback asked Ipopt to stop.
    UserRequestedStop,
    /// Stopped through the user-stop hook because the run's wall-clock limit passed
    /// (`spine_stop::with_time_limit`); Ipopt's own code is `user_requested_stop`.
    TimeLimit,
    /// Stopped through the user-stop hook on a request from outside (Ctrl-C, SIGTERM,
    /// `spine_stop::request_interrupt`); Ipopt's own code is `user_requested_stop`.
    Interrupted,
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
    /// The status of an `ApplicationReturnStatus` code (the same codes in Ipopt 3.11 and 3.14).
    pub(crate) fn from_code(code: i32) -> Status {
        match code {
            0 => Status::SolveSucceeded,
            1 => Status::SolvedToAcceptableLevel,
            2 => Status::InfeasibleProblemDetected,
            3 => Status::SearchDirectionBecomesTooSmall,
            4 => Status::DivergingIterates,
            5 => Status::UserRequestedStop,
            6 => Status::FeasiblePointFound,
            -1 => Status::MaximumIterationsExceeded,
            -2 => Status::RestorationFailed,
            -3 => Status::ErrorInStepComputation,
            -4 => Status::MaximumCpuTimeExceeded,
            -10 => Status::NotEnoughDegreesOfFreedom,
            -11 => Status::InvalidProblemDefinition,
            -12 => Status::InvalidOption,
            -13 => Status::InvalidNumberDetected,
            -100 => Status::UnrecoverableException,
            -101 => Status::NonIpoptExceptionThrown,
            -102 => Status::InsufficientMemory,
            -199 => Status::InternalError,
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
            Status::TimeLimit => "time_limit".into(),
            Status::Interrupted => "interrupted".into(),
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
    /// The snake_case name, padded as a string would be (`{:<20}` in tables).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(&self.name())
    }
}

impl Status {
    /// Every named status (all but [`Status::Unknown`]): those of Ipopt's return codes
    /// (`Status::from_code`, the one table of codes) and the two stops of this wrapper.
    pub fn named() -> impl Iterator<Item = Status> {
        (-199..=6)
            .map(Status::from_code)
            .filter(|s| !matches!(s, Status::Unknown(_)))
            .chain([Status::TimeLimit, Status::Interrupted])
    }

    /// The status of a [`Status::name`] (`None` for a name no status has).
    pub fn from_name(name: &str) -> Option<Status> {
        if let Some(code) = name.strip_prefix("unknown_status_") {
            return code.parse().ok().map(Status::Unknown);
        }
        Status::named().find(|s| s.name() == name)
    }
}

/// Serialised as its [`Status::name`] (`"solve_succeeded"`), as result files have always held it.
impl serde::Serialize for Status {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Status {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let name = String::deserialize(deserializer)?;
        Status::from_name(&name).ok_or_else(|| serde::de::Error::custom(format!("unknown Ipopt status {name:?}")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_status_round_trips_through_its_name_and_codes_through_from_code() {
        assert_eq!(Status::named().count(), 21);
        for s in Status::named().chain([Status::Unknown(-7)]) {
            assert_eq!(Status::from_name(&s.name()), Some(s));
            let json = serde_json::to_string(&s).unwrap();
            assert_eq!(json, format!("\"{}\"", s.name()));
            assert_eq!(serde_json::from_str::<Status>(&json).unwrap(), s);
        }
        assert_eq!(Status::from_name("solve_suceeded"), None);
        assert_eq!(format!("{:>17}|", Status::SolveSucceeded), "  solve_succeeded|");
    }
}
