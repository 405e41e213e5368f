//! The KKT system of eq. (33) at an optimum, reduced to the free variables and the active rows:
//! `[H_FF J_AFᵀ; J_AF 0]`, factorised once (with its inertia, which certifies second-order
//! sufficiency and, with no zero eigenvalue, the independence of the active rows), solved for
//! every parameter.

use super::active_set::{ActiveSet, Bound, Side};
use super::point::Evaluation;
use super::smallest_singular_value;
use crate::assembly::Assembled;
use crate::full_space::assemble;
use crate::layout::Layout;
use crate::problem::DesignProblem;
use spine_kkt::{Inertia, KktError, Structure, SymmetricSolver};
use std::collections::BTreeMap;

/// The Hessian of the Lagrangian (lower triangle) and the constraint Jacobian at the optimum, with
/// their patterns.
pub(crate) struct Matrices {
    pub hessian_pattern: Vec<(usize, usize)>,
    pub hessian: Vec<f64>,
    pub jacobian_pattern: Vec<(usize, usize)>,
    pub jacobian: Vec<f64>,
}

impl Matrices {
    /// The problem's NLP evaluated at `x` (layout order) and its Lagrangian's Hessian with the
    /// constraint multipliers `lambda` (objective factor 1): the evaluation and the matrices.
    pub fn at(problem: &DesignProblem, layout: Layout, x: &[f64], lambda: &[f64]) -> (Evaluation, Self) {
        Self::of(&assemble(problem, layout.states), problem, layout, x, lambda)
    }

    /// [`Matrices::at`] with the problem's elements already assembled.
    pub fn of(
        assembled: &Assembled,
        problem: &DesignProblem,
        layout: Layout,
        x: &[f64],
        lambda: &[f64],
    ) -> (Evaluation, Self) {
        let at = Evaluation::of(assembled, problem, layout, x);
        let mut hessian = vec![0.0; assembled.patterns.hessian.len()];
        assembled.hessian(x, 1.0, lambda, &mut hessian);
        let matrices = Self {
            hessian_pattern: assembled.patterns.hessian.clone(),
            hessian,
            jacobian_pattern: assembled.patterns.jacobian.clone(),
            jacobian: at.jacobian.clone(),
        };
        (at, matrices)
    }
}

/// The position of each of `n` variables among those not fixed by a bound in `fixed` (`None` for a
/// fixed one), and how many are free.
pub(crate) fn free_positions(n: usize, fixed: &[Bound]) -> (Vec<Option<usize>>, usize) {
    let mut position = vec![Some(0usize); n];
    for b in fixed {
        position[b.index] = None;
    }
    let mut free = 0;
    for slot in position.iter_mut().flatten() {
        *slot = free;
        free += 1;
    }
    (position, free)
}

/// One active set's system: the dependent rows left out of it (each derivative is checked against
/// them) and the factorised reduced KKT matrix of the rest (`None` when singular).
pub(crate) struct ActiveSystem {
    /// The bounds that fix variables.
    pub variables: Vec<Bound>,
    /// Every active row, the dependent ones included.
    pub rows: Vec<Bound>,
    /// The rows that depend linearly on earlier ones (empty above [`MAX_DENSE`]).
    pub dependent: Vec<usize>,
    pub kkt: Option<ReducedKkt>,
}

impl ActiveSystem {
    /// The system of this active set. The KKT matrix with every active row is factorised first:
    /// where its inertia certifies a minimum, no row depends on the others (a dependent row would
    /// give a zero eigenvalue) and nothing else is needed; otherwise the dependent rows are found
    /// ([`dependent_rows`]) and left out, and the rest is factorised.
    pub fn new(matrices: &Matrices, layout: Layout, variables: Vec<Bound>, rows: Vec<Bound>) -> Self {
        let jacobian = (&matrices.jacobian_pattern[..], &matrices.jacobian[..]);
        let hessian = (&matrices.hessian_pattern[..], &matrices.hessian[..]);
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        let factorise = |rows: &[Bound]| ReducedKkt::new(n, m, &variables, rows, hessian, jacobian).ok();
        let all = factorise(&rows);
        if all.as_ref().is_some_and(ReducedKkt::certifies_minimum) {
            return Self { variables, rows, dependent: Vec::new(), kkt: all };
        }
        let dependent = dependent_rows(n, &variables, &rows, jacobian).unwrap_or_default();
        let kkt = if dependent.is_empty() {
            all
        } else {
            let kept: Vec<Bound> = rows.iter().filter(|b| !dependent.contains(&b.index)).copied().collect();
            factorise(&kept)
        };
        Self { variables, rows, dependent, kkt }
    }

