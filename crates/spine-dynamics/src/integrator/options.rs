//! What a run is asked for ([`Options`]) and what it reports ([`Stats`], [`Outcome`]).

use serde::Serialize;
use spine_check::FieldError;

/// Default relative tolerance: T_90 of a step response and the reach and return times of a pulse
/// train within 1e-6 relative of a run at 1e-12. Chosen with TR-BDF2 (measured 3e-7 on the paper's
/// 5- and 10-link step cases and the 7-link pulse case; its error shrinks like rtol^0.67); Radau IIA
/// is far inside it (T_90 within about 1e-11 s at this rtol, `benchmarks/DYNAMICS.md`), and the
/// default is kept so that results of a case stay comparable. `tests/accuracy.rs` checks it.
pub const DEFAULT_RTOL: f64 = 1e-9;
/// Default absolute tolerance, rad and rad/s (a hundredth of [`DEFAULT_RTOL`]).
pub const DEFAULT_ATOL: f64 = 1e-11;

/// The integration method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Radau IIA, order 5 (three stages; the default).
    #[default]
    Radau5,
    /// TR-BDF2, order 2 (the cross-check).
    #[serde(rename = "trbdf2")]
    TrBdf2,
}

/// Integrator settings.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Options {
    /// The method (default [`Method::Radau5`]).
    pub method: Method,
    /// Relative tolerance (default [`DEFAULT_RTOL`]).
    pub rtol: f64,
    /// Absolute tolerance, in the units of each component (rad, rad/s; default [`DEFAULT_ATOL`]).
    pub atol: f64,
    /// First step, s (default: 1e-5 of the span).
    pub initial_step: Option<f64>,
    /// Largest step, s (default: no limit).
    pub max_step: Option<f64>,
    /// Most accepted steps (default 200 000).
    pub max_steps: usize,
    /// Newton stops when the weighted correction is below this (default 1e-3).
    pub newton_tolerance: f64,
}

impl Options {
    /// Checks every setting against what the integrator can do: `rtol` in [1e-14, 0.1] (below,
    /// round-off dominates and the steps never pass the test), `atol` in [1e-20, 1],
    /// `newton_tolerance` in [1e-10, 1], steps finite and positive, 1 … 10⁸ accepted steps.
    pub fn validate(&self) -> Result<(), FieldError> {
        let ranges = [
            ("rtol", Some(self.rtol), 1e-14, 0.1),
            ("atol", Some(self.atol), 1e-20, 1.0),
            ("newton_tolerance", Some(self.newton_tolerance), 1e-10, 1.0),
            ("initial_step", self.initial_step, f64::MIN_POSITIVE, f64::MAX),
            ("max_step", self.max_step, f64::MIN_POSITIVE, f64::MAX),
        ];
        for (field, v, lo, hi) in ranges {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= lo && *v <= hi)) {
                let message = if hi == f64::MAX {
                    format!("must be a finite number > 0, got {v}")
                } else {
                    format!("must be in [{lo:e}, {hi}], got {v}")
                };
                return Err(FieldError::new(field, message));
            }
        }
        if !(1..=MAX_STEPS).contains(&self.max_steps) {
            let message = format!("must be between 1 and {MAX_STEPS}, got {}", self.max_steps);
            return Err(FieldError::new("max_steps", message));
        }
        Ok(())
    }
}

impl Options {
    /// Whether a run over `span` seconds of a system of dimension `dim` can reach its end: with a
    /// `max_step`, it needs at least `span / max_step` steps, which must fit in `max_steps` and in
    /// the memory budget (`spine_stop::memory`; every step is stored). The error names `max_step`
    /// and says how many steps fit.
    pub fn check_reach(&self, span: f64, dim: usize) -> Result<(), FieldError> {
        let Some(h) = self.max_step else { return Ok(()) };
        let needed = span / h;
        let within = super::steps_within_memory(dim, 0);
        let (limit, what) = if self.max_steps <= within {
            (self.max_steps, "max_steps allows".to_string())
        } else {
            (
                within,
                format!(
                    "the memory budget ({}) holds",
                    spine_stop::memory::shown_bytes(spine_stop::memory::budget() as f64)
                ),
            )
        };
        if needed > limit as f64 {
            return Err(FieldError::new(
                "max_step",
                format!(
                    "steps of at most {h} s need at least {needed:.3e} steps to cover {span} s, and {what} {limit}: the run could never reach its end; give a max_step of at least {:.3e} s (or none)",
                    span / limit as f64
                ),
            ));
        }
        Ok(())
    }
}

/// Most accepted steps a run may be given.
pub const MAX_STEPS: usize = 100_000_000;

impl Default for Options {
    fn default() -> Self {
        Self {
            method: Method::default(),
            rtol: DEFAULT_RTOL,
            atol: DEFAULT_ATOL,
            initial_step: None,
            max_step: None,
            max_steps: 200_000,
            newton_tolerance: 1e-3,
        }
    }
}

/// Counts of the integrator's work.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Stats {
    pub accepted_steps: usize,
    pub rejected_steps: usize,
    pub newton_failures: usize,
    pub newton_iterations: usize,
    pub rhs_evaluations: usize,
    pub jacobian_evaluations: usize,
    pub factorizations: usize,
    /// Largest `‖Δy‖∞` the projection applied to an accepted step.
    pub max_projection: f64,
}

impl Stats {
    /// Adds the work of another run (the largest projection is the larger of the two).
    pub fn absorb(&mut self, other: &Stats) {
        self.accepted_steps += other.accepted_steps;
        self.rejected_steps += other.rejected_steps;
        self.newton_failures += other.newton_failures;
        self.newton_iterations += other.newton_iterations;
        self.rhs_evaluations += other.rhs_evaluations;
        self.jacobian_evaluations += other.jacobian_evaluations;
        self.factorizations += other.factorizations;
        self.max_projection = self.max_projection.max(other.max_projection);
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum Outcome {
    Completed,
    /// The step size fell below round-off at `t`.
    StepTooSmall {
        t: f64,
    },
    /// `max_steps` accepted steps before reaching the end, at `t`.
    StepLimit {
        t: f64,
    },
    /// The steps stored so far filled the process's memory budget (`spine_stop::memory`) at `t`:
    /// the run ends with what it reached instead of aborting.
    MemoryLimit {
        t: f64,
    },
    /// The caller's stop condition held at `t`.
    Stopped {
        t: f64,
    },
    /// The run's wall-clock limit passed (`spine_stop`) at `t`.
    TimeLimit {
        t: f64,
    },
    /// A stop was requested from outside (Ctrl-C) at `t`.
    Interrupted {
        t: f64,
    },
}

impl std::fmt::Display for Outcome {
    /// `completed`, or how the run ended and at which time (`step too small at t = 0.1234 s`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (what, t) = match *self {
            Self::Completed => return f.write_str("completed"),
            Self::StepTooSmall { t } => ("step too small", t),
            Self::StepLimit { t } => ("step limit reached", t),
            Self::MemoryLimit { t } => ("memory budget of the stored steps reached", t),
            Self::Stopped { t } => ("stopped by its stop condition", t),
            Self::TimeLimit { t } => ("time limit passed", t),
            Self::Interrupted { t } => ("interrupted", t),
        };
        write!(f, "{what} at t = {t:.6} s")
    }
}
