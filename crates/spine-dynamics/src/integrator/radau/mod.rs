//! Radau IIA of order 5 ([`super::Method::Radau5`]; Hairer & Wanner, *Solving ODEs II*, IV.8, the
//! method of RADAU5 and of scipy's `Radau`): the collocation stages, their simplified Newton
//! iterations, the error estimate, the forward sensitivities and the driver.
//!
//! **Stages.** `Z_i = h Σ_j a_ij f(t + c_j h, y + Z_j)` at the Radau points `c = ((4 − √6)/10,
//! (4 + √6)/10, 1)`; `y₁ = y + Z₃` (stiffly accurate, order 5 at the step's end, stage order 3).
//! With `A⁻¹ = T Λ T⁻¹` (one real eigenvalue `μ` and a complex pair `α ± iβ`), the simplified Newton
//! iteration in `W = T⁻¹ Z` needs one real matrix `μ/h I − J̃` and one complex `(α − iβ)/h I − J̃`,
//! each factored once per step size ([`super::linear`]); its rate is watched and the iteration given
//! up when the predicted error after the remaining iterations exceeds the tolerance.
//!
//! **Error.** `err = (μ/h I − J̃)⁻¹ (f(y) + Σ e_i Z_i / h)` (third-order embedded estimate, filtered so
//! that stiff components do not force tiny steps; refiltered through `f(y + err)` after a
//! rejection), on the weighted RMS norm; steps follow Gustafsson's predictive controller with
//! exponent 1/4, the safety factor shrinking with the Newton iterations.
//!
//! **Sensitivities.** `S = ∂y/∂p` by internal differentiation: the stage sensitivities solve the
//! linear collocation system `dZ_i = h Σ_j a_ij (J(Y_j) (S₀ + dZ_j) + ∂f/∂p(Y_j))` at the converged
//! stage points `Y_j` (exact `J v` products, [`OdeSystem::jacobian_times`]), by the same transformed
//! iteration to round-off; `S₁ = S₀ + dZ₃`, then the projection's derivative.
//!
//! Modules: [`stages`] (constants, Newton matrices, the collocation iteration, the polynomial and
//! the step-size prediction), [`sensitivities`] (the step's forward sensitivities); this file is
//! the driver.

pub(super) mod adjoint;
mod sensitivities;
mod stages;

use super::dense::{Interval, Trajectory};
use super::options::{Options, Outcome, Stats};
use super::{sensitivity_rate, weighted_rms, Course, Extras};
use crate::linearization::Linearization;
use crate::ode::OdeSystem;
use nalgebra::DMatrix;
use sensitivities::step_sensitivities;
use stages::{
    carried_contraction, collocation, factor, newton_tol, predict_factor, Collocation, Factors, Orientation,
    Polynomial, Stages, Workspace,
};
use stages::{C, E, NEWTON_MAXITER};

/// The Radau IIA driver.
pub(super) fn integrate(
    sys: &dyn OdeSystem,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    opts: &Options,
    extras: Extras<'_>,
) -> Trajectory {
    let Extras { sensitivities, steps, stop } = extras;
    let columns = sensitivities.as_ref().map_or(0, |s| s.ncols());
    let mut course = Course::new(sys, (t0, t_end), steps, opts, columns);
    let mut run = Run::start(sys, opts, &course, t0, y0, sensitivities);
    let y_start = run.y.clone();
    let h_max = opts.max_step.unwrap_or(f64::INFINITY);
    let mut intervals = Vec::new();
    let mut outcome = Outcome::Completed;
    while run.t < t_end {
        if let Some(o) = course.must_stop(run.t, &run.stats) {
            outcome = o;
            break;
        }
        if run.h > h_max {
            run.h = h_max;
            run.last = None;
        }
        let step = match run.attempt(&mut course) {
            Ok(step) => step,
            Err(o) => {
                outcome = o;
                break;
            }
        };
        let t1 = step.t1;
        if let Err(o) = super::store(&mut intervals, run.accept(step, &course), t1) {
            outcome = o;
            break;
        }
        if stop.is_some_and(|g| g(run.t, &run.y)) {
            outcome = Outcome::Stopped { t: run.t };
            break;
        }
        if course.passed_break(run.t) {
            run.enter_piece(&course);
        }
    }
    Trajectory { start: (t0, y_start), intervals, outcome, stats: run.stats }
}

/// A step that passed the error test.
struct Accepted {
    t1: f64,
    col: Collocation,
    err: f64,
    /// The safety factor of the step-size prediction (it shrinks with the Newton iterations).
    safety: f64,
}

