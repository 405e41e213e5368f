//! A load path and Newton's method on it: the corrector shared by load and arclength continuation.

use crate::linalg::BorderedLu;
use crate::options::ContinuationOptions;
use crate::solution::SolveStats;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::residual::equilibrium_residual;
use spine_model::sparse::BorderedTridiagonal;
use spine_model::{Design, LinkLoads, State};

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

pub(crate) fn angle_change(a: &State, b: &State) -> f64 {
    a.theta.iter().zip(&b.theta).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

/// Corrections below this (rad) are never taken for a branch change.
pub(crate) const BRANCH_FLOOR: f64 = 1e-6;
