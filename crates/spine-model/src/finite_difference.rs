//! Central finite differences of the equilibrium residual (eq. (5)), element by element: the
//! third way to get the state Jacobian, beside forward AD ([`crate::jacobian`]) and the paper's
//! hand-derived entries ([`crate::hand`]). Tests and benchmarks compare the three.
//!
//! Each joint row depends on four state variables (`θ_{i−1}, θ_i, θ_{i+1}, λ`) and the constraint
//! row `Φ = Σ L_i sin θ_i` on each `θ_i` through one term, so the differences are taken on the
//! row's own [`JointStencil`] and on each link's rise: `2 × 5` element evaluations per link, O(N)
//! in total, the same cost class as the AD Jacobian (a column-by-column difference of the whole
//! residual would cost O(N²) because of the `λ` column and the `Φ` row).
//!
//! The step of a variable `v` is `step · max(1, |v|)`; the truncation error is `O(step²)` and the
//! rounding error `O(ε / step)`, so `step ≈ ε^{1/3} ≈ 6e-6` balances them.

use crate::kinematics::{end_constraint, link_rise};
use crate::residual::{slot, JointStencil};
use crate::sparse::BorderedTridiagonal;
use crate::{Design, LinkLoads, State};

/// The step that balances truncation and rounding for central differences, `ε^{1/3}`.
pub const CENTRAL_STEP: f64 = 6.0e-6;

/// `(f(v + h) − f(v − h)) / 2h` with `h = step · max(1, |v|)`.
pub fn central(v: f64, step: f64, f: impl Fn(f64) -> f64) -> f64 {
    let h = step * v.abs().max(1.0);
    (f(v + h) - f(v - h)) / (2.0 * h)
}

/// The gradient of a scalar function by [`central`] differences in each entry of `x`.
pub fn central_gradient(x: &[f64], step: f64, f: impl Fn(&[f64]) -> f64) -> Vec<f64> {
    (0..x.len())
        .map(|k| {
            central(x[k], step, |v| {
                let mut moved = x.to_vec();
                moved[k] = v;
                f(&moved)
            })
        })
        .collect()
}

/// The Jacobian `J[i][k] = ∂f_i/∂x_k` of a vector function by central differences (dense, rows
/// `i`), with the steps of [`central`].
pub fn central_jacobian(x: &[f64], step: f64, f: impl Fn(&[f64]) -> Vec<f64>) -> Vec<Vec<f64>> {
    let m = f(x).len();
    let mut jac = vec![vec![0.0; x.len()]; m];
    for k in 0..x.len() {
        let h = step * x[k].abs().max(1.0);
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[k] += h;
        xm[k] -= h;
        let (fp, fm) = (f(&xp), f(&xm));
        for i in 0..m {
            jac[i][k] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    jac
}

/// The residual of eq. (5) and its Jacobian with respect to `(θ, λ)` by central differences, in
/// the bordered tridiagonal layout of [`crate::jacobian::residual_and_state_jacobian`].
pub fn residual_and_state_jacobian(
    spans: &[f64],
    design: &Design,
    loads: &LinkLoads,
    state: &State,
    step: f64,
) -> (Vec<f64>, BorderedTridiagonal) {
    let n = spans.len();
    let mut jac = BorderedTridiagonal::zeros(n);
    let mut r = Vec::with_capacity(n + 1);
    for i in 0..n {
        let stencil =
            JointStencil::<f64>::gather(i, &state.theta, state.lambda, &design.theta0, &design.stiffness, |_, v| v);
        let row = |s: &JointStencil<f64>| s.residual(spans[i], loads.vertical[i], loads.axial[i]);
        let partial = |k: usize| {
            central(stencil.values[k], step, |v| {
                let mut moved = stencil;
                moved.values[k] = v;
                row(&moved)
            })
        };
        r.push(row(&stencil));
        if stencil.has_prev {
            jac.lower[i - 1] = partial(slot::THETA_PREV);
        }
        jac.diag[i] = partial(slot::THETA);
        if stencil.has_next {
            jac.upper[i] = partial(slot::THETA_NEXT);
        }
        jac.column[i] = partial(slot::LAMBDA);
        jac.row[i] = central(state.theta[i], step, |t| link_rise(spans[i], design.theta0[i], t));
    }
    r.push(end_constraint(spans, &design.theta0, &state.theta));
    (r, jac)
}
