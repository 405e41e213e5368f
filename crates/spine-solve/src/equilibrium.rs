//! Static equilibrium: Newton on `(θ, λ)` with load continuation and a stability check at every
//! accepted step.
//!
//! The load is ramped from `from` to `to` along `s ∈ [0, 1]` (`LinkLoads::lerp`). Each step predicts
//! with the path tangent `dx/ds = −J⁻¹ ∂r/∂s` and corrects with Newton. A step is accepted only when
//! it stays on the path: Newton converges within `max_newton_iterations`, no link turns by more
//! than `max_angle_step`, Newton's correction is at most half the step's move (a predictor is
//! second-order accurate on the path; converging onto another branch is not), and the number of
//! negative directions of the projected Hessian changes by at most one. Otherwise the step is
//! halved. The physically reached equilibrium is the one on this path.
//!
//! When that number becomes positive the load factor where stability was lost is located by
//! bisection to `critical_load_tolerance`; the smallest eigenvalue at the bracket's stable end must
//! then be near zero (it is continuous along a path), or the step is taken for a jump and halved.
//! The path is followed to the full load and reported as [`EquilibriumStatus::Unstable`] (the real
//! structure would have buckled there). When the steps shrink below `min_step` the path is
//! followed in arclength (`arclength`): if the load turns back it is a fold,
//! [`EquilibriumStatus::LimitPoint`] (snap-through), located to `critical_load_tolerance`; if the
//! path rises on to the full load, load control only stalled and the run goes on.

use crate::arclength::{self, Trace};
use crate::corrector::{
    angle_change, factor, load_derivative, max_abs, newton, on_branch, rounding_floor, Converged, LoadPath,
};
use crate::options::ContinuationOptions;
use crate::problem::StaticProblem;
use crate::solution::{EquilibriumSolution, EquilibriumStatus, SolveStats};
use crate::stability::{self, Stability};
use serde::Serialize;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::kinematics::end_x;
use spine_model::{LinkLoads, State};
use std::time::Instant;

/// A loss of stability is accepted only where the smallest projected eigenvalue at the last stable
/// point of its bracket is below this fraction of its value at the start or before the step.
const CROSSING_EIGENVALUE: f64 = 1e-4;

/// Steps of at most this many `min_step` are accepted without the branch-jump checks on the
/// inertia (a real double crossing must still be passable).
const TINY_STEPS: f64 = 16.0;

/// Euler predictor along the path tangent `dx/ds = −J⁻¹ ∂r/∂s` from the converged point `cur`.
fn predict(path: &LoadPath<'_>, cur: &Converged, ds: f64, stats: &mut SolveStats) -> State {
    let dr_ds = load_derivative(path, &cur.state);
    let mut next = cur.state.clone();
    if let Some(lu) = factor(&cur.jac, stats) {
        let tangent = lu.solve(&dr_ds);
        let n = next.theta.len();
        if tangent.iter().all(|v| v.is_finite()) {
            for (t, d) in next.theta.iter_mut().zip(&tangent) {
                *t -= ds * d;
            }
            next.lambda -= ds * tangent[n];
        }
    }
    next
}

