//! The derivative of the optimum for one active set (one solve with the factorised reduced KKT
//! matrix), in the paper's quantities, and the one-sided derivatives where bounds are weakly
//! active.

use super::rates::Rates;
use super::{Derivative, Optimum};
use crate::layout::{LoadState, StateForm};
use crate::optimality::active_set::{ActiveSet, Bound, Side};
use crate::optimality::point::Evaluation;
use crate::optimality::system::{
    bound_rate, hessian_times, jacobian_times, jacobian_transpose_times, with_weak, ActiveSystem, Matrices, ReducedKkt,
};

/// One active set's solution for one parameter: the derivative, the full `dx`, the rates `dz` of
/// the stationarity residual (the bound multipliers' rates), `dg` of every row's value and `dλ`,
/// and the first dependent row (left out of the system) whose linearised constraint it breaks.
pub(crate) struct Solution {
    pub derivative: Derivative,
    dx: Vec<f64>,
    dz: Vec<f64>,
    dg: Vec<f64>,
    dlambda: Vec<f64>,
    pub broken_row: Option<usize>,
}

/// The derivative for the active set of `system`, whose factorisation is `Some`. With `one_sided`
/// the solution also carries the rates of the bound multipliers (`dz`) that a one-sided choice is
/// checked with; the rows' rates (`dg`) are formed where they are checked (dependent rows, or
/// `one_sided`).
pub(crate) fn derivative(
    optimum: &Optimum<'_>,
    matrices: &Matrices,
    system: &ActiveSystem,
    rates: &Rates,
    at: &Evaluation,
    one_sided: bool,
) -> Option<Solution> {
    let kkt = system.kkt.as_ref()?;
    let (n, m) = (optimum.layout.num_variables(), optimum.layout.num_constraints());
    let (mut dx, mut rhs) = right_hand_side(kkt, &system.variables, matrices, rates);
    // A failed solve leaves the right-hand side; the factorisation succeeded, so it does not fail.
    let _ = kkt.solve(&mut rhs);
    for i in 0..n {
        if let Some(p) = kkt.free_position[i] {
            dx[i] = rhs[p];
        }
    }
    // The multipliers' rates are checked only by a one-sided choice.
    let dlambda: Vec<f64> = if one_sided {
        let mut dlambda = vec![0.0; m];
        for (k, b) in kkt.rows.iter().enumerate() {
            dlambda[b.index] = rhs[kkt.free + k];
        }
        dlambda
    } else {
        Vec::new()
    };
    let dz: Vec<f64> = if one_sided {
        let h_dx = hessian_times(&matrices.hessian_pattern, &matrices.hessian, &dx);
        let jt_dl = jacobian_transpose_times(&matrices.jacobian_pattern, &matrices.jacobian, &dlambda, n);
        (0..n).map(|i| h_dx[i] + jt_dl[i] + rates.lagrangian_gradient[i]).collect()
    } else {
        Vec::new()
    };
    let dg: Vec<f64> = if one_sided || !system.dependent.is_empty() {
        let j_dx = jacobian_times(&matrices.jacobian_pattern, &matrices.jacobian, &dx, m);
        (0..m).map(|r| j_dx[r] + rates.constraints[r]).collect()
    } else {
        Vec::new()
    };
    let derivative = report(optimum, &system.variables, &kkt.rows, rates, at, &dx);
    let broken_row = if dg.is_empty() { None } else { dependent_row_broken(system, rates, &dg) };
    Some(Solution { derivative, dx, dz, dg, dlambda, broken_row })
}