/// The driver's state between steps.
struct Run<'a> {
    sys: &'a dyn OdeSystem,
    opts: &'a Options,
    /// The Newton tolerance ([`newton_tol`]).
    tol: f64,
    stats: Stats,
    t: f64,
    y: Vec<f64>,
    /// `f(t, y)`.
    f: Vec<f64>,
    /// A time inside the current smooth piece of `f` ([`Course::piece`]).
    piece: f64,
    /// The Jacobian `J̃` of the Newton matrices, and whether it was taken at `(t, y)`.
    lin: Box<dyn Linearization>,
    current: bool,
    /// `S = ∂y/∂p` and `Ṡ`, when sensitivities are asked for.
    s: Option<DMatrix<f64>>,
    s_dot: Option<DMatrix<f64>>,
    factors: Option<Factors>,
    /// The last accepted step's collocation polynomial (the next stages' guess).
    polynomial: Option<Polynomial>,
    /// The next step to try.
    h: f64,
    /// `(h, err)` of the last accepted step, for the predictive controller.
    last: Option<(f64, f64)>,
    /// The Newton iteration's contraction factor `Θ/(1 − Θ)` carried from step to step
    /// ([`stages::carried_contraction`]); 1 at the start and after a breakpoint.
    contraction: f64,
    /// The collocation iteration's vectors, kept from step to step.
    work: Workspace,
}

impl<'a> Run<'a> {
    fn start(
        sys: &'a dyn OdeSystem,
        opts: &'a Options,
        course: &Course<'_>,
        t0: f64,
        y0: &[f64],
        s: Option<DMatrix<f64>>,
    ) -> Self {
        let mut stats = Stats::default();
        let mut y = y0.to_vec();
        sys.project(&mut y);
        let piece = course.piece(t0);
        let mut f = vec![0.0; y.len()];
        sys.rhs_into(t0, piece, &y, &mut f);
        stats.rhs_evaluations += 1;
        let lin = sys.linearize(t0, piece, &y);
        stats.jacobian_evaluations += 1;
        let s_dot = s.as_ref().map(|s| sensitivity_rate(sys, t0, piece, &y, s));
        Self {
            sys,
            opts,
            tol: newton_tol(opts),
            stats,
            t: t0,
            y,
            f,
            piece,
            lin,
            current: true,
            s,
            s_dot,
            factors: None,
            polynomial: None,
            h: course.initial_step(opts),
            last: None,
            contraction: 1.0,
            work: Workspace::default(),
        }
    }

    /// `J̃` at `(t, y)`.
    fn relinearize(&mut self) {
        self.lin = self.sys.linearize(self.t, self.piece, &self.y);
        self.stats.jacobian_evaluations += 1;
        self.current = true;
    }

    /// Steps from `t` until one passes the error test: a failed Newton iteration takes a fresh
    /// linearisation, then a smaller step; a failed error test a smaller step. `Err` when the step
    /// gets too small.
    fn attempt(&mut self, course: &mut Course<'_>) -> Result<Accepted, Outcome> {
        let mut rejected = false;
        loop {
            let next = course.next_step(self.t, self.h)?;
            let (t1, fixed) = (next.t1, next.fixed);
            let h_step = t1 - self.t;
            if self.factors.as_ref().is_none_or(|fa| fa.h != h_step) {
                self.factors = factor(self.lin.as_ref(), h_step, &mut self.stats);
            }
            // A singular Newton matrix or a failed iteration: a fresh linearisation, then a
            // smaller step.
            let Some(col) = self.stages(h_step) else {
                self.factors = None;
                if !self.current {
                    self.relinearize();
                } else if fixed {
                    return Err(Outcome::StepTooSmall { t: self.t });
                } else {
                    self.h = 0.5 * h_step;
                }
                continue;
            };
            let err = self.error(&col, h_step, rejected);
            let safety = 0.9 * (2 * NEWTON_MAXITER + 1) as f64 / (2 * NEWTON_MAXITER + col.iterations) as f64;
            if !fixed && err > 1.0 {
                self.stats.rejected_steps += 1;
                rejected = true;
                self.h = h_step * (safety * predict_factor(h_step, self.last, err)).max(0.2);
                continue;
            }
            return Ok(Accepted { t1, col, err, safety });
        }
    }

    /// The stages of a step of `h_step` from `(t, y)`, from the last polynomial's guess; `None`
    /// without factors or when the iteration fails.
    fn stages(&mut self, h_step: f64) -> Option<Collocation> {
        let Self { sys, opts, tol, stats, t, y, piece, factors, polynomial, contraction, work, .. } = self;
        let fa = factors.as_ref()?;
        let n = y.len();
        let (t, piece) = (*t, *piece);
        let guess: Stages = match polynomial {
            Some(p) => std::array::from_fn(|i| p.value_minus(t + C[i] * h_step, y)),
            None => std::array::from_fn(|_| vec![0.0; n]),
        };
        let scale: Vec<f64> = y.iter().map(|v| opts.atol + opts.rtol * v.abs()).collect();
        let norm = |dw: &Stages| {
            let sum: f64 = dw.iter().map(|d| d.iter().zip(&scale).map(|(a, s)| (a / s).powi(2)).sum::<f64>()).sum();
            (sum / (3 * n.max(1)) as f64).sqrt()
        };
        let mut yi = vec![0.0; n];
        let mut stage = |i: usize, zi: &[f64], fi: &mut [f64]| {
            for (v, (&a, &b)) in yi.iter_mut().zip(y.iter().zip(zi)) {
                *v = a + b;
            }
            stats.rhs_evaluations += 1;
            stats.newton_iterations += usize::from(i == 0);
            sys.rhs_into(t + C[i] * h_step, piece, &yi, fi);
        };
        let carried = carried_contraction(*contraction);
        let col = collocation(Orientation::Stages, &mut stage, guess, fa, &norm, *tol, carried, NEWTON_MAXITER, work);
        stats.newton_failures += usize::from(col.is_none());
        if let Some(col) = &col {
            *contraction = col.contraction(carried);
        }
        col
    }