/// Follows `path` from `s = 0` to `s = 1`. See the module docs for the statuses.
pub fn solve_path(path: &LoadPath<'_>, opts: &ContinuationOptions) -> EquilibriumSolution {
    let clock = Instant::now();
    let mut stats = SolveStats::default();
    // The status may depend on the final point's stability (certified once, here).
    let finish = |cur: &Converged, s: f64, status: &dyn Fn(&Stability) -> EquilibriumStatus, mut stats: SolveStats| {
        let n = cur.state.theta.len();
        stats.time_seconds = clock.elapsed().as_secs_f64();
        let loads = LinkLoads::lerp(&path.from, &path.to, s);
        let tolerance_used = opts.residual_tolerance.max(rounding_floor(path, &loads, &cur.state));
        let stability = stability::certify(&cur.jac);
        EquilibriumSolution {
            state: cur.state.clone(),
            load_factor: s,
            residual_norm: max_abs(&cur.residual[..n]),
            constraint_violation: cur.residual[n].abs(),
            tolerance_used,
            status: status(&stability),
            stability,
            stats,
        }
    };

    let Some(cur) = newton(path, &path.from, path.start.clone(), opts, &mut stats) else {
        let (residual, jac) = residual_and_state_jacobian(path.spans, path.design, &path.from, &path.start);
        let start = Converged { state: path.start.clone(), residual, jac, iterations: 0 };
        return finish(&start, 0.0, &|_| EquilibriumStatus::NewtonFailed { load_factor: 0.0 }, stats);
    };
    let mut walk = Walk::new(cur, opts);
    while walk.s < 1.0 {
        let s = walk.s;
        if stats.continuation_steps >= opts.max_steps {
            return finish(&walk.cur, s, &|_| EquilibriumStatus::StepLimit { load_factor: s }, stats);
        }
        if let Some(reason) = spine_stop::check() {
            return finish(&walk.cur, s, &|_| stopped(reason, s), stats);
        }
        if walk.step(path, opts, &mut stats) {
            continue;
        }
        // Load control stalls: a fold, or only a hard stretch of the path. Follow it in
        // arclength to tell which.
        match arclength::trace(path, walk.cur.clone(), s, opts, &mut stats) {
            Trace::Fold { last, s: s_last, fold } => {
                return finish(&last, s_last, &|_| EquilibriumStatus::LimitPoint { load_factor: fold }, stats);
            }
            Trace::Full { point, inertia_grew } => {
                walk.critical = walk.critical.or(inertia_grew);
                walk.cur = point;
                walk.s = 1.0;
            }
            Trace::Stuck => {
                let status = match spine_stop::check() {
                    Some(reason) => stopped(reason, s),
                    None if stats.continuation_steps >= opts.max_steps => {
                        EquilibriumStatus::StepLimit { load_factor: s }
                    }
                    None => EquilibriumStatus::NewtonFailed { load_factor: s },
                };
                return finish(&walk.cur, s, &|_| status, stats);
            }
        }
    }
    let critical = walk.critical;
    let status = |st: &Stability| match (critical, st.stable) {
        (None, true) => EquilibriumStatus::Stable,
        (Some(c), _) => EquilibriumStatus::Unstable { critical_load_factor: c },
        (None, false) => EquilibriumStatus::Unstable { critical_load_factor: 1.0 },
    };
    finish(&walk.cur, 1.0, &status, stats)
}

/// The status of a run stopped at load factor `s`.
fn stopped(reason: spine_stop::StopReason, s: f64) -> EquilibriumStatus {
    match reason {
        spine_stop::StopReason::TimeLimit => EquilibriumStatus::TimeLimit { load_factor: s },
        spine_stop::StopReason::Interrupted => EquilibriumStatus::Interrupted { load_factor: s },
    }
}

/// Load control along the path: where it is and what it has seen.
struct Walk {
    /// The last accepted equilibrium, at load factor `s`.
    cur: Converged,
    s: f64,
    /// The next step in `s`.
    ds: f64,
    /// Where stability was lost, when it was.
    critical: Option<f64>,
    /// Negative directions of the projected Hessian at `cur`.
    negative: usize,
    /// The smallest projected eigenvalue at the start.
    start_eigenvalue: Option<f64>,
}

impl Walk {
    fn new(cur: Converged, opts: &ContinuationOptions) -> Self {
        let start = stability::certify(&cur.jac);
        Self {
            cur,
            s: 0.0,
            ds: opts.initial_step.clamp(opts.min_step, 1.0),
            critical: (start.negative_directions > 0).then_some(0.0),
            negative: start.negative_directions,
            start_eigenvalue: start.min_eigenvalue,
        }
    }