/// The linearised KKT conditions' right-hand side for one parameter on the reduced system `kkt`
/// (free variables first, then the active rows), with `dx` holding the moves of the variables
/// fixed by the bounds in `variables` (zero elsewhere).
pub(crate) fn right_hand_side(
    kkt: &ReducedKkt,
    variables: &[Bound],
    matrices: &Matrices,
    rates: &Rates,
) -> (Vec<f64>, Vec<f64>) {
    let (n, m) = (rates.lagrangian_gradient.len(), rates.constraints.len());
    let mut dx = vec![0.0; n];
    for b in variables {
        dx[b.index] = bound_rate(b, rates.lower[b.index], rates.upper[b.index]);
    }
    // Most parameters move no active variable bound: then `H dx` and `J dx` are zero.
    let fixed_move = dx.iter().any(|&d| d != 0.0);
    let moved = fixed_move.then(|| {
        (
            hessian_times(&matrices.hessian_pattern, &matrices.hessian, &dx),
            jacobian_times(&matrices.jacobian_pattern, &matrices.jacobian, &dx, m),
        )
    });
    let h_dx = |i: usize| moved.as_ref().map_or(0.0, |(h, _)| h[i]);
    let j_dx = |r: usize| moved.as_ref().map_or(0.0, |(_, j)| j[r]);
    let mut rhs = vec![0.0; kkt.free + kkt.rows.len()];
    for i in 0..n {
        if let Some(p) = kkt.free_position[i] {
            rhs[p] = -(rates.lagrangian_gradient[i] + h_dx(i));
        }
    }
    for (k, b) in kkt.rows.iter().enumerate() {
        let r = b.index;
        rhs[kkt.free + k] = bound_rate(b, rates.row_lower[r], rates.row_upper[r]) - rates.constraints[r] - j_dx(r);
    }
    (dx, rhs)
}

/// The derivative in the paper's quantities, and `dJ*/dp` both ways.
fn report(
    optimum: &Optimum<'_>,
    variables: &[Bound],
    rows: &[Bound],
    rates: &Rates,
    at: &Evaluation,
    dx: &[f64],
) -> Derivative {
    let layout = optimum.layout;
    let (x, ck) = (optimum.x, optimum.problem.stiffness_scale);
    let multipliers = optimum.multipliers;
    let n = layout.n;
    let deflection = layout.states == StateForm::Deflection;
    let state = |s: LoadState| -> Vec<f64> {
        (0..n).map(|i| dx[layout.state_angle(s, i)] + if deflection { dx[layout.theta0(i)] } else { 0.0 }).collect()
    };
    let mut envelope = rates.objective;
    for b in rows {
        let r = b.index;
        let bound = bound_rate(b, rates.row_lower[r], rates.row_upper[r]);
        envelope += multipliers.constraints[r] * (rates.constraints[r] - bound);
    }
    for b in variables {
        let i = b.index;
        envelope += match b.side {
            Side::Lower => multipliers.z_lower[i] * rates.lower[i],
            Side::Upper => -multipliers.z_upper[i] * rates.upper[i],
            Side::Both => multipliers.z_lower[i] * rates.lower[i] - multipliers.z_upper[i] * rates.upper[i],
        };
    }
    let direct = rates.objective + at.gradient.iter().zip(dx).map(|(g, d)| g * d).sum::<f64>();
    Derivative {
        theta0: (0..n).map(|i| dx[layout.theta0(i)]).collect(),
        stiffness: (0..=n)
            .map(|j| ck * dx[layout.stiffness(j)] + x[layout.stiffness(j)] * rates.stiffness_scale)
            .collect(),
        theta1: state(LoadState::Passive),
        theta2: state(LoadState::Loaded),
        lambda1: dx[layout.lambda(LoadState::Passive)],
        lambda2: dx[layout.lambda(LoadState::Loaded)],
        objective: envelope,
        objective_direct: direct,
    }
}

/// The first dependent active row (left out of the system) whose linearised constraint the
/// derivative breaks (by more than 1e-8 of the largest rate), or `None`: then the derivative holds
/// for them too. `dg` holds the rates of every row's value.
fn dependent_row_broken(system: &ActiveSystem, rates: &Rates, dg: &[f64]) -> Option<usize> {
    let scale = dg.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    system
        .rows
        .iter()
        .filter(|b| system.dependent.contains(&b.index))
        .find(|b| {
            (dg[b.index] - bound_rate(b, rates.row_lower[b.index], rates.row_upper[b.index])).abs() > 1e-8 * scale
        })
        .map(|b| b.index)
}

