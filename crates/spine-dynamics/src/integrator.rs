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

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// A first-order system `ẏ = f(t, y; p)`.
pub trait OdeSystem {
    /// Length of `y`.
    fn dim(&self) -> usize;
    /// `f(t, y)`. `piece` is a time inside the current smooth piece (see [`OdeSystem::breakpoints`]).
    fn rhs(&self, t: f64, piece: f64, y: &[f64]) -> Vec<f64>;
    /// `∂f/∂y`, `dim × dim`.
    fn jacobian(&self, t: f64, piece: f64, y: &[f64]) -> DMatrix<f64>;
    /// Number of parameters `p` whose sensitivities can be propagated.
    fn n_params(&self) -> usize {
        0
    }
    /// `∂f/∂p`, `dim × n_params`.
    fn rhs_params(&self, _t: f64, _piece: f64, _y: &[f64]) -> DMatrix<f64> {
        DMatrix::zeros(self.dim(), 0)
    }
    /// Moves `y` onto the invariant manifold (default: nothing).
    fn project(&self, _y: &mut [f64]) {}
    /// `S ← (∂ project / ∂y) S` at the unprojected `y` (default: identity).
    fn project_sensitivities(&self, _y: &[f64], _s: &mut DMatrix<f64>) {}
    /// Instants in `(t0, t1)` where `f` is discontinuous in `t`, increasing.
    fn breakpoints(&self, _t0: f64, _t1: f64) -> Vec<f64> {
        Vec::new()
    }
}

/// Integrator settings.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Options {
    /// Relative tolerance (default 1e-6).
    pub rtol: f64,
    /// Absolute tolerance, in the units of each component (rad, rad/s; default 1e-8).
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

impl Default for Options {
    fn default() -> Self {
        Self { rtol: 1e-6, atol: 1e-8, initial_step: None, max_step: None, max_steps: 200_000, newton_tolerance: 1e-3 }
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
    /// The caller's stop condition held at `t`.
    Stopped {
        t: f64,
    },
}

/// One accepted step: the data of its cubic Hermite interpolant.
#[derive(Clone, Debug)]
pub struct Interval {
    pub t0: f64,
    pub t1: f64,
    pub y0: Vec<f64>,
    pub y1: Vec<f64>,
    pub f0: Vec<f64>,
    pub f1: Vec<f64>,
    /// Sensitivities and their time derivatives at both ends (when requested).
    pub sens: Option<[DMatrix<f64>; 4]>,
}

/// Hermite basis `(h00, h10, h01, h11)` and derivatives at `s ∈ [0, 1]` of an interval of length `h`.
fn hermite(s: f64, h: f64) -> ([f64; 4], [f64; 4]) {
    let (s2, s3) = (s * s, s * s * s);
    (
        [2.0 * s3 - 3.0 * s2 + 1.0, (s3 - 2.0 * s2 + s) * h, -2.0 * s3 + 3.0 * s2, (s3 - s2) * h],
        [(6.0 * s2 - 6.0 * s) / h, 3.0 * s2 - 4.0 * s + 1.0, (-6.0 * s2 + 6.0 * s) / h, 3.0 * s2 - 2.0 * s],
    )
}

impl Interval {
    fn weights(&self, t: f64) -> ([f64; 4], [f64; 4]) {
        let h = self.t1 - self.t0;
        hermite(((t - self.t0) / h).clamp(0.0, 1.0), h)
    }

    /// `y(t)` on this interval.
    pub fn value(&self, t: f64) -> Vec<f64> {
        let (b, _) = self.weights(t);
        (0..self.y0.len())
            .map(|i| b[0] * self.y0[i] + b[1] * self.f0[i] + b[2] * self.y1[i] + b[3] * self.f1[i])
            .collect()
    }

    /// `ẏ(t)` of the interpolant.
    pub fn derivative(&self, t: f64) -> Vec<f64> {
        let (_, d) = self.weights(t);
        (0..self.y0.len())
            .map(|i| d[0] * self.y0[i] + d[1] * self.f0[i] + d[2] * self.y1[i] + d[3] * self.f1[i])
            .collect()
    }

    /// `S(t) = ∂y(t)/∂p` on this interval.
    pub fn sensitivity(&self, t: f64) -> Option<DMatrix<f64>> {
        let (b, _) = self.weights(t);
        self.sens.as_ref().map(|[s0, sd0, s1, sd1]| s0 * b[0] + sd0 * b[1] + s1 * b[2] + sd1 * b[3])
    }
}

/// A computed solution.
#[derive(Clone, Debug)]
pub struct Trajectory {
    pub intervals: Vec<Interval>,
    pub outcome: Outcome,
    pub stats: Stats,
}

/// A located event: the first time `g(y(t))` reaches zero.
#[derive(Clone, Debug)]
pub struct Event {
    pub t: f64,
    pub y: Vec<f64>,
    /// `dt/dp` of the event time, when sensitivities were propagated.
    pub t_sensitivity: Option<Vec<f64>>,
}

impl Trajectory {
    /// Start and end times.
    pub fn span(&self) -> (f64, f64) {
        (self.intervals.first().map_or(0.0, |i| i.t0), self.intervals.last().map_or(0.0, |i| i.t1))
    }

