//! TR-BDF2: an L-stable, stiffly accurate, second-order one-step method with an embedded
//! third-order error estimate (Bank et al. 1985; Hosea & Shampine 1996, the method of MATLAB's
//! `ode23tb`), with
//!
//! * simplified Newton iterations on each implicit stage, using the exact Jacobian `∂f/∂y` supplied
//!   by the system (forward AD for the spine);
//! * error control on the weighted RMS norm `‖e_i / (atol + rtol |y_i|)‖`, with the estimate filtered
//!   through `(I − h d J)⁻¹` as in Hosea & Shampine (so stiff components do not force tiny steps);
//! * a projection of every accepted step onto the system's invariant manifold (for the spine,
//!   `Φ = 0` and `Φ̇ = 0`);
//! * steps that land on the system's breakpoints (switching instants of the forcing), never across;
//! * cubic Hermite dense output, used to locate events and sample the solution;
//! * optional forward sensitivities `S = ∂y/∂p`, propagated through the same discrete scheme
//!   (internal differentiation: the exact derivative of the computed solution for the accepted step
//!   sequence), including the projection.
//!
//! Stages: `z₂ = y + h d (f(y) + f(z₂))` (trapezoidal rule to `t + γh`) and
//! `y₁ = y + h (w f(y) + w f(z₂) + d f(y₁))` (BDF2), with `γ = 2 − √2`, `d = γ/2`, `w = √2/4`.
//!
//! Modules: [`options`] (settings and statistics), [`trbdf2`] (one step), [`dense`] (dense output
//! and events); this file is the driver (step-size control, breakpoints, projection).

mod dense;
mod options;
mod trbdf2;

pub use crate::ode::OdeSystem;
pub use dense::{Event, Interval, Trajectory};
pub use options::{Options, Outcome, Stats, DEFAULT_ATOL, DEFAULT_RTOL};

use nalgebra::DMatrix;
use trbdf2::{attempt, step_sensitivities, D};

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

