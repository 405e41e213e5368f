//! The derivative of the optimum for one active set (one solve with the factorised reduced KKT
//! matrix), in the paper's quantities, and the one-sided derivatives where bounds are weakly
//! active.

use super::active_set::{ActiveSet, Bound, Side};
use super::point::Evaluation;
use super::rates::Rates;
use super::system::{bound_rate, hessian_times, jacobian_times, jacobian_transpose_times, licq, with_weak, ReducedKkt};
use super::{factorise, Derivative, Matrices, Optimum};
use crate::full_space::{LoadState, StateForm};

/// The derivative for one active set, and the full `dx` and the stationarity residual rates
/// (`dz` of the bound multipliers, `dg` of the rows) the one-sided checks need.
pub(crate) fn derivative(
    optimum: &Optimum<'_>,
    matrices: &Matrices,
    variables: &[Bound],
    kkt: &ReducedKkt,
    rates: &Rates,
    at: &Evaluation,
) -> (Derivative, Vec<f64>, Vec<f64>, Vec<f64>) {
    let (n, m) = (optimum.layout.num_variables(), optimum.layout.num_constraints());
    let mut dx = vec![0.0; n];
    for b in variables {
        dx[b.index] = bound_rate(b, rates.lower[b.index], rates.upper[b.index]);
    }
    let h_dx = hessian_times(&matrices.hessian_pattern, &matrices.hessian, &dx);
    let j_dx = jacobian_times(&matrices.jacobian_pattern, &matrices.jacobian, &dx, m);
    let mut rhs = vec![0.0; kkt.free + kkt.rows.len()];
    for i in 0..n {
        if let Some(p) = kkt.free_position[i] {
            rhs[p] = -(rates.lagrangian_gradient[i] + h_dx[i]);
        }
    }
    for (k, &r) in kkt.rows.iter().enumerate() {
        let side = kkt_row_side(at, r, optimum.multipliers.constraints[r]);
        let target = match side {
            Side::Upper => rates.row_upper[r],
            _ => rates.row_lower[r],
        };
        rhs[kkt.free + k] = target - rates.constraints[r] - j_dx[r];
    }
    // A failed solve leaves the right-hand side; the factorisation succeeded, so it does not fail.
    let _ = kkt.solve(&mut rhs);
    let mut dlambda = vec![0.0; m];
    for i in 0..n {
        if let Some(p) = kkt.free_position[i] {
            dx[i] = rhs[p];
        }
    }
    for (k, &r) in kkt.rows.iter().enumerate() {
        dlambda[r] = rhs[kkt.free + k];
    }
    // Rates of the stationarity residual (the bound multipliers' rates) and of the rows.
    let h_dx = hessian_times(&matrices.hessian_pattern, &matrices.hessian, &dx);
    let jt_dl = jacobian_transpose_times(&matrices.jacobian_pattern, &matrices.jacobian, &dlambda, n);
    let dz: Vec<f64> = (0..n).map(|i| h_dx[i] + jt_dl[i] + rates.lagrangian_gradient[i]).collect();
    let j_dx = jacobian_times(&matrices.jacobian_pattern, &matrices.jacobian, &dx, m);
    let dg: Vec<f64> = (0..m).map(|r| j_dx[r] + rates.constraints[r]).collect();
    let report = report(optimum, variables, &kkt.rows, rates, at, &dx);
    (report, dx, dz, dg.into_iter().chain(dlambda).collect())
}

/// The side of an active row: an equality, or the bound its multiplier points to.
pub(crate) fn kkt_row_side(at: &Evaluation, r: usize, lambda: f64) -> Side {
    if at.row_lower[r] == at.row_upper[r] {
        Side::Both
    } else if lambda > 0.0 {
        Side::Upper
    } else {
        Side::Lower
    }
}