/// The weakly active bounds of an active set (with whether each bounds a variable) and, for every
/// choice of those taken as active (bit `k` of the mask for the `k`-th), the system of that active
/// set where its factorisation certifies a strict local minimum. Built once for all parameters and
/// both directions.
pub(crate) struct WeakCandidates {
    weak: Vec<(Bound, bool)>,
    systems: Vec<(u32, ActiveSystem)>,
}

/// The [`WeakCandidates`] of `set`.
pub(crate) fn weak_candidates(optimum: &Optimum<'_>, matrices: &Matrices, set: &ActiveSet) -> WeakCandidates {
    let weak: Vec<(Bound, bool)> =
        set.weak_variables.iter().map(|b| (*b, true)).chain(set.weak_rows.iter().map(|b| (*b, false))).collect();
    // Most weak bounds kept active first: where the QP of the degenerate set is strictly convex,
    // one choice is consistent and the order does not matter; where a weak bound bounds a flat
    // direction (a spring in a flat valley of `J`), both keeping it and releasing it can be
    // consistent, and the first choice is the one that changes the active set least (what a
    // re-solve at `p ± h` does: it stays on the bound).
    let mut masks: Vec<u32> = (0u32..(1 << weak.len())).collect();
    masks.sort_by_key(|m| std::cmp::Reverse(m.count_ones()));
    let systems = masks
        .into_iter()
        .filter_map(|mask| {
            let chosen = |variable: bool| -> Vec<Bound> {
                weak.iter()
                    .enumerate()
                    .filter(|(k, (_, v))| *v == variable && mask & (1 << k) != 0)
                    .map(|(_, (b, _))| *b)
                    .collect()
            };
            let (variables, rows) = with_weak(set, &chosen(true), &chosen(false));
            // Fixing a weak bound can make more rows dependent: they leave the system too.
            let system = ActiveSystem::new(matrices, optimum.layout, variables, rows);
            system.certified().is_some().then_some((mask, system))
        })
        .collect();
    WeakCandidates { weak, systems }
}

/// The one-sided derivative for an increase (`direction` 1) or a decrease (−1) of the parameter:
/// the first candidate ([`weak_candidates`]) whose solution keeps every weak bound feasible (an
/// inactive one is not crossed, an active one's multiplier does not change sign) and whose
/// dependent rows can follow.
pub(crate) fn one_sided(
    optimum: &Optimum<'_>,
    matrices: &Matrices,
    WeakCandidates { weak, systems }: &WeakCandidates,
    rates: &Rates,
    at: &Evaluation,
    direction: f64,
) -> Option<Derivative> {
    systems.iter().find_map(|(mask, system)| {
        let s = derivative(optimum, matrices, system, rates, at, true)?;
        if s.broken_row.is_some() {
            return None;
        }
        let scale = s.dx.iter().fold(1.0f64, |m, v| m.max(v.abs())) * 1e-9;
        let feasible = weak.iter().enumerate().all(|(k, (b, variable))| {
            let active = mask & (1 << k) != 0;
            let i = b.index;
            let sign = if b.side == Side::Upper { -1.0 } else { 1.0 };
            let change = match (active, variable) {
                // An active bound's multiplier must not change sign: z_L = ∂L/∂x_i, z_U = −∂L/∂x_i.
                (true, true) => sign * s.dz[i],
                // A row's multiplier is positive at its upper bound, negative at its lower bound.
                (true, false) => -sign * s.dlambda[i],
                // An inactive bound must not be crossed.
                (false, true) => sign * (s.dx[i] - bound_rate(b, rates.lower[i], rates.upper[i])),
                (false, false) => sign * (s.dg[i] - bound_rate(b, rates.row_lower[i], rates.row_upper[i])),
            };
            direction * change >= -scale
        });
        feasible.then_some(s.derivative)
    })
}