    /// The factorisation, where it certifies a strict local minimum with independent active rows.
    pub fn certified(&self) -> Option<&ReducedKkt> {
        self.kkt.as_ref().filter(|k| k.certifies_minimum())
    }
}

/// The factorised reduced KKT matrix and the index maps behind it.
pub(crate) struct ReducedKkt {
    /// Position of each variable among the free ones (`None`: fixed by an active bound).
    pub free_position: Vec<Option<usize>>,
    /// The active rows in the system, in order.
    pub rows: Vec<Bound>,
    pub free: usize,
    pub inertia: Inertia,
    solver: SymmetricSolver,
}

impl ReducedKkt {
    /// Builds and factorises the system for this active set (the bounds in `variables` fix their
    /// variables; `rows` are the active rows). `hessian` is the Hessian of the Lagrangian in its
    /// lower-triangle pattern, `jacobian` the constraint Jacobian in its pattern.
    pub fn new(
        n: usize,
        m: usize,
        variables: &[Bound],
        rows: &[Bound],
        hessian: (&[(usize, usize)], &[f64]),
        jacobian: (&[(usize, usize)], &[f64]),
    ) -> Result<Self, KktError> {
        let (free_position, free) = free_positions(n, variables);
        let mut row_position = vec![None; m];
        for (k, b) in rows.iter().enumerate() {
            row_position[b.index] = Some(k);
        }
        let order = free + rows.len();
        let mut entries: BTreeMap<(usize, usize), f64> = (0..order).map(|i| ((i, i), 0.0)).collect();
        for (&(a, b), &v) in hessian.0.iter().zip(hessian.1) {
            if let (Some(p), Some(q)) = (free_position[a], free_position[b]) {
                *entries.entry((p.min(q), p.max(q))).or_insert(0.0) += v;
            }
        }
        for (&(r, c), &v) in jacobian.0.iter().zip(jacobian.1) {
            if let (Some(k), Some(p)) = (row_position[r], free_position[c]) {
                *entries.entry((p, free + k)).or_insert(0.0) += v;
            }
        }
        let list: Vec<(usize, usize)> = entries.keys().copied().collect();
        let (structure, position) = Structure::from_entries(order, &list)?;
        let mut values = vec![0.0; list.len()];
        for (e, v) in entries.values().enumerate() {
            values[position[e]] = *v;
        }
        let mut solver = SymmetricSolver::new(structure);
        let inertia = solver.factorize(&values)?;
        Ok(Self { free_position, rows: rows.to_vec(), free, inertia, solver })
    }

    /// Whether the inertia is that of a strict local minimum with independent active rows:
    /// `free` positive, one negative per active row, none zero.
    pub fn certifies_minimum(&self) -> bool {
        self.inertia.positive == self.free && self.inertia.negative == self.rows.len() && self.inertia.zero == 0
    }

    /// Solves `[H_FF J_AFᵀ; J_AF 0] (dx_F, dλ_A) = rhs` (free-variable entries first).
    pub fn solve(&self, rhs: &mut [f64]) -> Result<(), KktError> {
        self.solver.solve(rhs).map(|_| ())
    }
}

/// `y = H v` for the symmetric Hessian given by its lower triangle.
pub(crate) fn hessian_times(pattern: &[(usize, usize)], values: &[f64], v: &[f64]) -> Vec<f64> {
    let mut y = vec![0.0; v.len()];
    for (&(a, b), &h) in pattern.iter().zip(values) {
        y[a] += h * v[b];
        if a != b {
            y[b] += h * v[a];
        }
    }
    y
}

