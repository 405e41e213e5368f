//! TR-BDF2 ([`super::Method::TrBdf2`]): the two implicit stages by simplified Newton, the embedded
//! error estimate, the forward sensitivities through the same discrete scheme, and the driver.
//!
//! Stages: `z₂ = y + h d (f(y) + f(z₂))` (trapezoidal rule to `t + γh`) and
//! `y₁ = y + h (w f(y) + w f(z₂) + d f(y₁))` (BDF2), with `γ = 2 − √2`, `d = γ/2`, `w = √2/4`. The
//! error estimate is filtered through `(I − h d J)⁻¹` as in Hosea & Shampine (so stiff components do
//! not force tiny steps). The sensitivities use the exact dense Jacobian at both stages.

use super::dense::{Interval, Trajectory};
use super::options::{Options, Outcome, Stats};
use super::{weighted_rms, Course, Extras};
use crate::linearization::{Linearization, ShiftedSolve};
use crate::ode::OdeSystem;
use nalgebra::DMatrix;

const SQRT2: f64 = std::f64::consts::SQRT_2;
/// `γ = 2 − √2`: the trapezoidal stage ends at `t + γ h`.
const GAMMA: f64 = 2.0 - SQRT2;
/// Diagonal coefficient `d = γ / 2`.
const D: f64 = GAMMA / 2.0;
/// BDF2 stage weights of `f(y)` and `f(z₂)`.
const W: f64 = SQRT2 / 4.0;
/// `b − b̂` for the error estimate (third-order companion `b̂ = ((1 − w)/3, (3w + 1)/3, d/3)`).
const E1: f64 = (4.0 * W - 1.0) / 3.0;
const E2: f64 = -1.0 / 3.0;
const E3: f64 = 2.0 * D / 3.0;

/// A tried step: the new point, the stage, and the weighted error estimate.
struct Attempt {
    /// The trapezoidal stage at `t + γh`.
    pub z2: Vec<f64>,
    /// The new point (before projection).
    pub y1: Vec<f64>,
    /// The weighted RMS error estimate (accept when ≤ 1).
    pub err: f64,
}

/// Simplified Newton on `z = base + c f(t, z)` with the factored `I − c J`; `None` when it diverges
/// or does not converge in `MAX_NEWTON` iterations.
#[allow(clippy::too_many_arguments)]
fn newton(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    base: &[f64],
    c: f64,
    mut z: Vec<f64>,
    solve: &dyn Fn(Vec<f64>) -> Vec<f64>,
    y_ref: &[f64],
    opts: &Options,
    stats: &mut Stats,
) -> Option<(Vec<f64>, Vec<f64>)> {
    const MAX_NEWTON: usize = 12;
    let mut previous = f64::INFINITY;
    for _ in 0..MAX_NEWTON {
        let fz = sys.rhs(t, piece, &z);
        stats.rhs_evaluations += 1;
        stats.newton_iterations += 1;
        let residual: Vec<f64> = (0..z.len()).map(|i| base[i] + c * fz[i] - z[i]).collect();
        let dz = solve(residual);
        if dz.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for (zi, di) in z.iter_mut().zip(&dz) {
            *zi += di;
        }
        let norm = weighted_rms(&dz, y_ref, &z, opts);
        if norm <= opts.newton_tolerance {
            let fz = sys.rhs(t, piece, &z);
            stats.rhs_evaluations += 1;
            return Some((z, fz));
        }
        if norm > previous {
            return None;
        }
        previous = norm;
    }
    None
}

#[allow(clippy::too_many_arguments)]
fn attempt(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    h: f64,
    y: &[f64],
    f: &[f64],
    newton_matrix: &dyn ShiftedSolve<f64>,
    opts: &Options,
    stats: &mut Stats,
) -> Option<Attempt> {
    let n = y.len();
    // `I − h d J̃ = h d (σ I − J̃)` with `σ = 1/(h d)`.
    let solve = |mut rhs: Vec<f64>| -> Vec<f64> {
        newton_matrix.solve(&mut rhs);
        rhs.iter_mut().for_each(|v| *v /= h * D);
        rhs
    };
    // Stage 2: trapezoidal rule to t + γh.
    let guess: Vec<f64> = (0..n).map(|i| y[i] + GAMMA * h * f[i]).collect();
    let base2: Vec<f64> = (0..n).map(|i| y[i] + h * D * f[i]).collect();
    let (z2, f2) = newton(sys, t + GAMMA * h, piece, &base2, h * D, guess, &solve, y, opts, stats)?;
    // Stage 3: BDF2 to t + h; guess from the line through y and z2.
    let guess: Vec<f64> = (0..n).map(|i| y[i] + (z2[i] - y[i]) / GAMMA).collect();
    let base3: Vec<f64> = (0..n).map(|i| y[i] + h * W * (f[i] + f2[i])).collect();
    let (y1, f3) = newton(sys, t + h, piece, &base3, h * D, guess, &solve, y, opts, stats)?;
    let est = solve((0..n).map(|i| h * (E1 * f[i] + E2 * f2[i] + E3 * f3[i])).collect());
    let err = weighted_rms(&est, y, &y1, opts);
    Some(Attempt { z2, y1, err: if err.is_finite() { err } else { f64::INFINITY } })
}

