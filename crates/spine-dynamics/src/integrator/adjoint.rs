//! Gradients of outputs of a computed solution by the discrete adjoint of its Radau IIA steps.
//!
//! An output is a linear functional of the dense output's sensitivities, `Σ_k c_kᵀ S(t_k)` (the
//! envelope form of `d g(y(t*))/dp` at an extremum or a fixed time, `∇g · S(t*)`; an event's
//! `dt/dp` is this over `−ġ`). [`adjoint`] gives, for each output, `λ₀ = ∂/∂y(t₀)` and the
//! parameters' direct part, so that `d/dp = λ₀ᵀ S(t₀) + direct`: the same numbers as forward
//! sensitivities started from `S(t₀)` ([`super::Extras::sensitivities`]), to round-off, at a cost
//! that does not grow with the number of parameters (a backward sweep per output, sharing each
//! step's stage Jacobians and Newton matrices between the outputs).
//!
//! * The runs are swept last to first (e.g. the periods of a periodic response, each its own
//!   run, the next one starting where the last ended), each step by
//!   `super::radau::adjoint::step_adjoint`.
//! * An output at `t` belongs to the step with `t₀ < t ≤ t₁` (the first step for the start, the
//!   first run whose span reaches `t`), where the forward dense output reads `S(t) = b₀ S₀ + b₁ Ṡ₀ +
//!   b₂ S₁ + b₃ Ṡ₁` (cubic Hermite, `Ṡ = J S + ∂f/∂p`): its weights seed the step's two ends.
//!
//! The runs must be Radau IIA runs whose steps are stored ([`super::Trajectory`]); `None` for
//! TR-BDF2 runs (no collocation polynomial) and where a step's Newton matrices are singular.

use super::dense::{Interval, Trajectory};
use super::options::Stats;
use super::radau::adjoint::{step_adjoint, AdjointWork};
use super::OdeSystem;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// How a design's gradients through the motion are computed (eq. (35)'s `dT_90/dC`, eq. (37)'s
/// `d min_t X / dK`): both are the exact derivative of the computed motion and agree to
/// round-off (`tests/adjoint.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Sensitivities {
    /// The discrete adjoint of the Radau IIA steps ([`adjoint`]): each simulation runs plain
    /// and keeps its steps, and a backward sweep per output gives the gradients, at a cost that
    /// does not grow with the number of parameters. A TR-BDF2 run falls back to `forward`.
    #[default]
    Adjoint,
    /// Forward sensitivities `S = ∂y/∂p` (`N + 1` columns) through every step of every
    /// simulation.
    Forward,
}

impl Sensitivities {
    /// What a run by `method` uses: the adjoint needs Radau IIA's stored steps.
    pub fn for_method(self, method: super::Method) -> Self {
        match (self, method) {
            (Self::Adjoint, super::Method::Radau5) => Self::Adjoint,
            _ => Self::Forward,
        }
    }
}

/// One term `cᵀ S(t)` of an output.
#[derive(Clone, Debug, PartialEq)]
pub struct Term {
    /// Time, s, and the weights `c` (one per state).
    pub t: f64,
    pub weights: Vec<f64>,
}

/// The gradient of one output: `d/dp = initialᵀ S(t₀) + direct`.
#[derive(Clone, Debug, PartialEq)]
pub struct Gradient {
    /// `λ₀`, the output's gradient in the first run's start state.
    pub initial: Vec<f64>,
    /// The parameters' part through `∂f/∂p` along the runs.
    pub direct: Vec<f64>,
}

impl Gradient {
    /// `d/dp` for the start sensitivities `s0` (`dim × n_params`).
    pub fn total(&self, s0: &DMatrix<f64>) -> Vec<f64> {
        let from_start = s0.tr_mul(&DVector::from_column_slice(&self.initial));
        self.direct.iter().zip(from_start.iter()).map(|(a, b)| a + b).collect()
    }
}

