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
    #[error("kind: {command} needs {needs}, the file is \"{kind}\"")]
    WrongKind { command: &'static str, needs: std::borrow::Cow<'static, str>, kind: &'static str },
    /// Eq. (33) could not start (its setup rejected the case).
    #[error("solver: {0}")]
    Design(#[source] DesignError),
    /// A dynamic task could not start (an unstable static end).
    #[error("design: {0}")]
    Dynamics(#[source] DynamicsError),
    /// A dynamic design (eq. (35), eq. (37)) could not start, or gave nothing to report; the
    /// message names the field to blame (`design` for the start's equilibria).
    #[error(transparent)]
    DynamicDesign(DynamicDesignError),
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
    #[error(transparent)]
    Worker(#[from] WorkerError),
    /// Shards that cannot be merged (mismatched, missing, incomplete).
    #[error(transparent)]
    Merge(Box<MergeError>),
    /// A run of a figure failed.
    #[error("runs[{index}] ({name}): {source}")]
    InRun {
        index: usize,
        name: String,
        #[source]
        source: Box<RunError>,
    },
}

impl From<MergeError> for RunError {
    fn from(e: MergeError) -> Self {
        Self::Merge(Box::new(e))
    }
}

impl RunError {
    /// The run's time limit stopped it before it had a result (exit code 3).
    pub fn is_time_limit(&self) -> bool {
        matches!(self, Self::TimeLimit { .. })
    }

    /// An embedded eq. (33) design (of a dynamic case, or of a figure's dynamic run) did not end
    /// clean, so nothing ran on it: the run ended but not clean (exit code 3, nothing written).
    pub fn is_not_clean(&self) -> bool {
        match self {
            Self::StaticDesignNotClean { .. } => true,
            Self::InRun { source, .. } => source.is_not_clean(),
            _ => false,
        }
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
    /// A shard file of another format.
    #[error("shard format \"{}\", expected \"{expected}\"", spine_check::shown(.found))]
    Format { found: String, expected: &'static str },
    #[error("shard.index {index} of shard.count {count}: 1 ≤ index ≤ count ≤ {max} expected")]
    ShardNumber { index: usize, count: usize, max: usize },
    #[error("overrides.starts {starts}: at most {max} expected")]
    TooManyStarts { starts: usize, max: usize },
    #[error("shard {shard} ran another case file than shard {first}")]
    OtherCase { shard: String, first: String },
    /// Shards run with other overrides (or one of a census, the other not).
    #[error(
        "shard {shard} ran with other settings ({}) than shard {first} ({})",
        settings_text(.settings, *.batch),
        settings_text(.first_settings, *.first_batch)
    )]
    OtherSettings {
        shard: String,
        settings: crate::DesignOverrides,
        batch: Option<usize>,
        first: String,
        first_settings: crate::DesignOverrides,
        first_batch: Option<usize>,
    },
    /// The case the shards carry is not a valid design case.
    #[error("the shards' case: {0}")]
    Case(#[source] CaseError),
    #[error(
        "shard {shard} holds a batch of a census to a stated confidence, but its case and overrides set no confidence"
    )]
    NotACensus { shard: String },
    #[error("shard {shard}: batch {batch}, expected 1 ≤ batch ≤ {count} (the cap allows {count})")]
    BatchNumber { shard: String, batch: usize, count: usize },
    /// Batches of a census missing below the last one given (the first ten).
    #[error("a census's batches 1..={last} expected; missing batch {}", crate::text::joined(.missing))]
    MissingBatches { last: usize, missing: Vec<usize> },
    #[error("batch 1 holds no start 0")]
    NoStartZero,
    #[error("shard {shard} and shard {other}: one batch is split into one number of shards")]
    ShardCounts { shard: String, other: String },
    /// Shards of one multi-start (or batch) missing (the first ten of `missing_count`) or given
    /// more than once.
    #[error("{count} shards{} expected; {}", batch.map(|b| format!(" of batch {b}")).unwrap_or_default(), missing_text(*.missing_count, .missing, .twice))]
    MissingShards { count: usize, batch: Option<usize>, missing: Vec<usize>, missing_count: usize, twice: Vec<usize> },
    #[error("{0}")]
    IncompleteShard(ShardContents),
    /// A shard's run does not fit the case's problem (edited or from another case).
    #[error("shard {shard}, start {start}: {reason}")]
    OtherProblem {
        shard: String,
        start: usize,
        #[source]
        reason: FieldError,
    },
}

/// What a shard holds against the starts of its share, counted from the same lists the merge
/// compares: the starts it lacks and those it holds that are not its share's (the first ten of
/// each), and whether it says it finished.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShardContents {
    pub shard: String,
    /// The shard's own `complete` flag.
    pub complete: bool,
    /// Runs the shard holds.
    pub held: usize,
    /// Starts its share has.
    pub expected: usize,
    /// Starts of the share it lacks: how many, and the first ten.
    pub missing: (usize, Vec<usize>),
    /// Runs it holds of starts that are not its share's (or held twice): how many, the first ten.
    pub foreign: (usize, Vec<usize>),
}

impl ShardContents {
    /// `got` (the shard's start numbers, in its order) against `expected` (its share, ascending).
    pub fn compare(shard: String, complete: bool, got: &[usize], expected: &[usize]) -> Self {
        let mut sorted = got.to_vec();
        sorted.sort_unstable();
        let missing: Vec<usize> = expected.iter().copied().filter(|i| sorted.binary_search(i).is_err()).collect();
        let mut seen = std::collections::BTreeSet::new();
        let foreign: Vec<usize> =
            got.iter().copied().filter(|i| expected.binary_search(i).is_err() || !seen.insert(*i)).collect();
        let first = |v: Vec<usize>| (v.len(), v.into_iter().take(10).collect());
        Self {
            shard,
            complete,
            held: got.len(),
            expected: expected.len(),
            missing: first(missing),
            foreign: first(foreign),
        }
    }
}

impl std::fmt::Display for ShardContents {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let list = |(n, first): &(usize, Vec<usize>)| {
            let more = if *n > first.len() { format!(", … ({n} in all)") } else { String::new() };
            format!("{}{more}", crate::text::joined(first))
        };
        write!(f, "shard {}: ", self.shard)?;
        let mut parts = Vec::new();
        if self.missing.0 > 0 {
            parts.push(format!(
                "{} of its share's {} starts are missing (start {})",
                self.missing.0,
                self.expected,
                list(&self.missing)
            ));
        }
        if self.foreign.0 > 0 {
            parts.push(format!(
                "it holds {} run(s) of starts not in its share or held twice (start {})",
                self.foreign.0,
                list(&self.foreign)
            ));
        }
        if parts.is_empty() && !self.complete {
            parts.push(format!(
                "it holds all {} starts of its share but says it did not finish (\"complete\": false): it was stopped or edited",
                self.expected
            ));
        } else if !self.complete {
            parts.push("it says it did not finish (stopped early?)".into());
        }
        write!(f, "{}; it cannot be merged (run the shard again)", parts.join("; "))
    }
}

