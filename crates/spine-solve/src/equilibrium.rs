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
use crate::linalg::BorderedLu;
use crate::problem::StaticProblem;
use crate::stability::{self, Stability};
use serde::{Deserialize, Serialize};
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::kinematics::end_x;
use spine_model::residual::equilibrium_residual;
use spine_model::sparse::BorderedTridiagonal;
use spine_model::{Design, LinkLoads, State};
use std::time::Instant;

/// Options of Newton and of the load continuation. Mirrored by a case file's `solver` section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContinuationOptions {
    /// Newton stops when `max |r_i|` is at most this: joint rows in N·m, the constraint row in m.
    /// Where this is below the rounding floor of the residual (`32 ε` times the largest sum of
    /// absolute terms of a row, e.g. stiff springs of 10⁷ N·m/rad) that floor is used instead and
    /// reported as `tolerance_used`.
    pub residual_tolerance: f64,
    /// Newton iterations allowed per continuation step.
    pub max_newton_iterations: usize,
    /// First load step (fraction of the full load, `0 < step ≤ 1`).
    pub initial_step: f64,
    /// Smallest load step before the path is declared stuck.
    pub min_step: f64,
    /// Accepted continuation steps allowed.
    pub max_steps: usize,
    /// Largest change of any link angle in one step, rad: keeps the path from jumping branches.
    pub max_angle_step: f64,
    /// Width of the load-factor bracket when locating a loss of stability or a fold.
    pub critical_load_tolerance: f64,
}

/// A setting outside its allowed range: the field and what is allowed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct OptionError {
    /// The field's name (as in a case file's `solver` object).
    pub field: &'static str,
    pub message: String,
}

impl ContinuationOptions {
    /// Checks every setting against the range where the solver is meaningful and finishes:
    /// `residual_tolerance` in [1e-300, 1] (below the rounding floor the floor is used),
    /// `critical_load_tolerance` in [1e-15, 0.1], `max_angle_step` in (0, π/2],
    /// `1e-15 ≤ min_step ≤ initial_step ≤ 1`, 1 … 1000 Newton iterations, 1 … 10⁷ steps.
    pub fn validate(&self) -> Result<(), OptionError> {
        let err = |field, message: String| Err(OptionError { field, message });
        let within = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        if !within(self.residual_tolerance, 1e-300, 1.0) {
            return err("residual_tolerance", format!("must be in [1e-300, 1], got {}", self.residual_tolerance));
        }
        if !(self.max_angle_step > 0.0 && self.max_angle_step <= std::f64::consts::FRAC_PI_2) {
            return err("max_angle_step", format!("must be in (0, π/2] rad, got {}", self.max_angle_step));
        }
        if !within(self.critical_load_tolerance, 1e-15, 0.1) {
            let v = self.critical_load_tolerance;
            return err("critical_load_tolerance", format!("must be in [1e-15, 0.1], got {v}"));
        }
        if !(self.initial_step > 0.0 && self.initial_step <= 1.0) {
            return err("initial_step", format!("must be in (0, 1], got {}", self.initial_step));
        }
        if !(self.min_step >= 1e-15 && self.min_step <= self.initial_step) {
            return err("min_step", format!("must be in [1e-15, initial_step], got {}", self.min_step));
        }
        if !(1..=MAX_NEWTON_ITERATIONS).contains(&self.max_newton_iterations) {
            let v = self.max_newton_iterations;
            return err("max_newton_iterations", format!("must be between 1 and {MAX_NEWTON_ITERATIONS}, got {v}"));
        }
        if !(1..=MAX_CONTINUATION_STEPS).contains(&self.max_steps) {
            return err("max_steps", format!("must be between 1 and {MAX_CONTINUATION_STEPS}, got {}", self.max_steps));
        }
        Ok(())
    }
}

/// Most Newton iterations per continuation step a case may ask for.
pub const MAX_NEWTON_ITERATIONS: usize = 1000;
/// Most continuation steps a case may ask for.
pub const MAX_CONTINUATION_STEPS: usize = 10_000_000;

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            residual_tolerance: 1e-10,
            max_newton_iterations: 12,
            initial_step: 1.0,
            min_step: 1e-6,
            max_steps: 10_000,
            max_angle_step: 0.1,
            critical_load_tolerance: 1e-9,
        }
    }
}