    fn interval_at(&self, t: f64) -> &Interval {
        let k = self.intervals.partition_point(|iv| iv.t1 < t);
        &self.intervals[k.min(self.intervals.len() - 1)]
    }

    /// `y(t)` from the dense output.
    pub fn value(&self, t: f64) -> Vec<f64> {
        self.interval_at(t).value(t)
    }

    /// The accepted step points `(t, y)`, the start included.
    pub fn points(&self) -> impl Iterator<Item = (f64, &[f64])> {
        let first = self.intervals.first().map(|iv| (iv.t0, iv.y0.as_slice()));
        first.into_iter().chain(self.intervals.iter().map(|iv| (iv.t1, iv.y1.as_slice())))
    }

    /// The first time after `after` where the scalar event function `g(y)` changes sign from its
    /// sign at `after`, located on the dense output to round-off (bisection refined by the secant
    /// rule). Each step is scanned at `SCAN` sub-points so that a crossing and return inside one step
    /// is not missed. With sensitivities, also `dt/dp = −(∇g · S) / (∇g · ẏ)` at the root, `∇g` from
    /// `grad`.
    pub fn first_root(
        &self,
        after: f64,
        g: &dyn Fn(&[f64]) -> f64,
        grad: &dyn Fn(&[f64]) -> Vec<f64>,
    ) -> Option<Event> {
        const SCAN: usize = 8;
        let start = self.value(after);
        let sign0 = if g(&start) < 0.0 { -1.0 } else { 1.0 };
        for iv in self.intervals.iter().filter(|iv| iv.t1 > after) {
            let lo0 = iv.t0.max(after);
            let mut prev = lo0;
            for k in 1..=SCAN {
                let t = lo0 + (iv.t1 - lo0) * k as f64 / SCAN as f64;
                if g(&iv.value(t)) * sign0 <= 0.0 {
                    let root = refine(prev, t, &|s| g(&iv.value(s)) * sign0);
                    let y = iv.value(root);
                    let t_sensitivity = iv.sensitivity(root).map(|s| {
                        let dg = grad(&y);
                        let rate: f64 = dg.iter().zip(iv.derivative(root)).map(|(a, b)| a * b).sum();
                        (0..s.ncols()).map(|p| -(0..s.nrows()).map(|i| dg[i] * s[(i, p)]).sum::<f64>() / rate).collect()
                    });
                    return Some(Event { t: root, y, t_sensitivity });
                }
                prev = t;
            }
        }
        None
    }
}

/// Root of `f` in `[a, b]` with `f(a) > 0 ≥ f(b)`: Illinois (regula falsi) iterations.
fn refine(mut a: f64, mut b: f64, f: &dyn Fn(f64) -> f64) -> f64 {
    let (mut fa, mut fb) = (f(a), f(b));
    let mut side = 0;
    for _ in 0..200 {
        if fb == 0.0 || (b - a).abs() <= 4.0 * f64::EPSILON * b.abs().max(1e-300) {
            break;
        }
        let c = (a * fb - b * fa) / (fb - fa);
        let c = if c > a.min(b) && c < a.max(b) { c } else { 0.5 * (a + b) };
        let fc = f(c);
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    b
}

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

fn weighted_rms(v: &[f64], y0: &[f64], y1: &[f64], o: &Options) -> f64 {
    let n = v.len().max(1);
    let s: f64 = (0..v.len())
        .map(|i| {
            let scale = o.atol + o.rtol * y0[i].abs().max(y1[i].abs());
            (v[i] / scale).powi(2)
        })
        .sum();
    (s / n as f64).sqrt()
}

/// A tried step: the new point, the stage, and the weighted error estimate.
struct Attempt {
    z2: Vec<f64>,
    y1: Vec<f64>,
    err: f64,
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
    lu: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>,
    opts: &Options,
    stats: &mut Stats,
) -> Option<Attempt> {
    let n = y.len();
    let solve = |rhs: Vec<f64>| -> Vec<f64> {
        lu.solve(&DVector::from_vec(rhs)).map(|v| v.as_slice().to_vec()).unwrap_or_else(|| vec![f64::NAN; n])
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
        let mut y1 = step.y1;
        let start_sens = s.clone().zip(s_dot.clone());
        if let (Some(s0), Some(sd0)) = (s.as_mut(), s_dot.as_ref()) {
            let t2 = t + GAMMA * h_step;
            let j2 = sys.jacobian(t2, piece, &step.z2);
            let p2 = sys.rhs_params(t2, piece, &step.z2);
            let w2 = (DMatrix::<f64>::identity(n, n) - &j2 * (h_step * D)).lu();
            let s2 = w2.solve(&(&*s0 + (sd0 + &p2) * (h_step * D))).expect("stage matrix is regular");
            let j3 = sys.jacobian(t1, piece, &y1);
            let p3 = sys.rhs_params(t1, piece, &y1);
            let w3 = (DMatrix::<f64>::identity(n, n) - &j3 * (h_step * D)).lu();
            let rhs = &*s0 + (sd0 * W + (&j2 * &s2 + &p2) * W + &p3 * D) * h_step;
            let mut s1 = w3.solve(&rhs).expect("stage matrix is regular");
            stats.jacobian_evaluations += 2;
            stats.factorizations += 2;
            sys.project_sensitivities(&y1, &mut s1);
            *s0 = s1;
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
    Trajectory { intervals, outcome, stats }
}