    /// The weighted error of the converged stages `col` (infinite when not finite):
    /// `(μ/h I − J̃)⁻¹ (f(y) + Σ e_i Z_i / h)`, refiltered through `f(y + err)` after a rejection.
    fn error(&mut self, col: &Collocation, h_step: f64, rejected: bool) -> f64 {
        let n = self.y.len();
        let (y, opts) = (&self.y, self.opts);
        // Invariant: the stages converged with the factors of this step, which `factors` keeps until
        // the step is accepted or rejected.
        let fa = self.factors.as_ref().expect("converged stages have their factors");
        let y_new: Vec<f64> = (0..n).map(|j| y[j] + col.z[2][j]).collect();
        let ze: Vec<f64> = (0..n).map(|j| (0..3).map(|i| E[i] * col.z[i][j]).sum::<f64>() / h_step).collect();
        let mut error: Vec<f64> = (0..n).map(|j| self.f[j] + ze[j]).collect();
        fa.real.solve(&mut error);
        let mut err = weighted_rms(&error, y, &y_new, opts);
        if rejected && err > 1.0 {
            let shifted: Vec<f64> = (0..n).map(|j| y[j] + error[j]).collect();
            let mut fs = vec![0.0; n];
            self.sys.rhs_into(self.t, self.piece, &shifted, &mut fs);
            self.stats.rhs_evaluations += 1;
            error = (0..n).map(|j| fs[j] + ze[j]).collect();
            fa.real.solve(&mut error);
            err = weighted_rms(&error, y, &y_new, opts);
        }
        if err.is_finite() {
            err
        } else {
            f64::INFINITY
        }
    }

    /// Takes an accepted step: the sensitivities, the projection, the dense-output interval, the
    /// next step size and, when the Newton iteration was slow, a fresh linearisation.
    fn accept(&mut self, step: Accepted, course: &Course<'_>) -> Interval {
        let Accepted { t1, col, err, safety } = step;
        let (sys, n, t, piece) = (self.sys, self.y.len(), self.t, self.piece);
        let h_step = t1 - t;
        // Invariant: only a step whose stages converged (with these factors) is accepted.
        let fa = self.factors.as_ref().expect("an accepted step has its factors");
        let mut y1: Vec<f64> = (0..n).map(|j| self.y[j] + col.z[2][j]).collect();
        let start_sens = self.s.clone().zip(self.s_dot.clone());
        if let (Some(s0), Some(sd0)) = (self.s.as_mut(), self.s_dot.as_ref()) {
            *s0 = step_sensitivities(sys, t, piece, &self.y, &col.z, fa, s0, sd0, &mut self.stats);
        }
        self.polynomial = Some(Polynomial::new(t, h_step, &self.y, &col.z));
        course.project(&mut y1, self.s.as_mut(), &mut self.stats);
        let mut f1 = vec![0.0; n];
        sys.rhs_into(t1, piece, &y1, &mut f1);
        self.stats.rhs_evaluations += 1;
        let s_dot1 = self.s.as_ref().map(|s| sensitivity_rate(sys, t1, piece, &y1, s));
        let end_sens = self.s.clone().zip(s_dot1.clone());
        let collocation = self.polynomial.as_ref().map(|p| p.q.clone());
        // The step's start moves into the interval; its end stays as the next step's start.
        let (y0, f0) = (std::mem::replace(&mut self.y, y1.clone()), std::mem::replace(&mut self.f, f1.clone()));
        let interval = Interval::accepted((t, y0, f0), (t1, y1, f1), (start_sens, end_sens), collocation);
        self.stats.accepted_steps += 1;
        let refresh = col.iterations > 2 && col.rate.is_some_and(|r| r > 1e-3);
        let factor = (safety * predict_factor(h_step, self.last, err)).min(10.0);
        self.last = Some((h_step, err));
        self.h = if refresh || factor >= 1.2 { h_step * factor } else { h_step };
        self.t = t1;
        self.s_dot = s_dot1;
        self.current = false;
        if refresh {
            self.relinearize();
            self.factors = None;
        }
        interval
    }

    /// At a breakpoint of the forcing: `f` and `J̃` of the new piece, and no history.
    fn enter_piece(&mut self, course: &Course<'_>) {
        self.piece = course.piece(self.t);
        self.sys.rhs_into(self.t, self.piece, &self.y, &mut self.f);
        self.stats.rhs_evaluations += 1;
        self.relinearize();
        self.factors = None;
        self.polynomial = None;
        self.last = None;
        self.contraction = 1.0;
        self.s_dot = self.s.as_ref().map(|s| sensitivity_rate(self.sys, self.t, self.piece, &self.y, s));
    }
}