    /// One predictor–corrector step of `ds`, accepted only when it stays on the path (module
    /// docs), or halved. `false` when the step has fallen below `min_step`.
    fn step(&mut self, path: &LoadPath<'_>, opts: &ContinuationOptions, stats: &mut SolveStats) -> bool {
        let (s, cur) = (self.s, &self.cur);
        let s_new = (s + self.ds).min(1.0);
        let loads = LinkLoads::lerp(&path.from, &path.to, s_new);
        let guess = predict(path, cur, s_new - s, stats);
        // Steps this small are no longer suspected of jumping branches.
        let tiny = self.ds <= TINY_STEPS * opts.min_step;
        let accepted = newton(path, &loads, guess.clone(), opts, stats).and_then(|next| {
            let next_negative = stability::negative_directions(&next.jac);
            // A bifurcation or a fold changes the inertia by one; more in one step is a jump to
            // another branch (unless the step is already tiny).
            let inertia_ok = next_negative.abs_diff(self.negative) <= 1 || tiny;
            let ok = angle_change(&next.state, &cur.state) <= opts.max_angle_step
                && on_branch(&cur.state, &guess, &next.state)
                && inertia_ok;
            ok.then_some((next, next_negative))
        });
        let Some((next, next_negative)) = accepted else {
            stats.rejected_steps += 1;
            self.ds *= 0.5;
            return self.ds >= opts.min_step;
        };
        if self.critical.is_none() && next_negative > 0 {
            let (at, eigenvalue) = locate_critical(path, cur, s, s_new, opts, stats);
            let scale = [self.start_eigenvalue, stability::certify(&cur.jac).min_eigenvalue]
                .into_iter()
                .flatten()
                .fold(0.0, f64::max);
            if eigenvalue.is_some_and(|e| e > CROSSING_EIGENVALUE * scale) && !tiny {
                // The path was still clearly stable next to the "crossing": the step jumped to an
                // unstable equilibrium of another branch.
                stats.rejected_steps += 1;
                self.ds *= 0.5;
                return true;
            }
            self.critical = Some(at);
        }
        let easy = next.iterations <= 3;
        self.cur = next;
        self.negative = next_negative;
        self.s = s_new;
        stats.continuation_steps += 1;
        if easy {
            self.ds = (2.0 * self.ds).min(1.0);
        }
        true
    }
}

/// Bisection on the load factor between the stable point `stable` at `lo` and an unstable one at
/// `hi`, for where the projected Hessian first gets a negative direction. Returns the load factor
/// and the smallest projected eigenvalue at the last stable point of the bracket, which tends to
/// zero at a true loss of stability (the eigenvalue is continuous along a path) and stays away from
/// it when the unstable point was on another branch.
fn locate_critical(
    path: &LoadPath<'_>,
    stable: &Converged,
    mut lo: f64,
    mut hi: f64,
    opts: &ContinuationOptions,
    stats: &mut SolveStats,
) -> (f64, Option<f64>) {
    let mut anchor = stable.clone();
    while hi - lo > opts.critical_load_tolerance {
        let mid = 0.5 * (lo + hi);
        let loads = LinkLoads::lerp(&path.from, &path.to, mid);
        let guess = predict(path, &anchor, mid - lo, stats);
        match newton(path, &loads, guess.clone(), opts, stats) {
            Some(c) if stability::negative_directions(&c.jac) == 0 && on_branch(&anchor.state, &guess, &c.state) => {
                lo = mid;
                anchor = c;
            }
            _ => hi = mid,
        }
    }
    (0.5 * (lo + hi), stability::certify(&anchor.jac).min_eigenvalue)
}

/// The two load states of eq. (33): `θ1` under the passive load, `θ2` with the actuation added.
#[derive(Clone, Debug, Serialize)]
pub struct StaticSolution {
    /// Path from the unloaded design `θ0` to the passive load.
    pub passive: EquilibriumSolution,
    /// Path from `θ1` to passive plus actuation; `None` when the passive path did not reach its load.
    pub loaded: Option<EquilibriumSolution>,
    /// `X_{N+1}(θ1) − L_x`, m.
    pub passive_end_displacement: f64,
    /// `X_{N+1}(θ2) − L_x`, m (the `δ` of eq. (32)).
    pub end_displacement: Option<f64>,
}

/// Solves both load states of a design by continuation: `θ0 → θ1 → θ2`.
pub fn solve_static(problem: &StaticProblem, opts: &ContinuationOptions) -> StaticSolution {
    let spans = &problem.structure.chain.spans;
    let n = spans.len();
    let passive_loads = problem.passive_loads();
    let passive = solve_path(
        &LoadPath {
            spans,
            design: &problem.design,
            from: LinkLoads::zero(n),
            to: passive_loads.clone(),
            start: State::unloaded(&problem.design),
        },
        opts,
    );
    let lx = problem.structure.chain.length_x();
    let passive_end_displacement = end_x(spans, &problem.design.theta0, &passive.state.theta) - lx;
    let loaded = (passive.load_factor == 1.0).then(|| {
        solve_path(
            &LoadPath {
                spans,
                design: &problem.design,
                from: passive_loads,
                to: problem.total_loads(),
                start: passive.state.clone(),
            },
            opts,
        )
    });
    let end_displacement = loaded
        .as_ref()
        .filter(|l| l.load_factor == 1.0)
        .map(|l| end_x(spans, &problem.design.theta0, &l.state.theta) - lx);
    StaticSolution { passive, loaded, passive_end_displacement, end_displacement }
}
