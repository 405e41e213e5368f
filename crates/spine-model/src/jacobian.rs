//! Exact sparse Jacobians of the equilibrium residual by forward-mode AD.
//!
//! Each joint row is evaluated once with fixed-size dual numbers seeded only on the slots of its
//! [`JointStencil`]; the derivative parts are scattered into the sparse result. Cost and memory are
//! linear in `N`: no dense `N × N` matrix is formed.

use crate::kinematics::{end_constraint, link_rise};
use crate::residual::{slot, JointStencil};
use crate::sparse::{BorderedTridiagonal, SparseMatrix};
use crate::{Design, LinkLoads, State};
use nalgebra::{Const, U1};
use num_dual::DualSVec64;

/// Derivatives of one term `L_i sin θ_i` of `Φ`: `(∂/∂θ_i, ∂/∂θ0_i)`.
pub fn rise_derivatives(span: f64, theta0: f64, theta: f64) -> (f64, f64) {
    let t = DualSVec64::<2>::from_re(theta).derivative(0);
    let t0 = DualSVec64::<2>::from_re(theta0).derivative(1);
    let d = link_rise(span, t0, t).eps.unwrap_generic(Const::<2>, U1);
    (d[0], d[1])
}

/// Joint `i`'s stencil with the `M` slots `first..first + M` seeded as independent variables.
fn seeded_stencil<const M: usize>(
    i: usize,
    design: &Design,
    state: &State,
    first: usize,
) -> JointStencil<DualSVec64<M>> {
    JointStencil::gather(i, &state.theta, state.lambda, &design.theta0, &design.stiffness, |s, v| {
        let d = DualSVec64::<M>::from_re(v);
        if (first..first + M).contains(&s) {
            d.derivative(s - first)
        } else {
            d
        }
    })
}

/// Residual of eq. (5) and its Jacobian with respect to `(θ, λ)` in one pass.
///
/// The Jacobian is bordered tridiagonal: `∂r_i/∂θ_{i±1}` from the springs, `∂r_i/∂θ_i`,
/// `∂r_i/∂λ = −L_i cos θ_i`, and the constraint row `∂Φ/∂θ_i = L_i cos θ_i`.
///
/// One AD pass per joint gives the whole row and the border entry of the constraint row: `r_i` is
/// `∂(U + V − λΦ)/∂θ_i`, so `∂Φ/∂θ_i = −∂r_i/∂λ` exactly (the λ-derivative of the seeded pass;
/// `tests/local_and_hand.rs` checks it against the AD of `Φ` itself). This halves the
/// transcendental calls against a second pass over `L_i sin θ_i`.
pub fn residual_and_state_jacobian(
    spans: &[f64],
    design: &Design,
    loads: &LinkLoads,
    state: &State,
) -> (Vec<f64>, BorderedTridiagonal) {
    let n = spans.len();
    let mut jac = BorderedTridiagonal::zeros(n);
    let mut r = Vec::with_capacity(n + 1);
    for i in 0..n {
        let st = seeded_stencil::<4>(i, design, state, slot::THETA_PREV);
        let ri = st.residual(spans[i], loads.vertical[i], loads.axial[i]);
        let g = ri.eps.unwrap_generic(Const::<4>, U1);
        r.push(ri.re);
        if st.has_prev {
            jac.lower[i - 1] = g[slot::THETA_PREV];
        }
        jac.diag[i] = g[slot::THETA];
        if st.has_next {
            jac.upper[i] = g[slot::THETA_NEXT];
        }
        jac.column[i] = g[slot::LAMBDA];
        jac.row[i] = -g[slot::LAMBDA];
    }
    r.push(end_constraint(spans, &design.theta0, &state.theta));
    (r, jac)
}

/// Index of design variables: `θ0_i` is column `i`, `K_j` is column `N + j` (`2N + 1` columns).
pub fn design_column_of_stiffness(n_links: usize, j: usize) -> usize {
    n_links + j
}

/// Jacobian of the residual `[r; Φ]` with respect to the design `(θ0, K)`, `(N+1) × (2N+1)`.
///
/// Row `i < N` has at most five entries (`θ0_{i−1..=i+1}`, `K_i`, `K_{i+1}`); the constraint row
/// `Φ = Σ (a_i / cos θ0_i) sin θ_i` has one entry per `θ0_i` through the link lengths.
pub fn design_jacobian(spans: &[f64], design: &Design, loads: &LinkLoads, state: &State) -> SparseMatrix {
    let n = spans.len();
    let mut m = SparseMatrix::new(n + 1, 2 * n + 1);
    for i in 0..n {
        let st = seeded_stencil::<5>(i, design, state, slot::THETA0_PREV);
        let g = st.residual(spans[i], loads.vertical[i], loads.axial[i]).eps.unwrap_generic(Const::<5>, U1);
        let local = |s: usize| g[s - slot::THETA0_PREV];
        if st.has_prev {
            m.push(i, i - 1, local(slot::THETA0_PREV));
        }
        m.push(i, i, local(slot::THETA0));
        if st.has_next {
            m.push(i, i + 1, local(slot::THETA0_NEXT));
        }
        m.push(i, design_column_of_stiffness(n, i), local(slot::STIFFNESS_LEFT));
        m.push(i, design_column_of_stiffness(n, i + 1), local(slot::STIFFNESS_RIGHT));
        m.push(n, i, rise_derivatives(spans[i], design.theta0[i], state.theta[i]).1);
    }
    m
}
