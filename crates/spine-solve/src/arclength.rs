//! Pseudo-arclength continuation where load control stalls.
//!
//! Load control (`equilibrium`) steps in the load factor `s`; at a fold of the path `dθ/ds` blows
//! up and its steps shrink to nothing. Here the path is followed in its arclength `σ` instead:
//! the unknowns are `(θ, λ, s)`, the extra equation fixes the step along the unit tangent
//! `t = (t_θ, t_s)` (`λ` is carried along but not measured: it is in N, the rest in rad and load
//! fraction), and the bordered Newton matrix `[J ∂r/∂s; t_θᵀ 0 t_s]` stays regular through the
//! fold. The trace tells a fold (the load component `t_s` of the tangent changes sign) from a
//! stall of load control only (the path goes on to the full load), and locates a fold's load
//! factor by bisection on the sign of `t_s`: near the fold `s(σ) ≈ s* − c (σ − σ*)²`, so a
//! bracket of width `w` in `σ` gives `s*` to `c w²`, far below `critical_load_tolerance`.

use crate::corrector::{
    angle_change, factor, load_derivative, max_abs, newton, on_branch, rounding_floor, Converged, LoadPath,
};
use crate::options::ContinuationOptions;
use crate::solution::SolveStats;
use crate::stability;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::{LinkLoads, State};

/// How a trace from a stalled point ended.
pub(crate) enum Trace {
    /// The path turns back at load factor `fold`. `last` is the last point of the trace before
    /// the fold's bracket (on the rising, stable side), at load factor `s`.
    Fold { last: Converged, s: f64, fold: f64 },
    /// The path reaches the full load: `point` is the equilibrium at `s = 1`; `inertia_grew` is
    /// the load factor where the projected Hessian gained a negative direction on the way, if it
    /// did.
    Full { point: Converged, inertia_grew: Option<f64> },
    /// The arclength corrector failed too, or the step budget ran out.
    Stuck,
}

/// A point of the path with its unit tangent (θ and λ parts, and the load part).
struct ArcPoint {
    point: Converged,
    s: f64,
    tangent: Vec<f64>,
    tangent_s: f64,
}

/// Smallest arclength step before the trace gives up.
const MIN_ARC_STEP: f64 = 1e-12;
/// The fold's bracket in `σ` is halved until it is this fraction of the step that found it.
const FOLD_BRACKET: f64 = 1e-9;

/// Unit tangent at `c` (load factor `s`): `(−J⁻¹ ∂r/∂s, 1)` normalised over `θ` and `s`, oriented
/// along `previous` (or toward increasing load without one).
fn tangent(
    path: &LoadPath<'_>,
    c: &Converged,
    previous: Option<(&[f64], f64)>,
    stats: &mut SolveStats,
) -> Option<(Vec<f64>, f64)> {
    let n = c.state.theta.len();
    let lu = factor(&c.jac, stats)?;
    let mut t: Vec<f64> = lu.solve(&load_derivative(path, &c.state)).iter().map(|v| -v).collect();
    let norm = (t[..n].iter().map(|v| v * v).sum::<f64>() + 1.0).sqrt();
    if !norm.is_finite() {
        return None;
    }
    t.iter_mut().for_each(|v| *v /= norm);
    let mut t_s = 1.0 / norm;
    if let Some((p, p_s)) = previous {
        let dot: f64 = t[..n].iter().zip(&p[..n]).map(|(a, b)| a * b).sum::<f64>() + t_s * p_s;
        if dot < 0.0 {
            t.iter_mut().for_each(|v| *v = -*v);
            t_s = -t_s;
        }
    }
    Some((t, t_s))
}

