//! Stiff one-step integrators for `ẏ = f(t, y)` with a projection onto an invariant manifold:
//!
//! * **Radau IIA of order 5** (the default, [`Method::Radau5`]; Hairer & Wanner 1996, IV.8): three
//!   collocation stages, L-stable and stiffly accurate, solved by simplified Newton iterations in the
//!   transformed variables (one real and one complex Newton matrix per step size), with the
//!   embedded third-order error estimate filtered through `(μ/h I − J̃)⁻¹` and Gustafsson's
//!   predictive step-size control;
//! * **TR-BDF2** ([`Method::TrBdf2`]; Bank et al. 1985, Hosea & Shampine 1996, MATLAB's `ode23tb`):
//!   L-stable, second order, kept as an option and as the cross-check of the tests.
//!
//! Both share:
//! * error control on the weighted RMS norm `‖e_i / (atol + rtol |y_i|)‖`;
//! * Newton matrices `σ I − J̃` from the system's [`OdeSystem::linearize`] ([`crate::newton`]: dense LU by
//!   default, the chain's `O(N)` structured factorisation for the spine);
//! * a projection of every accepted step onto the system's invariant manifold (for the spine,
//!   `Φ = 0` and `Φ̇ = 0`);
//! * steps that land on the system's breakpoints (switching instants of the forcing), never across;
//! * dense output, used to locate events and sample the solution: Radau IIA's collocation
//!   polynomial (through the stage values), TR-BDF2's cubic Hermite interpolant of the step ends
//!   (sensitivities: cubic Hermite of `S` and `Ṡ` for both);
//! * optional forward sensitivities `S = ∂y/∂p`, propagated through the same discrete scheme
//!   (internal differentiation: the exact derivative of the computed solution for the accepted step
//!   sequence), including the projection.
//!
//! Modules: `options` (settings and statistics), `radau` and `trbdf2` (each method's step
//! and driver), [`crate::newton`] (the chain's Newton matrices), `dense` (dense output and events); this file
//! holds what the drivers share (stops, landing on breakpoints, projection).

pub mod adjoint;
mod dense;
mod event;
mod options;
mod radau;
mod trbdf2;

pub use crate::ode::OdeSystem;
pub use dense::{Event, EventFunction, Interval, Trajectory};
pub use event::first_event;
pub use options::{Method, Options, Outcome, Stats, DEFAULT_ATOL, DEFAULT_RTOL};

use nalgebra::DMatrix;

/// Optional parts of a run.
#[derive(Default)]
pub struct Extras<'a> {
    /// `S0` (`dim × n_params`, usually zeros): also propagate `S = ∂y/∂p`.
    pub sensitivities: Option<DMatrix<f64>>,
    /// Replay this step sequence exactly (no error control): finite-difference checks of
    /// sensitivities use it.
    pub steps: Option<&'a [f64]>,
    /// Checked after every accepted step at `(t, y)`; `true` ends the run ([`Outcome::Stopped`]).
    pub stop: Option<&'a StopCondition<'a>>,
}

/// A test on an accepted step `(t, y)`: `true` ends the integration.
pub type StopCondition<'a> = dyn Fn(f64, &[f64]) -> bool + 'a;

/// Integrates from `(t0, y0)` to `t_end` by `opts.method`.
pub fn integrate(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
    extras: Extras<'_>,
) -> Trajectory {
    match opts.method {
        Method::Radau5 => radau::integrate(sys, t0, y0, t_end, opts, extras),
        Method::TrBdf2 => trbdf2::integrate(sys, t0, y0, t_end, opts, extras),
    }
}

/// Bytes one stored step takes in a system of dimension `dim` with `sensitivities` parameter
/// columns: the [`Interval`] itself three times over (a growing vector holds its old buffer and
/// one of twice its length while it moves), seven vectors of `dim` values (both ends, their
/// derivatives, the collocation polynomial) with the allocator's overhead, and four `dim ×
/// sensitivities` matrices when sensitivities are propagated.
pub fn step_bytes(dim: usize, sensitivities: usize) -> usize {
    let vector = 8 * dim.max(1) + 32;
    let matrices = if sensitivities > 0 { 4 * (8 * dim.max(1) * sensitivities + 64) } else { 0 };
    3 * std::mem::size_of::<Interval>() + 7 * vector + matrices
}

/// Most steps a run may store within the process's memory budget ([`spine_stop::memory::budget`]);
/// the run ends there with [`Outcome::MemoryLimit`], and a vector that cannot grow (a tighter
/// limit than the budget assumed) ends it the same way.
pub fn steps_within_memory(dim: usize, sensitivities: usize) -> usize {
    spine_stop::memory::budget() / step_bytes(dim, sensitivities)
}

/// Stores an accepted step, or says the memory is exhausted (the vector could not grow).
pub(super) fn store(intervals: &mut Vec<Interval>, step: Interval, t: f64) -> Result<(), Outcome> {
    intervals.try_reserve(1).map_err(|_| Outcome::MemoryLimit { t })?;
    intervals.push(step);
    Ok(())
}

/// The span `[t0, t_end]` cut at the system's breakpoints, and where the driver is in it.
pub(super) struct Course<'a> {
    span: f64,
    breaks: Vec<f64>,
    next_break: usize,
    replay: Option<std::vec::IntoIter<f64>>,
    max_steps: usize,
    /// Steps that fit in the memory budget.
    memory_steps: usize,
    sys: &'a dyn OdeSystem,
}