/// Integrates from `(t0, y0)` to `t_end`.
pub fn integrate(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
    extras: Extras<'_>,
) -> Trajectory {
    let Extras { sensitivities, steps, stop } = extras;
    let n = sys.dim();
    let mut stats = Stats::default();
    let mut intervals = Vec::new();
    let mut breaks = sys.breakpoints(t0, t_end);
    breaks.push(t_end);
    let mut next_break = 0;
    let piece_of = |t: f64, end: f64| 0.5 * (t + end);

    let mut t = t0;
    let mut y = y0.to_vec();
    sys.project(&mut y);
    let y_start = y.clone();
    let mut s = sensitivities;
    let mut piece = piece_of(t, breaks[0]);
    let evaluate = |t: f64, piece: f64, y: &[f64], s: &Option<DMatrix<f64>>, stats: &mut Stats| {
        let f = sys.rhs(t, piece, y);
        let jac = sys.jacobian(t, piece, y);
        stats.rhs_evaluations += 1;
        stats.jacobian_evaluations += 1;
        let s_dot = s.as_ref().map(|s| &jac * s + sys.rhs_params(t, piece, y));
        (f, jac, s_dot)
    };
    // Without sensitivities the Newton matrix may use a Jacobian from an earlier step (simplified
    // Newton); it is refreshed when Newton slows down, fails, or after `JACOBIAN_AGE` steps. With
    // sensitivities it is exact at every step (`Ṡ = J S + ∂f/∂p` needs it).
    const JACOBIAN_AGE: usize = 20;
    const SLOW_NEWTON: usize = 6;
    let mut jac_age = 0usize;
    let (mut f, mut jac, mut s_dot) = evaluate(t, piece, &y, &s, &mut stats);
    let span = t_end - t0;
    let mut h = opts.initial_step.unwrap_or(1e-5 * span);
    let h_max = opts.max_step.unwrap_or(f64::INFINITY);
    let mut replay = steps.map(|st| st.iter().copied().filter(|&x| x > t0).collect::<Vec<_>>().into_iter());
    let mut outcome = Outcome::Completed;

    while t < t_end {
        if let Some(reason) = spine_stop::check() {
            outcome = match reason {
                spine_stop::StopReason::TimeLimit => Outcome::TimeLimit { t },
                spine_stop::StopReason::Interrupted => Outcome::Interrupted { t },
            };
            break;
        }
        if stats.accepted_steps >= opts.max_steps {
            outcome = Outcome::StepLimit { t };
            break;
        }
        let seg_end = breaks[next_break];
        let fixed = replay.as_mut().map(|r| r.next().unwrap_or(t_end));
        let mut h_try = match fixed {
            Some(t1) => t1 - t,
            None => h.min(h_max).min(seg_end - t),
        };
        if seg_end - (t + h_try) <= 1e-10 * h_try {
            h_try = seg_end - t;
        }
        // Below the step floor, or NaN.
        if h_try.partial_cmp(&(10.0 * f64::EPSILON * t.abs().max(span))) != Some(std::cmp::Ordering::Greater) {
            outcome = Outcome::StepTooSmall { t };
            break;
        }
        let t1 = if seg_end - (t + h_try) <= 1e-10 * h_try { seg_end } else { t + h_try };
        let h_step = t1 - t;

        let lu = (DMatrix::<f64>::identity(n, n) - &jac * (h_step * D)).lu();
        stats.factorizations += 1;
        let iterations_before = stats.newton_iterations;
        let Some(step) = attempt(sys, t, piece, h_step, &y, &f, &lu, opts, &mut stats) else {
            stats.newton_failures += 1;
            if jac_age > 0 {
                jac = sys.jacobian(t, piece, &y);
                stats.jacobian_evaluations += 1;
                jac_age = 0;
                continue;
            }
            if fixed.is_some() {
                outcome = Outcome::StepTooSmall { t };
                break;
            }
            h = 0.25 * h_step;
            continue;
        };
        if fixed.is_none() && step.err > 1.0 {
            stats.rejected_steps += 1;
            h = h_step * (0.9 * step.err.powf(-1.0 / 3.0)).clamp(0.2, 0.9);
            continue;
        }

        // Accepted.
        let mut y1 = step.y1.clone();
        let start_sens = s.clone().zip(s_dot.clone());
        if let (Some(s0), Some(sd0)) = (s.as_mut(), s_dot.as_ref()) {
            *s0 = step_sensitivities(sys, (t, t1), piece, &step, &y1, s0, sd0, &mut stats);
        }
        let before = y1.clone();
        sys.project(&mut y1);
        let moved = before.iter().zip(&y1).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        stats.max_projection = stats.max_projection.max(moved);
        let slow = stats.newton_iterations - iterations_before > SLOW_NEWTON;
        let (f1, jac1, s_dot1) = if s.is_some() || slow || jac_age + 1 >= JACOBIAN_AGE {
            jac_age = 0;
            let (f1, j1, sd1) = evaluate(t1, piece, &y1, &s, &mut stats);
            (f1, Some(j1), sd1)
        } else {
            jac_age += 1;
            stats.rhs_evaluations += 1;
            (sys.rhs(t1, piece, &y1), None, None)
        };
        let sens = match (start_sens, &s, &s_dot1) {
            (Some((s0, sd0)), Some(s1), Some(sd1)) => Some([s0, sd0, s1.clone(), sd1.clone()]),
            _ => None,
        };
        intervals.push(Interval { t0: t, t1, y0: y.clone(), y1: y1.clone(), f0: f.clone(), f1: f1.clone(), sens });
        stats.accepted_steps += 1;
        t = t1;
        y = y1;
        f = f1;
        if let Some(j1) = jac1 {
            jac = j1;
        }
        s_dot = s_dot1;
        if fixed.is_none() {
            h = h_step * (0.9 * step.err.max(1e-10).powf(-1.0 / 3.0)).clamp(0.2, 5.0);
        }
        if stop.is_some_and(|f| f(t, &y)) {
            outcome = Outcome::Stopped { t };
            break;
        }
        if t >= seg_end && next_break + 1 < breaks.len() {
            next_break += 1;
            piece = piece_of(t, breaks[next_break]);
            let (fa, ja, sa) = evaluate(t, piece, &y, &s, &mut stats);
            f = fa;
            jac = ja;
            s_dot = sa;
            jac_age = 0;
        }
    }
    Trajectory { start: (t0, y_start), intervals, outcome, stats }
}