/// How a path ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EquilibriumStatus {
    /// Full load reached; the path and the final equilibrium are stable.
    Stable,
    /// Full load reached, but the path lost stability at `critical_load_factor` (bifurcation): the
    /// returned equilibrium is unstable and not what the structure would do.
    Unstable { critical_load_factor: f64 },
    /// The path cannot pass `load_factor`: a fold (limit point, snap-through), located to
    /// `critical_load_tolerance`. The returned state is the last stable equilibrium traced before
    /// it (its own load factor is the solution's `load_factor`).
    LimitPoint { load_factor: f64 },
    /// Newton failed and the step could not be reduced further, away from any detected fold.
    NewtonFailed { load_factor: f64 },
    /// `max_steps` continuation steps were used up at `load_factor`.
    StepLimit { load_factor: f64 },
    /// The run's wall-clock limit passed (`spine_stop`) at `load_factor`.
    TimeLimit { load_factor: f64 },
    /// A stop was requested from outside (Ctrl-C) at `load_factor`.
    Interrupted { load_factor: f64 },
}

impl EquilibriumStatus {
    /// Full load reached and the equilibrium is stable: the only status a design may rely on.
    pub fn is_stable(&self) -> bool {
        matches!(self, Self::Stable)
    }

    /// One line for people.
    pub fn describe(&self) -> String {
        match *self {
            Self::Stable => "converged, stable".into(),
            Self::Unstable { critical_load_factor } => format!(
                "converged at full load but UNSTABLE: stability lost at {:.6} of the load (buckling)",
                critical_load_factor
            ),
            Self::LimitPoint { load_factor } => {
                format!("NOT converged: limit point (snap-through) at {load_factor:.6} of the load")
            }
            Self::NewtonFailed { load_factor } => {
                format!("NOT converged: Newton failed at {load_factor:.6} of the load")
            }
            Self::StepLimit { load_factor } => {
                format!("NOT converged: continuation step limit at {load_factor:.6} of the load")
            }
            Self::TimeLimit { load_factor } => {
                format!("NOT converged: the time limit passed at {load_factor:.6} of the load")
            }
            Self::Interrupted { load_factor } => format!("NOT converged: interrupted at {load_factor:.6} of the load"),
        }
    }
}

/// Work done by one path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SolveStats {
    pub continuation_steps: usize,
    pub rejected_steps: usize,
    pub newton_iterations: usize,
    /// Factorisations that needed the general sparse LU instead of the `O(N)` block elimination.
    pub general_factorisations: usize,
    pub factorisations: usize,
    /// Wall time, s.
    pub time_seconds: f64,
}

/// An equilibrium found along a load path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EquilibriumSolution {
    pub state: State,
    /// Fraction of the load reached (1 when the path completed).
    pub load_factor: f64,
    /// `max_i |r_i|` over the joint rows, N·m.
    pub residual_norm: f64,
    /// `|Φ(θ)|`, m.
    pub constraint_violation: f64,
    /// The convergence threshold Newton used at the returned state (see `residual_tolerance`).
    pub tolerance_used: f64,
    pub stability: Stability,
    pub status: EquilibriumStatus,
    pub stats: SolveStats,
}

/// A load path: the design, the start state (an equilibrium under `from`) and the two loads.
#[derive(Clone, Debug)]
pub struct LoadPath<'a> {
    pub spans: &'a [f64],
    pub design: &'a Design,
    pub from: LinkLoads,
    pub to: LinkLoads,
    pub start: State,
}

/// A converged Newton solve: the state, its residual and Jacobian, and the iterations it took.
#[derive(Clone)]
pub(crate) struct Converged {
    pub(crate) state: State,
    pub(crate) residual: Vec<f64>,
    pub(crate) jac: BorderedTridiagonal,
    pub(crate) iterations: usize,
}

/// Rounding floor of the residual at `state`: `32 ε` times the largest sum of absolute terms of a
/// joint row (springs `(K_i + K_{i+1}) (|θ| + |θ0|)`, loads `L_i (|V_i| + |A_i| + |λ|)`), N·m.
pub(crate) fn rounding_floor(path: &LoadPath<'_>, loads: &LinkLoads, state: &State) -> f64 {
    let d = path.design;
    let mut scale: f64 = 0.0;
    for i in 0..path.spans.len() {
        let springs = (d.stiffness[i] + d.stiffness[i + 1]) * (state.theta[i].abs() + d.theta0[i].abs() + 1.0);
        let length = path.spans[i] / d.theta0[i].cos();
        let forces = length * (loads.vertical[i].abs() + loads.axial[i].abs() + state.lambda.abs());
        scale = scale.max(springs + forces);
    }
    32.0 * f64::EPSILON * scale
}