/// Where the next step ends.
pub(super) struct NextStep {
    pub t1: f64,
    /// A replayed step (no error control).
    pub fixed: bool,
}

impl<'a> Course<'a> {
    pub(super) fn new(
        sys: &'a dyn OdeSystem,
        (t0, t_end): (f64, f64),
        steps: Option<&[f64]>,
        opts: &Options,
        sensitivities: usize,
    ) -> Self {
        let mut breaks = sys.breakpoints(t0, t_end);
        breaks.push(t_end);
        let replay = steps.map(|st| st.iter().copied().filter(|&x| x > t0).collect::<Vec<_>>().into_iter());
        let memory_steps = steps_within_memory(sys.dim(), sensitivities);
        Self { span: t_end - t0, breaks, next_break: 0, replay, max_steps: opts.max_steps, memory_steps, sys }
    }

    /// A time inside the current smooth piece of `f`.
    pub(super) fn piece(&self, t: f64) -> f64 {
        0.5 * (t + self.breaks[self.next_break])
    }

    /// The end of the current piece.
    pub(super) fn piece_end(&self) -> f64 {
        self.breaks[self.next_break]
    }

    /// The default first step, s.
    pub(super) fn initial_step(&self, opts: &Options) -> f64 {
        opts.initial_step.unwrap_or(1e-5 * self.span)
    }

    /// Why the run must end before a step from `t`: a stop request, the step limit.
    pub(super) fn must_stop(&self, t: f64, stats: &Stats) -> Option<Outcome> {
        if let Some(reason) = spine_stop::check() {
            return Some(match reason {
                spine_stop::StopReason::TimeLimit => Outcome::TimeLimit { t },
                spine_stop::StopReason::Interrupted => Outcome::Interrupted { t },
            });
        }
        if stats.accepted_steps >= self.max_steps {
            return Some(Outcome::StepLimit { t });
        }
        (stats.accepted_steps >= self.memory_steps).then_some(Outcome::MemoryLimit { t })
    }

    /// The next step from `t` of (at most) `h`: the replayed one, or `h` cut at the piece's end and
    /// stretched onto it when it would stop just short. `Err` below the step floor (or NaN).
    pub(super) fn next_step(&mut self, t: f64, h: f64) -> Result<NextStep, Outcome> {
        let seg_end = self.piece_end();
        let fixed = self.replay.as_mut().map(|r| r.next().unwrap_or(seg_end.max(t)));
        let mut h_try = match fixed {
            Some(t1) => t1 - t,
            None => h.min(seg_end - t),
        };
        if seg_end - (t + h_try) <= 1e-10 * h_try {
            h_try = seg_end - t;
        }
        if h_try.partial_cmp(&(10.0 * f64::EPSILON * t.abs().max(self.span))) != Some(std::cmp::Ordering::Greater) {
            return Err(Outcome::StepTooSmall { t });
        }
        let t1 = if seg_end - (t + h_try) <= 1e-10 * h_try { seg_end } else { t + h_try };
        Ok(NextStep { t1, fixed: fixed.is_some() })
    }

    /// After an accepted step to `t`: `true` when `t` ends the current piece and another follows
    /// (the caller re-evaluates `f` and `J̃` there).
    pub(super) fn passed_break(&mut self, t: f64) -> bool {
        if t >= self.piece_end() && self.next_break + 1 < self.breaks.len() {
            self.next_break += 1;
            return true;
        }
        false
    }

    /// Projects an accepted `y₁` (and its sensitivities, at the unprojected point) onto the
    /// system's manifold, recording the largest move.
    pub(super) fn project(&self, y1: &mut [f64], s1: Option<&mut DMatrix<f64>>, stats: &mut Stats) {
        if let Some(s1) = s1 {
            self.sys.project_sensitivities(y1, s1);
        }
        let before = y1.to_vec();
        self.sys.project(y1);
        let moved = before.iter().zip(y1.iter()).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        stats.max_projection = stats.max_projection.max(moved);
    }
}

/// The weighted RMS norm of `v` with scales `atol + rtol max(|a_i|, |b_i|)`.
pub(super) fn weighted_rms(v: &[f64], a: &[f64], b: &[f64], o: &Options) -> f64 {
    let n = v.len().max(1);
    let s: f64 = (0..v.len())
        .map(|i| {
            let scale = o.atol + o.rtol * a[i].abs().max(b[i].abs());
            (v[i] / scale).powi(2)
        })
        .sum();
    (s / n as f64).sqrt()
}

/// Dense stage Jacobians pay when the state has at most this many times as many components as
/// there are parameters: a linear iteration or a directional pass per parameter column takes
/// about this many passes.
pub(super) const DENSE_AFTER: usize = 4;

/// `Ṡ = J S + ∂f/∂p` at `(t, y)`, column by column through [`OdeSystem::jacobian_times`].
pub(super) fn sensitivity_rate(sys: &dyn OdeSystem, t: f64, piece: f64, y: &[f64], s: &DMatrix<f64>) -> DMatrix<f64> {
    // With few states per parameter, one dense Jacobian beats a directional pass per column.
    if y.len() <= DENSE_AFTER * s.ncols() {
        let (jac, params) = sys.jacobian_and_params(t, piece, y);
        return jac * s + params;
    }
    let mut rate = sys.rhs_params(t, piece, y);
    for k in 0..s.ncols() {
        let column: Vec<f64> = s.column(k).iter().copied().collect();
        let js = sys.jacobian_times(t, piece, y, &column);
        for (i, v) in js.into_iter().enumerate() {
            rate[(i, k)] += v;
        }
    }
    rate
}