/// `S₁ = ∂y₁/∂p` of an accepted step from `S₀` and `Ṡ₀ = J S₀ + ∂f/∂p` at its start: the exact
/// derivative of the two stages (the same discrete scheme), then of the projection at the
/// unprojected `y₁`.
#[allow(clippy::too_many_arguments)]
fn step_sensitivities(
    sys: &dyn OdeSystem,
    (t, t1): (f64, f64),
    piece: f64,
    step: &Attempt,
    y1: &[f64],
    s0: &DMatrix<f64>,
    sd0: &DMatrix<f64>,
    stats: &mut Stats,
) -> Option<DMatrix<f64>> {
    let n = y1.len();
    let h_step = t1 - t;
    let t2 = t + GAMMA * h_step;
    let j2 = sys.jacobian(t2, piece, &step.z2);
    let p2 = sys.rhs_params(t2, piece, &step.z2);
    let w2 = (DMatrix::<f64>::identity(n, n) - &j2 * (h_step * D)).lu();
    // `None` where a stage matrix `I − h d J` is singular at the step's own Jacobians (the Newton
    // matrix, an older `J̃`, was regular): the driver takes a shorter step.
    let s2 = w2.solve(&(s0 + (sd0 + &p2) * (h_step * D)))?;
    let j3 = sys.jacobian(t1, piece, y1);
    let p3 = sys.rhs_params(t1, piece, y1);
    let w3 = (DMatrix::<f64>::identity(n, n) - &j3 * (h_step * D)).lu();
    let rhs = s0 + (sd0 * W + (&j2 * &s2 + &p2) * W + &p3 * D) * h_step;
    let s1 = w3.solve(&rhs)?;
    stats.jacobian_evaluations += 2;
    stats.factorizations += 2;
    Some(s1)
}

/// The Newton matrix may use a linearisation from an earlier step (simplified Newton); it is
/// refreshed when Newton slows down (more than `SLOW_NEWTON` iterations in a step), fails, or
/// after `JACOBIAN_AGE` steps.
const JACOBIAN_AGE: usize = 20;
const SLOW_NEWTON: usize = 6;

/// The TR-BDF2 driver: step-size control (exponent 1/3), Jacobian reuse, breakpoints, projection.
pub(super) fn integrate(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
    extras: Extras<'_>,
) -> Trajectory {
    let Extras { sensitivities, steps, stop } = extras;
    let mut stats = Stats::default();
    let mut intervals = Vec::new();
    let columns = sensitivities.as_ref().map_or(0, |s| s.ncols());
    let mut course = Course::new(sys, (t0, t_end), steps, opts, columns);
    let mut point = Point::start(sys, &course, t0, y0, sensitivities, &mut stats);
    let y_start = point.y.clone();
    let mut h = course.initial_step(opts);
    let h_max = opts.max_step.unwrap_or(f64::INFINITY);
    let mut outcome = Outcome::Completed;

    while point.t < t_end {
        let t = point.t;
        if let Some(o) = course.must_stop(t, &stats) {
            outcome = o;
            break;
        }
        let next = match course.next_step(t, h.min(h_max)) {
            Ok(next) => next,
            Err(o) => {
                outcome = o;
                break;
            }
        };
        let (t1, fixed) = (next.t1, next.fixed);
        let h_step = t1 - t;
        stats.factorizations += 1;
        let Some(matrix) = point.jac.factor_real(1.0 / (h_step * D)) else {
            outcome = Outcome::StepTooSmall { t };
            break;
        };
        let iterations_before = stats.newton_iterations;
        let Some(step) = attempt(sys, t, point.piece, h_step, &point.y, &point.f, matrix.as_ref(), opts, &mut stats)
        else {
            stats.newton_failures += 1;
            if point.jac_age > 0 {
                point.jac = sys.linearize(t, point.piece, &point.y);
                stats.jacobian_evaluations += 1;
                point.jac_age = 0;
                continue;
            }
            if fixed {
                outcome = Outcome::StepTooSmall { t };
                break;
            }
            h = 0.25 * h_step;
            continue;
        };
        if !fixed && step.err > 1.0 {
            stats.rejected_steps += 1;
            h = h_step * (0.9 * step.err.powf(-1.0 / 3.0)).clamp(0.2, 0.9);
            continue;
        }
        let slow = stats.newton_iterations - iterations_before > SLOW_NEWTON;
        let Some(interval) = point.accept(sys, &course, &step, t1, slow, &mut stats) else {
            // A stage matrix of the sensitivities is singular at this step: it is rejected for a
            // shorter one.
            stats.rejected_steps += 1;
            if fixed {
                outcome = Outcome::StepTooSmall { t };
                break;
            }
            h = 0.25 * h_step;
            continue;
        };
        if let Err(o) = super::store(&mut intervals, interval, t1) {
            outcome = o;
            break;
        }
        if !fixed {
            h = h_step * (0.9 * step.err.max(1e-10).powf(-1.0 / 3.0)).clamp(0.2, 5.0);
        }
        if stop.is_some_and(|f| f(point.t, &point.y)) {
            outcome = Outcome::Stopped { t: point.t };
            break;
        }
        if course.passed_break(point.t) {
            point.piece = course.piece(point.t);
            point.evaluate(sys, &mut stats);
        }
    }
    Trajectory { start: (t0, y_start), intervals, outcome, stats }
}