pub(crate) fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Newton's method on `(θ, λ)` at fixed load from `start`.
pub(crate) fn newton(
    path: &LoadPath<'_>,
    loads: &LinkLoads,
    start: State,
    opts: &ContinuationOptions,
    stats: &mut SolveStats,
) -> Option<Converged> {
    let mut state = start;
    let mut first_norm = None;
    for it in 0..=opts.max_newton_iterations {
        let (residual, jac) = residual_and_state_jacobian(path.spans, path.design, loads, &state);
        let norm = max_abs(&residual);
        if !norm.is_finite() {
            return None;
        }
        let tolerance = opts.residual_tolerance.max(rounding_floor(path, loads, &state));
        if norm <= tolerance {
            return Some(Converged { state, residual, jac, iterations: it });
        }
        let first = *first_norm.get_or_insert(norm);
        if it == opts.max_newton_iterations || norm > 1e6 * first.max(opts.residual_tolerance) {
            return None;
        }
        let lu = factor(&jac, stats)?;
        let step = lu.solve(&residual);
        stats.newton_iterations += 1;
        let n = state.theta.len();
        for (t, d) in state.theta.iter_mut().zip(&step) {
            *t -= d;
        }
        state.lambda -= step[n];
    }
    None
}

pub(crate) fn factor(jac: &BorderedTridiagonal, stats: &mut SolveStats) -> Option<BorderedLu> {
    let lu = BorderedLu::factor(jac).ok()?;
    stats.factorisations += 1;
    if !lu.is_block() {
        stats.general_factorisations += 1;
    }
    Some(lu)
}

/// `∂r/∂s` at `state`: the residual is affine in the loads, which are linear in `s`.
pub(crate) fn load_derivative(path: &LoadPath<'_>, state: &State) -> Vec<f64> {
    let r_to = equilibrium_residual(path.spans, path.design, &path.to, state);
    let r_from = equilibrium_residual(path.spans, path.design, &path.from, state);
    r_to.iter().zip(&r_from).map(|(a, b)| a - b).collect()
}

/// Whether a corrector ended on the branch its predictor pointed at: the correction (largest
/// angle change from the predicted state) is at most half the step's move, or below
/// [`BRANCH_FLOOR`]. A predictor is accurate to second order in the step, so on the path this
/// holds for small enough steps; Newton converging onto another branch fails it.
pub(crate) fn on_branch(from: &State, predicted: &State, converged: &State) -> bool {
    angle_change(converged, predicted) <= 0.5 * angle_change(converged, from) + BRANCH_FLOOR
}

/// A loss of stability is accepted only where the smallest projected eigenvalue at the last stable
/// point of its bracket is below this fraction of its value at the start or before the step.
const CROSSING_EIGENVALUE: f64 = 1e-4;

/// Steps of at most this many `min_step` are accepted without the branch-jump checks on the
/// inertia (a real double crossing must still be passable).
const TINY_STEPS: f64 = 16.0;

/// Corrections below this (rad) are never taken for a branch change.
pub(crate) const BRANCH_FLOOR: f64 = 1e-6;

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