/// The derivative in the paper's quantities, and `dJ*/dp` both ways.
fn report(
    optimum: &Optimum<'_>,
    variables: &[Bound],
    rows: &[usize],
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
    for &r in rows {
        let side = kkt_row_side(at, r, multipliers.constraints[r]);
        let bound = if side == Side::Upper { rates.row_upper[r] } else { rates.row_lower[r] };
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

/// The one-sided derivative for an increase (`direction` 1) or a decrease (−1) of the parameter:
/// the first choice of active weak bounds whose solution keeps every weak bound feasible (an
/// inactive one is not crossed, an active one's multiplier does not change sign).
pub(crate) fn one_sided(
    optimum: &Optimum<'_>,
    matrices: &Matrices,
    set: &ActiveSet,
    rates: &Rates,
    at: &Evaluation,
    direction: f64,
) -> Option<Derivative> {
    let weak: Vec<(Bound, bool)> =
        set.weak_variables.iter().map(|b| (*b, true)).chain(set.weak_rows.iter().map(|b| (*b, false))).collect();
    for mask in 0u32..(1 << weak.len()) {
        let chosen = |variable: bool| -> Vec<Bound> {
            weak.iter()
                .enumerate()
                .filter(|(k, (_, v))| *v == variable && mask & (1 << k) != 0)
                .map(|(_, (b, _))| *b)
                .collect()
        };
        let (variables, mut rows) = with_weak(set, &chosen(true), &chosen(false));
        // Fixing a weak bound can make more rows dependent: they leave the system too.
        let n = optimum.layout.num_variables();
        let all_rows = rows.clone();
        let dependent = licq(n, &variables, &rows, (&matrices.jacobian_pattern, &matrices.jacobian))
            .map(|(_, d)| d)
            .unwrap_or_default();
        rows.retain(|b| !dependent.contains(&b.index));
        let Some(kkt) = factorise(matrices, optimum.layout, &variables, &rows) else { continue };
        if !kkt.certifies_minimum() {
            continue;
        }
        let (result, dx, dz, dg_dl) = derivative(optimum, matrices, &variables, &kkt, rates, at);
        // A choice whose left-out rows cannot follow the parameter is not a solution.
        if dependent_rows_broken(optimum, &all_rows, &dependent, rates, at, &dg_dl).is_some() {
            continue;
        }
        let m = optimum.layout.num_constraints();
        let scale = dx.iter().fold(1.0f64, |s, v| s.max(v.abs())) * 1e-9;
        let feasible = weak.iter().enumerate().all(|(k, (b, variable))| {
            let active = mask & (1 << k) != 0;
            let i = b.index;
            let sign = if b.side == Side::Upper { -1.0 } else { 1.0 };
            let change = match (active, variable) {
                // An active bound's multiplier must not change sign: z_L = ∂L/∂x_i, z_U = −∂L/∂x_i.
                (true, true) => sign * dz[i],
                // A row's multiplier is positive at its upper bound, negative at its lower bound.
                (true, false) => -sign * dg_dl[m + i],
                // An inactive bound must not be crossed.
                (false, true) => sign * (dx[i] - bound_rate(b, rates.lower[i], rates.upper[i])),
                (false, false) => sign * (dg_dl[i] - bound_rate(b, rates.row_lower[i], rates.row_upper[i])),
            };
            direction * change >= -scale
        });
        if feasible {
            return Some(result);
        }
    }
    None
}

/// The first dependent active row (left out of the system) whose linearised constraint the
/// derivative breaks (by more than 1e-8 of the largest rate), or `None`: then the derivative holds
/// for them too. `dg` holds the rates of every row's value first.
pub(crate) fn dependent_rows_broken(
    optimum: &Optimum<'_>,
    rows: &[Bound],
    dependent: &[usize],
    rates: &Rates,
    at: &Evaluation,
    dg: &[f64],
) -> Option<usize> {
    let scale = dg.iter().fold(1.0f64, |m, v| m.max(v.abs()));
    rows.iter().filter(|b| dependent.contains(&b.index)).map(|b| b.index).find(|&r| {
        let target = match kkt_row_side(at, r, optimum.multipliers.constraints[r]) {
            Side::Upper => rates.row_upper[r],
            _ => rates.row_lower[r],
        };
        (dg[r] - target).abs() > 1e-8 * scale
    })
}
