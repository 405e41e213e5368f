//! Exact sparse Jacobians of the equilibrium residual by forward-mode AD.
//!
//! Each joint row is evaluated once with fixed-size dual numbers seeded only on the slots of its
//! [`JointStencil`]; the derivative parts are scattered into the sparse result. Cost and memory are
//! linear in `N`: no dense `N × N` matrix is formed.

use crate::jet::Jet;
use crate::kinematics::link_rise;
use crate::residual::{joint_deflections, slot, spring_moment, Joint, JointStencil};
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
/// One pass per joint through the same physics as the residual ([`spring_moment`] and
/// [`Joint::link`]), each with only the lanes it depends on: the springs with a 3-lane [`Jet`]
/// over the deflections `Δθ_{i−1}, Δθ_i, Δθ_{i+1}` (the stiffnesses plain numbers), the link with a
/// 2-lane [`Jet`] over `θ_i, λ` (`θ0_i` plain, so `L_i` costs one plain `cos`). The border entry of
/// the constraint row is the λ-derivative of the reaction: `r_i` is `∂(U + V − λΦ)/∂θ_i`, so
/// `∂Φ/∂θ_i = −∂r_i/∂λ` exactly (`tests/local_and_hand.rs` checks it against the AD of `Φ`
/// itself). The residual is the same expression as [`crate::residual::equilibrium_residual`]'s,
/// to the bit, `Φ` included (its terms are the link's rise from the same pass).
pub fn residual_and_state_jacobian(
    spans: &[f64],
    design: &Design,
    loads: &LinkLoads,
    state: &State,
) -> (Vec<f64>, BorderedTridiagonal) {
    let n = spans.len();
    let mut jac = BorderedTridiagonal::zeros(n);
    let mut r = Vec::with_capacity(n + 1);
    let (theta, theta0, k) = (&state.theta, &design.theta0, &design.stiffness);
    let mut phi = 0.0;
    for i in 0..n {
        let lanes = joint_deflections(theta, theta0, i);
        let spring = spring_moment(std::array::from_fn(|s| Jet::<3>::variable(lanes[s], s)), [k[i], k[i + 1]]);
        let joint = Joint { span: spans[i], vertical: loads.vertical[i], axial: loads.axial[i] };
        let link = joint.link(Jet::<2>::variable(theta[i], 0), theta0[i], Jet::variable(state.lambda, 1));
        r.push(spring.re - link.load.re - link.reaction.re);
        phi += link.rise.re;
        if i > 0 {
            jac.lower[i - 1] = spring.eps[0];
        }
        jac.diag[i] = spring.eps[1] - link.load.eps[0] - link.reaction.eps[0];
        if i + 1 < n {
            jac.upper[i] = spring.eps[2];
        }
        jac.column[i] = -link.reaction.eps[1];
        jac.row[i] = link.reaction.eps[1];
    }
    // Φ = Σ L_i sin θ_i from the same pass ([`crate::kinematics::end_constraint`]'s terms).
    r.push(phi);
    (r, jac)
}

/// Joint row `i`'s derivatives and link `i`'s terms of `Φ` and `X_{N+1}`, from one pass (see
/// [`joint_derivatives`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JointDerivatives {
    /// `r_i`, N·m.
    pub residual: f64,
    /// `∂r_i/∂(θ_{i−1}, θ_i, θ_{i+1}, λ)` (the first zero for `i = 0`, the third for `i = N − 1`).
    pub by_state: [f64; 4],
    /// `∂r_i/∂(θ0_{i−1}, θ0_i, θ0_{i+1}, K_i, K_{i+1})`.
    pub by_design: [f64; 5],
    /// `∂(L_i sin θ_i)/∂(θ_i, θ0_i)`: link `i`'s entries of `∂Φ/∂θ` and `∂Φ/∂θ0`.
    pub rise: [f64; 2],
    /// `L_i cos θ_i` and its derivatives `∂/∂(θ_i, θ0_i)`: link `i`'s term of `X_{N+1}`.
    pub run: (f64, [f64; 2]),
}

