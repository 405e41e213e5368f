//! The discrete adjoint of an accepted Radau IIA step: the transpose of its internal
//! differentiation ([`super::sensitivities`]), so that a backward sweep gives the same gradients
//! as the forward sensitivities, to round-off, with one sweep per output instead of one column
//! per parameter.
//!
//! The step `y₁ = P(y₀ + Z₃)` (`P` the projection) with stages `Z = h (A ⊗ I) F(y₀ + Z)` has the
//! tangent `dZ = h (A ⊗ I) (J_j (dy₀ + dZ_j) + ∂f/∂p_j dp)_j`. For an adjoint `λ₁` of `y₁`, with
//! `μ = Pᵀ λ₁` and `V` solving `V_j = h Σ_i a_ij (J_iᵀ V_i + δ_i3 μ)` (the stage system with `Aᵀ`,
//! [`Orientation::Adjoint`]),
//!
//! `λ₁ᵀ dy₁ = (μ + Σ_j J_jᵀ V_j)ᵀ dy₀ + (Σ_j ∂f/∂p_jᵀ V_j)ᵀ dp`.
//!
//! The stage values come back from the stored collocation polynomial (`Z_i = y(t₀ + c_i h) − y₀`);
//! the products with `J_jᵀ` and `∂f/∂p_jᵀ` are the system's at the stage points
//! ([`OdeSystem::vector_jacobian`], `O(N)` each for the chain); the adjoint stage system is solved
//! by the stages' own transformed iteration with the transposed Newton matrices (`O(N)` for the
//! chain), to round-off, or, where that iteration does not converge, by one LU of the
//! `3n × 3n` matrix.

use super::super::dense::Interval;
use super::super::options::Stats;
use super::stages::{collocation, factor, Factors, Orientation, Stages, Workspace, A, C};
use crate::ode::{OdeSystem, VectorJacobian};
use nalgebra::DMatrix;

/// The Newton matrices of the last step swept back, kept while the step size does not change (as
/// the forward run keeps them) and refreshed when the adjoint iteration slows.
#[derive(Default)]
pub(in crate::integrator) struct AdjointWork {
    factors: Option<Factors>,
    /// The iteration slowed: the next step takes fresh Newton matrices.
    stale: bool,
    work: Workspace,
}

/// The adjoint iteration stops when its predicted remaining error is below this, relative to `h
/// |μ|`: over thousands of steps the gradients come out within about 5e-10 relative of the forward
/// sensitivities (which run their own iteration to 1e-13), far inside what an optimiser needs
/// (benchmarks/DYNAMICS.md, measured 2026-11-28: 3e-11 for the springs of eq. (37), 5e-10 for
/// eq. (35)'s rise time). At 1e-12 the differences were 1e-12 and 9e-11, and `spine periodic` on
/// periodic7 by gradients took 5 % longer (1.99 s against 1.88 s, median of five runs each).
const TOLERANCE: f64 = 1e-11;

/// The Newton matrices of a step size within this relative margin of a step's precondition its
/// adjoint iteration (the forward run changes the step size at most steps; refactoring at each
/// would cost about as much as the iterations).
const REFACTOR_MARGIN: f64 = 0.1;

/// A contraction rate above which the next step takes fresh Newton matrices (the stale `J̃`
/// contracts at about 0.01 on the chain's steps).
const SLOW: f64 = 0.1;

/// `(λ₀, ∂/∂p)` of an accepted step for the adjoints `λ₁` (columns) of its end: see the module
/// docs. `None` when the interval has no collocation polynomial (not a Radau IIA step) or its
/// Newton matrices are singular.
pub(in crate::integrator) fn step_adjoint(
    sys: &dyn OdeSystem,
    iv: &Interval,
    lambda1: &DMatrix<f64>,
    work: &mut AdjointWork,
    stats: &mut Stats,
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    iv.collocation.as_ref()?;
    let m = lambda1.ncols();
    let (h, piece) = (iv.t1 - iv.t0, iv.piece());
    // The stage points `y₀ + Z_i` and the unprojected end `y₀ + Z₃` on the collocation polynomial.
    let points: Vec<(f64, Vec<f64>)> = (0..3).map(|i| (iv.t0 + C[i] * h, iv.value(iv.t0 + C[i] * h))).collect();
    let unprojected = iv.value(iv.t1);
    let mut mu = lambda1.clone();
    for mut column in mu.column_iter_mut() {
        sys.project_adjoint(&unprojected, column.as_mut_slice());
    }
    stats.jacobian_evaluations += 3;
    let products: Vec<Box<dyn VectorJacobian + '_>> =
        points.iter().map(|(ti, yi)| sys.vector_jacobian(*ti, piece, yi)).collect();
    if work.stale || work.factors.as_ref().is_none_or(|f| (f.h / h - 1.0).abs() > REFACTOR_MARGIN) {
        work.stale = false;
        stats.jacobian_evaluations += 1;
        work.factors = factor(sys.linearize(iv.t0, piece, &iv.y0).as_ref(), h, stats);
    }
    let mut lambda0 = mu.clone();
    let mut gradient = DMatrix::zeros(sys.n_params(), m);
    for k in 0..m {
        let mu_k: Vec<f64> = mu.column(k).iter().copied().collect();
        if mu_k.iter().all(|v| *v == 0.0) {
            continue;
        }
        let v = match stage_adjoint(&products, &mu_k, h, work, stats) {
            Some(v) => v,
            None => {
                let jac: Vec<DMatrix<f64>> = points.iter().map(|(ti, yi)| sys.jacobian(*ti, piece, yi)).collect();
                direct(&jac, &mu_k, h)?
            }
        };
        for (vj, pj) in v.iter().zip(&products) {
            let (to_state, to_params) = pj.products(vj);
            for (l, x) in lambda0.column_mut(k).iter_mut().zip(to_state) {
                *l += x;
            }
            for (g, x) in gradient.column_mut(k).iter_mut().zip(to_params) {
                *g += x;
            }
        }
    }
    Some((lambda0, gradient))
}