/// The gradients of `outputs` (each a sum of [`Term`]s) over `runs` (module docs), with the work
/// of the sweep; `None` when a step's adjoint fails or a stop ([`spine_stop::check`]) ends the sweep.
pub fn adjoint(sys: &dyn OdeSystem, runs: &[&Trajectory], outputs: &[Vec<Term>]) -> Option<(Vec<Gradient>, Stats)> {
    let (n, p, m) = (sys.dim(), sys.n_params(), outputs.len());
    let mut stats = Stats::default();
    // Each term's (run, step) (step `None`: the run's start, a run without steps).
    let mut seeds: Vec<(usize, Option<usize>, usize, &Term)> = Vec::new();
    for (k, output) in outputs.iter().enumerate() {
        for term in output {
            let r = runs.iter().position(|run| run.span().1 >= term.t).unwrap_or(runs.len().checked_sub(1)?);
            let steps = &runs[r].intervals;
            let s = (!steps.is_empty()).then(|| steps.partition_point(|iv| iv.t1 < term.t).min(steps.len() - 1));
            seeds.push((r, s, k, term));
        }
    }
    let mut lambda = DMatrix::zeros(n, m);
    let mut direct = DMatrix::zeros(p, m);
    let mut work = AdjointWork::default();
    for (r, run) in runs.iter().enumerate().rev() {
        for (s, iv) in run.intervals.iter().enumerate().rev() {
            // A stop (the time limit) ends the sweep: no gradient, as a failed step gives none.
            spine_stop::check().is_none().then_some(())?;
            let here: Vec<_> = seeds.iter().filter(|(rr, ss, ..)| *rr == r && *ss == Some(s)).collect();
            let mut at_start = DMatrix::zeros(n, m);
            for &&(_, _, k, term) in &here {
                let (b, _) = iv.weights(term.t);
                seed_end(sys, iv, (iv.t1, &iv.y1), (b[2], b[3]), term, k, &mut lambda, &mut direct);
                seed_end(sys, iv, (iv.t0, &iv.y0), (b[0], b[1]), term, k, &mut at_start, &mut direct);
            }
            let (lambda0, from_step) = step_adjoint(sys, iv, &lambda, &mut work, &mut stats)?;
            lambda = lambda0 + at_start;
            direct += from_step;
        }
        for &(_, _, k, term) in seeds.iter().filter(|(rr, ss, ..)| *rr == r && ss.is_none()) {
            for (l, c) in lambda.column_mut(k).iter_mut().zip(&term.weights) {
                *l += c;
            }
        }
    }
    let gradients = (0..m)
        .map(|k| Gradient {
            initial: lambda.column(k).iter().copied().collect(),
            direct: direct.column(k).iter().copied().collect(),
        })
        .collect();
    Some((gradients, stats))
}

/// A term's share at one end `(t, y)` of its step: `b cᵀ S + b' cᵀ Ṡ` with `Ṡ = J S + ∂f/∂p`
/// (`b'` carries the step's length).
#[allow(clippy::too_many_arguments)]
fn seed_end(
    sys: &dyn OdeSystem,
    iv: &Interval,
    (t, y): (f64, &[f64]),
    (b, b_rate): (f64, f64),
    term: &Term,
    k: usize,
    lambda: &mut DMatrix<f64>,
    direct: &mut DMatrix<f64>,
) {
    for (l, c) in lambda.column_mut(k).iter_mut().zip(&term.weights) {
        *l += b * c;
    }
    if b_rate == 0.0 {
        return;
    }
    let c: Vec<f64> = term.weights.iter().map(|w| w * b_rate).collect();
    let (to_state, to_params) = sys.vector_jacobian(t, iv.piece(), y).products(&c);
    for (l, x) in lambda.column_mut(k).iter_mut().zip(to_state) {
        *l += x;
    }
    for (d, x) in direct.column_mut(k).iter_mut().zip(to_params) {
        *d += x;
    }
}