/// The driver's state at its current point.
struct Point {
    t: f64,
    /// A time inside the current smooth piece of `f` ([`Course::piece`]).
    piece: f64,
    y: Vec<f64>,
    /// `f(t, y)`.
    f: Vec<f64>,
    /// `J̃` of the Newton matrix, taken `jac_age` accepted steps ago.
    jac: Box<dyn Linearization>,
    jac_age: usize,
    /// `S = ∂y/∂p` and `Ṡ`, when sensitivities are asked for.
    s: Option<DMatrix<f64>>,
    s_dot: Option<DMatrix<f64>>,
}

impl Point {
    fn start(
        sys: &dyn OdeSystem,
        course: &Course<'_>,
        t0: f64,
        y0: &[f64],
        s: Option<DMatrix<f64>>,
        stats: &mut Stats,
    ) -> Self {
        let mut y = y0.to_vec();
        sys.project(&mut y);
        let piece = course.piece(t0);
        let (f, jac, s_dot) = evaluate(sys, t0, piece, &y, &s, stats);
        Self { t: t0, piece, y, f, jac, jac_age: 0, s, s_dot }
    }

    /// `f`, a fresh `J̃` and `Ṡ` at the current point.
    fn evaluate(&mut self, sys: &dyn OdeSystem, stats: &mut Stats) {
        (self.f, self.jac, self.s_dot) = evaluate(sys, self.t, self.piece, &self.y, &self.s, stats);
        self.jac_age = 0;
    }

    /// Moves to the accepted step's end `t1`: its sensitivities, the projection, `f` (with a fresh
    /// `J̃` when Newton was slow or the Jacobian old). Returns the step's dense-output interval, or
    /// `None`, with the point unchanged, where the step's sensitivities cannot be formed (a
    /// singular stage matrix).
    fn accept(
        &mut self,
        sys: &dyn OdeSystem,
        course: &Course<'_>,
        step: &Attempt,
        t1: f64,
        slow: bool,
        stats: &mut Stats,
    ) -> Option<Interval> {
        let mut y1 = step.y1.clone();
        let start_sens = self.s.clone().zip(self.s_dot.clone());
        if let (Some(s0), Some(sd0)) = (self.s.as_mut(), self.s_dot.as_ref()) {
            *s0 = step_sensitivities(sys, (self.t, t1), self.piece, step, &y1, s0, sd0, stats)?;
        }
        course.project(&mut y1, self.s.as_mut(), stats);
        let t0 = std::mem::replace(&mut self.t, t1);
        let y0 = std::mem::replace(&mut self.y, y1);
        let f0 = if slow || self.jac_age + 1 >= JACOBIAN_AGE {
            let f0 = std::mem::take(&mut self.f);
            self.evaluate(sys, stats);
            f0
        } else {
            self.jac_age += 1;
            stats.rhs_evaluations += 1;
            self.s_dot = self.s.as_ref().map(|s| super::sensitivity_rate(sys, t1, self.piece, &self.y, s));
            std::mem::replace(&mut self.f, sys.rhs(t1, self.piece, &self.y))
        };
        let end_sens = self.s.clone().zip(self.s_dot.clone());
        stats.accepted_steps += 1;
        Some(Interval::accepted((t0, y0, f0), (t1, self.y.clone(), self.f.clone()), (start_sens, end_sens), None))
    }
}

/// `f`, `J̃` and `Ṡ = J S + ∂f/∂p` at `(t, y)`.
fn evaluate(
    sys: &dyn OdeSystem,
    t: f64,
    piece: f64,
    y: &[f64],
    s: &Option<DMatrix<f64>>,
    stats: &mut Stats,
) -> (Vec<f64>, Box<dyn Linearization>, Option<DMatrix<f64>>) {
    let f = sys.rhs(t, piece, y);
    let jac = sys.linearize(t, piece, y);
    stats.rhs_evaluations += 1;
    stats.jacobian_evaluations += 1;
    let s_dot = s.as_ref().map(|s| super::sensitivity_rate(sys, t, piece, y, s));
    (f, jac, s_dot)
}