/// `V` of the module docs by the transformed iteration with the transposed Newton matrices, run to
/// round-off relative to `h |μ|` (the size of `V`); `None` when it does not converge (the next step
/// then refactors, as after a slow contraction).
fn stage_adjoint(
    products: &[Box<dyn VectorJacobian + '_>],
    mu: &[f64],
    h: f64,
    work: &mut AdjointWork,
    stats: &mut Stats,
) -> Option<Stages> {
    let factors = work.factors.as_ref()?;
    let scale = h * mu.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut params = vec![0.0; products[0].n_params()];
    let mut stage = |i: usize, v: &[f64], out: &mut [f64]| {
        products[i].products_into(v, out, &mut params);
        if i == 2 {
            out.iter_mut().zip(mu).for_each(|(o, m)| *o += m);
        }
    };
    let norm = |dw: &Stages| dw.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs())) / scale;
    // The first-order guess `V_j = h a_3j μ` (the terms in `J` left out).
    let guess: Stages = std::array::from_fn(|j| mu.iter().map(|m| h * A[2][j] * m).collect());
    let orientation = Orientation::Adjoint(h);
    let col = collocation(orientation, &mut stage, guess, factors, &norm, TOLERANCE, f64::INFINITY, 60, &mut work.work);
    stats.newton_iterations += col.as_ref().map_or(60, |c| c.iterations);
    work.stale |= col.as_ref().is_none_or(|c| c.rate.is_some_and(|r| r > SLOW));
    col.map(|c| c.z)
}

/// `V` of the module docs by one LU of `I − h (A ⊗ I) diag(J_j)`: `Mᵀ W = e₃ ⊗ μ`, `V = h (Aᵀ ⊗
/// I) W`. `None` where the matrix is singular.
fn direct(jac: &[DMatrix<f64>], mu: &[f64], h: f64) -> Option<Stages> {
    use faer::linalg::solvers::Solve;
    let n = mu.len();
    let transposed = faer::Mat::<f64>::from_fn(3 * n, 3 * n, |r, c| {
        // Entry (c, r) of I − h (A ⊗ I) diag(J_j).
        let (i, j) = (c / n, r / n);
        let identity = if r == c { 1.0 } else { 0.0 };
        identity - h * A[i][j] * jac[j][(c % n, r % n)]
    });
    let rhs = faer::Mat::<f64>::from_fn(3 * n, 1, |r, _| if r >= 2 * n { mu[r - 2 * n] } else { 0.0 });
    let w = transposed.partial_piv_lu().solve(&rhs);
    let v: Stages =
        std::array::from_fn(|j| (0..n).map(|r| (0..3).map(|i| h * A[i][j] * w[(i * n + r, 0)]).sum()).collect());
    v.iter().flatten().all(|x| x.is_finite()).then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::periodic_problem;
    use crate::integrator::{integrate, Extras, Options};
    use crate::ode::DenseProducts;
    use crate::{Forcing, Parameters, SpineOde};

    /// The transformed iteration with the transposed Newton matrices solves the same adjoint stage
    /// system as the dense LU, on the steps of a pulse-train run (J̃ ≠ J in motion), to round-off.
    #[test]
    fn the_adjoint_iteration_solves_what_the_dense_lu_solves() {
        let problem = periodic_problem(5);
        let ends = problem.static_ends(&Default::default()).unwrap();
        let d = problem.dynamics(Forcing::PulseTrain { period: 0.2, duty: 0.5, delay: 0.0 });
        let ode = SpineOde { dynamics: &d, parameters: Parameters::Springs };
        let run = integrate(&ode, 0.0, &ends.rest_state(), 0.2, &Options::default(), Extras::default());
        let (mut work, mut stats) = (AdjointWork::default(), Stats::default());
        let mu: Vec<f64> = (0..10).map(|i| (i as f64 * 0.9).cos()).collect();
        let mut iterated = 0;
        for iv in run.intervals.iter().step_by(7) {
            let h = iv.t1 - iv.t0;
            let jac: Vec<DMatrix<f64>> =
                (0..3).map(|i| ode.jacobian(iv.t0 + C[i] * h, iv.piece(), &iv.value(iv.t0 + C[i] * h))).collect();
            let products: Vec<Box<dyn VectorJacobian>> = jac
                .iter()
                .map(|j| Box::new(DenseProducts::new(j, &DMatrix::zeros(10, 0))) as Box<dyn VectorJacobian>)
                .collect();
            work.factors = factor(ode.linearize(iv.t0, iv.piece(), &iv.y0).as_ref(), h, &mut stats);
            let Some(v) = stage_adjoint(&products, &mu, h, &mut work, &mut stats) else { continue };
            iterated += 1;
            let w = direct(&jac, &mu, h).unwrap();
            let scale = w.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            for (a, b) in v.iter().flatten().zip(w.iter().flatten()) {
                assert!((a - b).abs() <= 1e-11 * scale, "{a:e} vs {b:e} (scale {scale:e}, h = {h:e})");
            }
        }
        assert!(iterated >= 5, "the iteration converged on {iterated} steps");
    }
}