/// `y = J v` for the Jacobian in its pattern.
pub(crate) fn jacobian_times(pattern: &[(usize, usize)], values: &[f64], v: &[f64], m: usize) -> Vec<f64> {
    let mut y = vec![0.0; m];
    for (&(r, c), &j) in pattern.iter().zip(values) {
        y[r] += j * v[c];
    }
    y
}

/// `y = Jᵀ w` for the Jacobian in its pattern.
pub(crate) fn jacobian_transpose_times(pattern: &[(usize, usize)], values: &[f64], w: &[f64], n: usize) -> Vec<f64> {
    let mut y = vec![0.0; n];
    for (&(r, c), &j) in pattern.iter().zip(values) {
        y[c] += j * w[r];
    }
    y
}

/// The derivative of a bound's value in the parameter, for the side at which it holds.
pub(crate) fn bound_rate(bound: &Bound, lower_rate: f64, upper_rate: f64) -> f64 {
    match bound.side {
        Side::Lower | Side::Both => lower_rate,
        Side::Upper => upper_rate,
    }
}

/// The active set with some weakly active bounds taken as active (the others as inactive).
pub(crate) fn with_weak(set: &ActiveSet, variables: &[Bound], rows: &[Bound]) -> (Vec<Bound>, Vec<Bound>) {
    let mut v = set.variables.clone();
    v.extend_from_slice(variables);
    let mut r = set.rows.clone();
    r.extend_from_slice(rows);
    r.sort_by_key(|b| b.index);
    (v, r)
}

/// Most entries of the dense active-row Jacobian for the LICQ measures.
pub(crate) const MAX_DENSE: usize = 250_000;

/// The active rows' Jacobian on the free variables of `variables`, dense and row-major, with the
/// number of free variables; `None` above [`MAX_DENSE`] entries or without rows.
fn active_rows_dense(
    n: usize,
    variables: &[Bound],
    rows: &[Bound],
    jacobian: (&[(usize, usize)], &[f64]),
) -> Option<(Vec<f64>, usize)> {
    let (free, count) = free_positions(n, variables);
    if rows.is_empty() || rows.len() * count > MAX_DENSE {
        return None;
    }
    let position = row_positions(rows, jacobian.0);
    let mut a = vec![0.0; rows.len() * count];
    for (&(r, c), &v) in jacobian.0.iter().zip(jacobian.1) {
        if let (Some(p), Some(q)) = (position[r], free[c]) {
            a[p * count + q] += v;
        }
    }
    Some((a, count))
}

/// LICQ's measure at the active set: the smallest singular value of the active rows' Jacobian `A`
/// on the free variables (zero with more rows than free variables), by bidiagonalisation of the
/// dense `Aᵀ` ([`super::smallest_singular_value`]; not through the Gram matrix `A Aᵀ`, which
/// squares the condition and lost design10's `σ_min`). `None` above [`MAX_DENSE`].
pub(crate) fn smallest_singular_value(
    n: usize,
    variables: &[Bound],
    rows: &[Bound],
    jacobian: (&[(usize, usize)], &[f64]),
) -> Option<f64> {
    let (a, count) = active_rows_dense(n, variables, rows, jacobian)?;
    let k = rows.len();
    if k > count {
        return Some(0.0);
    }
    // `Aᵀ` (free variables by active rows, row-major): the bidiagonalisation wants it tall.
    let mut transposed: Vec<f64> = (0..count * k).map(|e| a[(e % k) * count + e / k]).collect();
    Some(smallest_singular_value::smallest_singular_value(&mut transposed, count, k))
}

/// Each constraint row's position among the active `rows` (`None` for an inactive row), sized for
/// every row the Jacobian's `pattern` or `rows` names.
fn row_positions(rows: &[Bound], pattern: &[(usize, usize)]) -> Vec<Option<usize>> {
    let m = pattern.iter().map(|&(r, _)| r + 1).chain(rows.iter().map(|b| b.index + 1)).max().unwrap_or(0);
    let mut position = vec![None; m];
    for (p, b) in rows.iter().enumerate() {
        position[b.index] = Some(p);
    }
    position
}

