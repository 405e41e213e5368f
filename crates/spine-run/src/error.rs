//! Why a run could not give a result, with its cause.

use spine_case::CaseError;
use spine_check::FieldError;
use spine_design::DesignError;
use spine_dynamic_design::DynamicDesignError;
use spine_dynamics::DynamicsError;

/// Why a run could not give a result. [`RunError::is_input`] says whether the case asked for
/// something impossible (exit code 2) or a step it depends on failed (exit code 1).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The case file breaks a rule (the error names the field).
    #[error(transparent)]
    Case(#[from] CaseError),
    /// A command (or a figure's run) given a case of a kind it does not take.
    #[error("kind: {command} needs {needs} case, the file is \"{kind}\"")]
    WrongKind { command: &'static str, needs: &'static str, kind: &'static str },
    /// Eq. (33) could not start (its setup rejected the case).
    #[error("solver: {0}")]
    Design(#[source] DesignError),
    /// A dynamic task could not start (an unstable static end).
    #[error("design: {0}")]
    Dynamics(#[source] DynamicsError),
    /// A dynamic design (eq. (35), eq. (37)) could not start.
    #[error("design: {0}")]
    DynamicDesign(#[source] DynamicDesignError),
    /// The eq. (33) design a dynamic case depends on did not end clean.
    #[error(
        "the static design of eq. (33) did not end clean ({status}; warnings: {}); no dynamics run on it",
        .warnings.join("; ")
    )]
    StaticDesignNotClean { status: spine_ipopt::Status, warnings: Vec<String> },
    /// The figure's recipe (named by `figure`) rejected its runs; the error names the run.
    #[error("{figure}: {error}")]
    Recipe { figure: String, error: FieldError },
    /// A stop was requested from outside (Ctrl-C, SIGTERM); nothing is reported.
    #[error("interrupted: the run was stopped before it finished; nothing written")]
    Interrupted,
    /// The run's time limit passed and left nothing to report (`cause`: how the run failed once
    /// its solvers stopped, e.g. a figure whose recipe needs every run). Exit code 3.
    #[error("time limit: {seconds} s passed before the run could give a result ({cause}); nothing written")]
    TimeLimit {
        seconds: f64,
        #[source]
        cause: Box<RunError>,
    },
    /// A command-line option out of its range, or one that does not fit the case.
    #[error(transparent)]
    Option(FieldError),
    /// A worker process of a multi-start failed (it could not start, or ended without an answer).
    #[error("{0}")]
    Worker(String),
    /// Shards that cannot be merged (mismatched, missing, incomplete).
    #[error(transparent)]
    Merge(#[from] MergeError),
    /// A run of a figure failed.
    #[error("runs[{index}] ({name}): {source}")]
    InRun {
        index: usize,
        name: String,
        #[source]
        source: Box<RunError>,
    },
}

impl RunError {
    /// The run's time limit stopped it before it had a result (exit code 3).
    pub fn is_time_limit(&self) -> bool {
        matches!(self, Self::TimeLimit { .. })
    }

    /// The run was stopped from outside (exit code 130).
    pub fn is_interrupted(&self) -> bool {
        match self {
            Self::Interrupted => true,
            Self::InRun { source, .. } => source.is_interrupted(),
            _ => false,
        }
    }

    /// The case asks for something impossible (bad input, exit code 2), as opposed to a step that
    /// did not succeed (exit code 1).
    pub fn is_input(&self) -> bool {
        match self {
            Self::Case(_)
            | Self::WrongKind { .. }
            | Self::Design(_)
            | Self::Dynamics(_)
            | Self::Recipe { .. }
            | Self::Option(_)
            | Self::Merge(_) => true,
            Self::DynamicDesign(e) => e.is_input(),
            Self::StaticDesignNotClean { .. } | Self::Interrupted | Self::TimeLimit { .. } | Self::Worker(_) => false,
            Self::InRun { source, .. } => source.is_input(),
        }
    }
}

/// Why shards cannot be merged (bad input: exit code 2).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MergeError {
    #[error("no shards given")]
    Empty,
    #[error("{0}")]
    Mismatch(String),
    #[error("{0}")]
    Incomplete(String),
    #[error("the shards' case: {0}")]
    Case(String),
}