/// Every joint's [`JointDerivatives`] in one pass per joint, through the same physics as the
/// residual: the springs with a 5-lane [`Jet`] over `Δθ_{i−1}, Δθ_i, Δθ_{i+1}, K_i, K_{i+1}`
/// (`∂/∂θ_j = ∂/∂Δθ_j`, `∂/∂θ0_j = −∂/∂Δθ_j`: the chain rule through `Δθ = θ − θ0`), the link with
/// a 3-lane [`Jet`] over `θ_i, θ0_i, λ` giving its load, reaction, rise and run together. The
/// design partials stay per joint, ready to be contracted with an adjoint (no triplets).
pub fn joint_derivatives(spans: &[f64], design: &Design, loads: &LinkLoads, state: &State) -> Vec<JointDerivatives> {
    let n = spans.len();
    let (theta, theta0, k) = (&state.theta, &design.theta0, &design.stiffness);
    (0..n)
        .map(|i| {
            let [before, here, after] = joint_deflections(theta, theta0, i);
            let lanes = [before, here, after, k[i], k[i + 1]];
            let x: [Jet<5>; 5] = std::array::from_fn(|s| Jet::variable(lanes[s], s));
            let spring = spring_moment([x[0], x[1], x[2]], [x[3], x[4]]);
            let joint = Joint { span: spans[i], vertical: loads.vertical[i], axial: loads.axial[i] };
            let link = joint.link(
                Jet::<3>::variable(theta[i], 0),
                Jet::variable(theta0[i], 1),
                Jet::variable(state.lambda, 2),
            );
            let g = spring.eps;
            let (load, reaction) = (link.load.eps, link.reaction.eps);
            let mut row = JointDerivatives {
                residual: spring.re - link.load.re - link.reaction.re,
                by_state: [g[0], g[1] - load[0] - reaction[0], g[2], -reaction[2]],
                by_design: [-g[0], -g[1] - load[1] - reaction[1], -g[2], g[3], g[4]],
                rise: [link.rise.eps[0], link.rise.eps[1]],
                run: (link.run.re, [link.run.eps[0], link.run.eps[1]]),
            };
            if i == 0 {
                (row.by_state[0], row.by_design[0]) = (0.0, 0.0);
            }
            if i + 1 == n {
                (row.by_state[2], row.by_design[2]) = (0.0, 0.0);
            }
            row
        })
        .collect()
}

/// The state Jacobian `∂r/∂(θ, λ)` (bordered tridiagonal) from the joints' derivatives.
pub fn state_jacobian_of(rows: &[JointDerivatives]) -> BorderedTridiagonal {
    let n = rows.len();
    let mut jac = BorderedTridiagonal::zeros(n);
    for (i, row) in rows.iter().enumerate() {
        if i > 0 {
            jac.lower[i - 1] = row.by_state[0];
        }
        jac.diag[i] = row.by_state[1];
        if i + 1 < n {
            jac.upper[i] = row.by_state[2];
        }
        jac.column[i] = row.by_state[3];
        jac.row[i] = row.rise[0];
    }
    jac
}

/// `ψᵀ ∂[r; Φ]/∂(θ0, K)` for `ψ` of `N + 1` entries, contracted joint by joint from their
/// derivatives: `2N + 1` values, `θ0` first, then `K`.
pub fn design_transpose_mul(rows: &[JointDerivatives], psi: &[f64]) -> Vec<f64> {
    let n = rows.len();
    let mut out = vec![0.0; 2 * n + 1];
    for (i, row) in rows.iter().enumerate() {
        let p = psi[i];
        if i > 0 {
            out[i - 1] += p * row.by_design[0];
        }
        out[i] += p * row.by_design[1] + psi[n] * row.rise[1];
        if i + 1 < n {
            out[i + 1] += p * row.by_design[2];
        }
        out[n + i] += p * row.by_design[3];
        out[n + i + 1] += p * row.by_design[4];
    }
    out
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