/// The active rows (constraint indices) that depend linearly on earlier ones on the free variables
/// (modified Gram–Schmidt in place: a row whose remainder is below 1e-9 of its norm). `None` above
/// [`MAX_DENSE`].
pub(crate) fn dependent_rows(
    n: usize,
    variables: &[Bound],
    rows: &[Bound],
    jacobian: (&[(usize, usize)], &[f64]),
) -> Option<Vec<usize>> {
    let (mut a, count) = active_rows_dense(n, variables, rows, jacobian)?;
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
    let mut basis: Vec<usize> = Vec::new();
    let mut dependent = Vec::new();
    for (p, b) in rows.iter().enumerate() {
        let (done, rest) = a.split_at_mut(p * count);
        let v = &mut rest[..count];
        let norm = dot(v, v).sqrt();
        for &q in &basis {
            let unit = &done[q * count..(q + 1) * count];
            let c = dot(unit, v);
            v.iter_mut().zip(unit).for_each(|(x, u)| *x -= c * u);
        }
        let remainder = dot(v, v).sqrt();
        if remainder <= 1e-9 * norm.max(f64::MIN_POSITIVE) {
            dependent.push(b.index);
        } else {
            v.iter_mut().for_each(|x| *x /= remainder);
            basis.push(p);
        }
    }
    Some(dependent)
}

#[cfg(test)]
mod tests {
    use super::*;
    use spine_model::rng::SplitMix64;

    fn bound(index: usize) -> Bound {
        Bound { index, side: Side::Both, multiplier: 1.0, gap: 0.0 }
    }

    /// LICQ's measure from the sparse Jacobian's active rows (with
    /// repeated entries, fixed variables and inactive rows) against the SVD of the dense active
    /// rows; and zero for dependent rows, where Gram–Schmidt finds the dependent one.
    #[test]
    fn licqs_measure_is_the_dense_svds_smallest_singular_value() {
        let (n, m) = (14, 9);
        let mut rng = SplitMix64::new(3);
        let mut pattern = Vec::new();
        let mut values = Vec::new();
        for r in 0..m {
            for _ in 0..5 {
                pattern.push((r, (rng.uniform(0.0, n as f64) as usize).min(n - 1)));
                values.push(rng.uniform(-2.0, 2.0));
            }
        }
        // A repeated entry (the assembly's patterns never repeat one, but the sum must not care).
        pattern.push(pattern[0]);
        values.push(0.7);
        let variables = [bound(2), bound(9)];
        let rows: Vec<Bound> = [0, 2, 3, 5, 6, 8].into_iter().map(bound).collect();
        let jacobian = (&pattern[..], &values[..]);
        let (dense, count) = active_rows_dense(n, &variables, &rows, jacobian).unwrap();
        let a = nalgebra::DMatrix::from_row_slice(rows.len(), count, &dense);
        let svd = a.singular_values().iter().copied().fold(f64::INFINITY, f64::min);
        let measure = smallest_singular_value(n, &variables, &rows, jacobian).unwrap();
        assert!(svd > 1e-3, "the random rows are independent ({svd:e})");
        assert!((measure - svd).abs() <= 1e-12 * a.norm(), "measure {measure:e} vs SVD {svd:e}");
        // Row 6 made a combination of rows 0 and 3: the measure falls to round-off.
        let mut dependent: Vec<f64> =
            pattern.iter().zip(&values).map(|(&(r, _), &v)| if r == 6 { 0.0 } else { v }).collect();
        let mut extended = pattern.clone();
        for (k, &(r, c)) in pattern.iter().enumerate() {
            if r == 0 || r == 3 {
                extended.push((6, c));
                dependent.push(if r == 0 { 2.0 } else { -0.5 } * values[k]);
            }
        }
        let jacobian = (&extended[..], &dependent[..]);
        let measure = smallest_singular_value(n, &variables, &rows, jacobian).unwrap();
        assert!(measure <= 1e-6, "dependent rows: {measure:e}");
        assert_eq!(dependent_rows(n, &variables, &rows, jacobian), Some(vec![6]));
    }
}
