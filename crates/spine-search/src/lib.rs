//! # spine-search: gradient-free optimisers for bounded, constrained problems
//!
//! For problems whose constraints are not smooth, such as eq. (37) of the paper (a minimum over time
//! of a simulated motion), where the paper used MATLAB's `ga` and `patternsearch`:
//!
//! * [`genetic_algorithm`]: a real-coded GA with binary tournaments, simulated binary crossover
//!   (SBX), polynomial mutation and elitism (Deb & Agrawal 1995; Deb 2000);
//! * [`pattern_search`]: a generalized pattern search with the `2n` coordinate directions, mesh
//!   expansion on success and contraction on failure (Torczon 1997).
//!
//! Both compare points by Deb's feasibility rules ([`Evaluation::better_than`]): a feasible point
//! beats an infeasible one, two feasible points compare by objective, two infeasible points by
//! constraint violation. No penalty weight to tune. Both are seeded and deterministic: the same
//! seed gives the same sequence of evaluations on every machine.
//!
//! No maintained crate offers both methods with constraint handling (genevo is unmaintained and
//! weak on continuous problems; argmin 0.11 has Nelder–Mead and PSO but neither a GA nor pattern
//! search; see `docs/design.md`);
//! these are tested on Rosenbrock, Rastrigin and a constrained problem with known minima.
//!
//! Further modules:
//!
//! * `pattern`: Generalized pattern search on the `2n` coordinate directions, with the mesh size
//!   measured as a fraction of each variable's range.
//!
//! ```
//! use spine_search::{pattern_search, Bounds, Evaluation, PatternSettings};
//! // min (x − 1)² + (y + 0.5)² subject to x ≥ 1.5 (the violation is counted, no penalty weight).
//! let mut f = |p: &[f64]| Evaluation { objective: (p[0] - 1.0).powi(2) + (p[1] + 0.5).powi(2), violation: (1.5 - p[0]).max(0.0) };
//! let bounds = Bounds { lower: vec![-2.0, -2.0], upper: vec![2.0, 2.0] };
//! let r = pattern_search(&mut f, &bounds, &[0.0, 0.0], &PatternSettings::default(), &mut |_| {}).unwrap();
//! assert_eq!(r.best.violation, 0.0);
//! assert!((r.x[0] - 1.5).abs() < 1e-4 && (r.x[1] + 0.5).abs() < 1e-4); // on the constraint
//! ```
#![forbid(unsafe_code)]

mod ga;
mod pattern;

pub use ga::{genetic_algorithm, GaSettings};
pub use pattern::{pattern_search, PatternSettings};

use serde::{Deserialize, Serialize};

pub use spine_check::FieldError;

/// The value of one point: objective and total constraint violation (`0` when feasible).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Evaluation {
    pub objective: f64,
    pub violation: f64,
}

impl Evaluation {
    /// An unconstrained value.
    pub fn unconstrained(objective: f64) -> Self {
        Self { objective, violation: 0.0 }
    }

    /// A point that could not be evaluated (the simulation failed): worse than any other.
    pub fn failed() -> Self {
        Self { objective: f64::INFINITY, violation: f64::INFINITY }
    }

    /// Deb's feasibility rules. NaN counts as failed.
    pub fn better_than(&self, other: &Evaluation) -> bool {
        let clean = |e: &Evaluation| {
            if e.objective.is_nan() || e.violation.is_nan() {
                Evaluation::failed()
            } else {
                *e
            }
        };
        let (a, b) = (clean(self), clean(other));
        match (a.violation <= 0.0, b.violation <= 0.0) {
            (true, true) => a.objective < b.objective,
            (true, false) => true,
            (false, true) => false,
            (false, false) => a.violation < b.violation,
        }
    }
}

/// Box bounds `lower ≤ x ≤ upper` (finite, `lower < upper`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Bounds {
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

impl Bounds {
    pub fn dim(&self) -> usize {
        self.lower.len()
    }

    fn clamp(&self, i: usize, v: f64) -> f64 {
        v.clamp(self.lower[i], self.upper[i])
    }

    fn width(&self, i: usize) -> f64 {
        self.upper[i] - self.lower[i]
    }
}

/// Progress of a search, reported after every generation or poll.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Progress {
    /// Generation (GA) or iteration (pattern search).
    pub iteration: usize,
    pub evaluations: usize,
    pub best: Evaluation,
}

/// How a search ended. Serialised as its [`SearchStatus::name`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SearchStatus {
    /// Pattern search: the mesh fell below its tolerance (a mesh-local minimum).
    MeshConverged,
    /// GA: all generations ran; the best point did not change in the last `stall_generations`.
    Stalled,
    /// GA: all generations ran.
    GenerationLimit,
    /// The evaluation budget ran out first.
    EvaluationLimit,
    /// The run's wall-clock limit passed (`spine_stop`); the best point so far is reported.
    TimeLimit,
    /// A stop was requested from outside (Ctrl-C); the best point so far is reported.
    Interrupted,
}

impl SearchStatus {
    /// The name written to result files (`mesh_converged`, `generation_limit`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::MeshConverged => "mesh_converged",
            Self::Stalled => "stalled",
            Self::GenerationLimit => "generation_limit",
            Self::EvaluationLimit => "evaluation_limit",
            Self::TimeLimit => "time_limit",
            Self::Interrupted => "interrupted",
        }
    }

    /// The search ran to one of its own ends (not stopped from outside or by the clock).
    pub fn finished(self) -> bool {
        !matches!(self, Self::TimeLimit | Self::Interrupted)
    }
}

impl Serialize for SearchStatus {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.name())
    }
}

impl std::fmt::Display for SearchStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl From<spine_stop::StopReason> for SearchStatus {
    fn from(reason: spine_stop::StopReason) -> Self {
        match reason {
            spine_stop::StopReason::TimeLimit => Self::TimeLimit,
            spine_stop::StopReason::Interrupted => Self::Interrupted,
        }
    }
}

/// The result of a search.
#[derive(Clone, Debug, Serialize)]
pub struct SearchResult {
    pub status: SearchStatus,
    pub x: Vec<f64>,
    pub best: Evaluation,
    pub evaluations: usize,
    pub iterations: usize,
    /// Best value after each iteration.
    pub history: Vec<Progress>,
}