/// The corrector: Newton on `r(θ, λ; s) = 0` and `t_θ·(θ − θ_p) + t_s (s − s_p) = 0` from the
/// prediction `p + h t`. Returns the converged point, its load factor and the prediction.
fn correct(
    path: &LoadPath<'_>,
    from: &ArcPoint,
    h: f64,
    opts: &ContinuationOptions,
    stats: &mut SolveStats,
) -> Option<(Converged, f64, State)> {
    let n = from.point.state.theta.len();
    let mut state = from.point.state.clone();
    for (x, t) in state.theta.iter_mut().zip(&from.tangent) {
        *x += h * t;
    }
    state.lambda += h * from.tangent[n];
    let predicted = state.clone();
    let s_predicted = from.s + h * from.tangent_s;
    let mut s = s_predicted;
    for it in 0..=opts.max_newton_iterations {
        let loads = LinkLoads::lerp(&path.from, &path.to, s);
        let (residual, jac) = residual_and_state_jacobian(path.spans, path.design, &loads, &state);
        let norm = max_abs(&residual);
        if !norm.is_finite() {
            return None;
        }
        if norm <= opts.residual_tolerance.max(rounding_floor(path, &loads, &state)) {
            return Some((Converged { state, residual, jac, iterations: it }, s, predicted));
        }
        if it == opts.max_newton_iterations {
            return None;
        }
        let g: f64 =
            state.theta.iter().zip(&predicted.theta).zip(&from.tangent).map(|((x, p), t)| t * (x - p)).sum::<f64>()
                + from.tangent_s * (s - s_predicted);
        let lu = factor(&jac, stats)?;
        let y1 = lu.solve(&residual);
        let y2 = lu.solve(&load_derivative(path, &state));
        let dot = |y: &[f64]| y[..n].iter().zip(&from.tangent).map(|(a, b)| a * b).sum::<f64>();
        let ds = (g - dot(&y1)) / (from.tangent_s - dot(&y2));
        if !ds.is_finite() {
            return None;
        }
        stats.newton_iterations += 1;
        for (i, x) in state.theta.iter_mut().enumerate() {
            *x -= y1[i] - ds * y2[i];
        }
        state.lambda -= y1[n] - ds * y2[n];
        s -= ds;
    }
    None
}

/// Follows the path from `start` (an equilibrium at load factor `s0` where load control stalled)
/// in arclength. See the module docs.
pub(crate) fn trace(
    path: &LoadPath<'_>,
    start: Converged,
    s0: f64,
    opts: &ContinuationOptions,
    stats: &mut SolveStats,
) -> Trace {
    let Some((t, t_s)) = tangent(path, &start, None, stats) else { return Trace::Stuck };
    let mut negative = stability::negative_directions(&start.jac);
    let mut p = ArcPoint { point: start, s: s0, tangent: t, tangent_s: t_s };
    let mut inertia_grew = None;
    let mut h = 0.25 * opts.max_angle_step;
    while stats.continuation_steps < opts.max_steps {
        if spine_stop::check().is_some() {
            // The caller reports the stop (time limit or interrupt) at its last point.
            return Trace::Stuck;
        }
        let step = correct(path, &p, h, opts, stats).filter(|(q, _, predicted)| {
            angle_change(&q.state, &p.point.state) <= opts.max_angle_step
                && on_branch(&p.point.state, predicted, &q.state)
        });
        let Some((q, s_q, _)) = step else {
            stats.rejected_steps += 1;
            h *= 0.5;
            if h < MIN_ARC_STEP {
                return Trace::Stuck;
            }
            continue;
        };
        let Some((t_q, t_q_s)) = tangent(path, &q, Some((&p.tangent, p.tangent_s)), stats) else {
            h *= 0.5;
            continue;
        };
        if t_q_s < 0.0 {
            // The load turned back between p and q: bracket the fold in σ.
            let (mut lo, mut hi) = (0.0, h);
            let mut fold = p.s.max(s_q);
            while hi - lo > FOLD_BRACKET * h {
                let mid = 0.5 * (lo + hi);
                let Some((r, s_r, _)) = correct(path, &p, mid, opts, stats) else { break };
                let Some((_, t_r_s)) = tangent(path, &r, Some((&p.tangent, p.tangent_s)), stats) else { break };
                fold = fold.max(s_r);
                if t_r_s > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Trace::Fold { s: p.s, last: p.point, fold };
        }
        if s_q >= 1.0 {
            // Past the full load on the rising side: the equilibrium at s = 1 by load control.
            let loads = LinkLoads::lerp(&path.from, &path.to, 1.0);
            match newton(path, &loads, q.state.clone(), opts, stats) {
                Some(point) if angle_change(&point.state, &q.state) <= opts.max_angle_step => {
                    if inertia_grew.is_none() && stability::negative_directions(&point.jac) > negative {
                        inertia_grew = Some(1.0);
                    }
                    return Trace::Full { point, inertia_grew };
                }
                _ => {
                    h *= 0.5;
                    continue;
                }
            }
        }
        stats.continuation_steps += 1;
        let q_negative = stability::negative_directions(&q.jac);
        if inertia_grew.is_none() && q_negative > negative {
            inertia_grew = Some(s_q);
        }
        negative = q_negative;
        if q.iterations <= 3 {
            h = (1.5 * h).min(opts.max_angle_step);
        }
        p = ArcPoint { point: q, s: s_q, tangent: t_q, tangent_s: t_q_s };
    }
    Trace::Stuck
}