/// A shard's settings as a person reads them: its overrides, and its batch.
fn settings_text(overrides: &crate::DesignOverrides, batch: Option<usize>) -> String {
    let mut text = serde_json::to_string(overrides).unwrap_or_default();
    if let Some(b) = batch {
        text += &format!(", batch {b}");
    }
    text
}

/// The missing and doubled shards of [`MergeError::MissingShards`].
fn missing_text(missing_count: usize, missing: &[usize], twice: &[usize]) -> String {
    let mut parts = Vec::new();
    if missing_count > 0 {
        parts.push(format!("missing {} ({missing_count} of them)", crate::text::joined(missing)));
    }
    if !twice.is_empty() {
        parts.push(format!("given more than once {}", crate::text::joined(twice)));
    }
    parts.join("; ")
}

/// Why a worker process of a multi-start failed.
#[derive(Debug, thiserror::Error)]
pub enum WorkerError {
    #[error("{}: cannot start a worker: {source}", .program.display())]
    Start {
        program: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("a worker started without its pipes")]
    NoPipes,
    #[error("a worker stopped answering: {0}")]
    Lost(#[source] std::io::Error),
    #[error("a worker ended before answering (see its message above)")]
    Ended,
    /// The worker's own error, as its text (what crosses the process boundary).
    #[error("{0}")]
    Failed(String),
    #[error("a worker's answer is not a run: {0}")]
    NotARun(#[source] serde_json::Error),
}

/// The design case of a command that runs design cases only (`spine study`, `spine sweep`, a
/// sharded multi-start), or [`RunError::WrongKind`] naming the command.
pub(crate) fn design_case<'c>(
    case: &'c spine_case::Case,
    command: &'static str,
) -> Result<&'c spine_case::DesignCase, RunError> {
    match case {
        spine_case::Case::Design(c) => Ok(c),
        other => Err(RunError::WrongKind { command, needs: "a \"design\" case".into(), kind: other.kind() }),
    }
}