pub(crate) fn angle_change(a: &State, b: &State) -> f64 {
    a.theta.iter().zip(&b.theta).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Follows `path` from `s = 0` to `s = 1`. See the module docs for the statuses.
pub fn solve_path(path: &LoadPath<'_>, opts: &ContinuationOptions) -> EquilibriumSolution {
    let clock = Instant::now();
    let mut stats = SolveStats::default();
    let finish = |cur: &Converged, s: f64, status: EquilibriumStatus, stability: Stability, mut stats: SolveStats| {
        let n = cur.state.theta.len();
        stats.time_seconds = clock.elapsed().as_secs_f64();
        let loads = LinkLoads::lerp(&path.from, &path.to, s);
        let tolerance_used = opts.residual_tolerance.max(rounding_floor(path, &loads, &cur.state));
        EquilibriumSolution {
            state: cur.state.clone(),
            load_factor: s,
            residual_norm: max_abs(&cur.residual[..n]),
            constraint_violation: cur.residual[n].abs(),
            tolerance_used,
            stability,
            status,
            stats,
        }
    };

    let Some(mut cur) = newton(path, &path.from, path.start.clone(), opts, &mut stats) else {
        let (residual, jac) = residual_and_state_jacobian(path.spans, path.design, &path.from, &path.start);
        let start = Converged { state: path.start.clone(), residual, jac, iterations: 0 };
        let stability = stability::certify(&start.jac);
        return finish(&start, 0.0, EquilibriumStatus::NewtonFailed { load_factor: 0.0 }, stability, stats);
    };
    let start_stability = stability::certify(&cur.jac);
    let mut critical = (start_stability.negative_directions > 0).then_some(0.0);
    let mut negative = start_stability.negative_directions;
    let mut s = 0.0;
    let mut ds = opts.initial_step.clamp(opts.min_step, 1.0);

    while s < 1.0 {
        if stats.continuation_steps >= opts.max_steps {
            let st = stability::certify(&cur.jac);
            return finish(&cur, s, EquilibriumStatus::StepLimit { load_factor: s }, st, stats);
        }
        if let Some(reason) = spine_stop::check() {
            let st = stability::certify(&cur.jac);
            let status = match reason {
                spine_stop::StopReason::TimeLimit => EquilibriumStatus::TimeLimit { load_factor: s },
                spine_stop::StopReason::Interrupted => EquilibriumStatus::Interrupted { load_factor: s },
            };
            return finish(&cur, s, status, st, stats);
        }
        let s_new = (s + ds).min(1.0);
        let loads = LinkLoads::lerp(&path.from, &path.to, s_new);
        let guess = predict(path, &cur, s_new - s, &mut stats);
        // Steps this small are no longer suspected of jumping branches.
        let tiny = ds <= TINY_STEPS * opts.min_step;
        let accepted = newton(path, &loads, guess.clone(), opts, &mut stats).and_then(|next| {
            let next_negative = stability::negative_directions(&next.jac);
            // A bifurcation or a fold changes the inertia by one; more in one step is a jump to
            // another branch (unless the step is already tiny).
            let inertia_ok = next_negative.abs_diff(negative) <= 1 || tiny;
            let ok = angle_change(&next.state, &cur.state) <= opts.max_angle_step
                && on_branch(&cur.state, &guess, &next.state)
                && inertia_ok;
            ok.then_some((next, next_negative))
        });
        match accepted {
            Some((next, next_negative)) => {
                if critical.is_none() && next_negative > 0 {
                    let (at, eigenvalue) = locate_critical(path, &cur, s, s_new, opts, &mut stats);
                    let scale = [start_stability.min_eigenvalue, stability::certify(&cur.jac).min_eigenvalue]
                        .into_iter()
                        .flatten()
                        .fold(0.0, f64::max);
                    if eigenvalue.is_some_and(|e| e > CROSSING_EIGENVALUE * scale) && !tiny {
                        // The path was still clearly stable next to the "crossing": the step
                        // jumped to an unstable equilibrium of another branch.
                        stats.rejected_steps += 1;
                        ds *= 0.5;
                        continue;
                    }
                    critical = Some(at);
                }
                let easy = next.iterations <= 3;
                cur = next;
                negative = next_negative;
                s = s_new;
                stats.continuation_steps += 1;
                if easy {
                    ds = (2.0 * ds).min(1.0);
                }
            }
            None => {
                stats.rejected_steps += 1;
                ds *= 0.5;
                if ds < opts.min_step {
                    // Load control stalls: a fold, or only a hard stretch of the path. Follow it
                    // in arclength to tell which.
                    match arclength::trace(path, cur.clone(), s, opts, &mut stats) {
                        Trace::Fold { last, s: s_last, fold } => {
                            let st = stability::certify(&last.jac);
                            return finish(
                                &last,
                                s_last,
                                EquilibriumStatus::LimitPoint { load_factor: fold },
                                st,
                                stats,
                            );
                        }
                        Trace::Full { point, inertia_grew } => {
                            if critical.is_none() {
                                critical = inertia_grew;
                            }
                            cur = point;
                            s = 1.0;
                        }
                        Trace::Stuck => {
                            let st = stability::certify(&cur.jac);
                            let status = match spine_stop::check() {
                                Some(spine_stop::StopReason::TimeLimit) => {
                                    EquilibriumStatus::TimeLimit { load_factor: s }
                                }
                                Some(spine_stop::StopReason::Interrupted) => {
                                    EquilibriumStatus::Interrupted { load_factor: s }
                                }
                                None if stats.continuation_steps >= opts.max_steps => {
                                    EquilibriumStatus::StepLimit { load_factor: s }
                                }
                                None => EquilibriumStatus::NewtonFailed { load_factor: s },
                            };
                            return finish(&cur, s, status, st, stats);
                        }
                    }
                }
            }
        }
    }
    let st = stability::certify(&cur.jac);
    let status = match (critical, st.stable) {
        (None, true) => EquilibriumStatus::Stable,
        (Some(c), _) => EquilibriumStatus::Unstable { critical_load_factor: c },
        (None, false) => EquilibriumStatus::Unstable { critical_load_factor: 1.0 },
    };
    finish(&cur, 1.0, status, st, stats)
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
