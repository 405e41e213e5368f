//! Gradients of the reduced functions `J(θ0, K) = U(θ1(θ0, K); θ0, K)` and
//! `X(θ0, K) = X_{N+1}(θ2(θ0, K); θ0)` with respect to the design `d = (θ0, K)`, where the states
//! `u_s = (θ_s, λ_s)` solve the equilibrium `R_s(u_s, d) = 0` (paper Sec. 3, eqs. (22)–(24),
//! Appendices I and II).
//!
//! * [`adjoint_hand`]: the adjoint method with the paper's hand-derived derivatives
//!   ([`spine_model::hand`]): one transposed solve per function, `Aᵀψ = ∂F/∂u`,
//!   `dF/dd = ∂F/∂d − ψᵀ ∂R/∂d` (Appendix II chooses the multipliers `Λ` "to eliminate `∂θ/∂K`":
//!   that is `ψ`). O(N) per gradient.
//! * [`adjoint_ad`]: the same implicit-function-theorem adjoint through the equilibrium (the KKT
//!   system of `U + V` under `Φ = 0`), with every partial derivative from forward AD: the sparse
//!   AD Jacobians of [`spine_model::jacobian`] and the element gradients of
//!   [`spine_model::local`]. O(N); nothing written by hand but the chain rule.
//! * [`forward_ad`]: the direct method of eqs. (23), (24), (46) with the AD Jacobians: one solve
//!   `A ∂u/∂d_k = −∂R/∂d_k` per design variable, O(N²). It is what the paper's Appendix I
//!   literally writes, and an independent check of the adjoints.
//! * [`central_differences`]: both equilibria re-solved at `d ± h e_k` for every `k`; O(N²).
//!
//! All return `K`-gradients in physical units (per N·m/rad); multiply by `C_K` for `k = K / C_K`.

use crate::problem::DesignProblem;
use spine_model::chain::spring_links;
use spine_model::jacobian::{design_transpose_mul, joint_derivatives, state_jacobian_of, JointDerivatives};
#[cfg(any(test, feature = "testing"))]
use spine_model::local::LinkRun;
use spine_model::local::{self, SpringEnergy};
use spine_model::sparse::BorderedTridiagonal;
use spine_model::{energy, hand, kinematics, Design, LinkLoads, State};
use spine_solve::linalg::{BorderedLu, SingularMatrix};
#[cfg(any(test, feature = "testing"))]
use spine_solve::ContinuationOptions;

/// Values and design gradients of the two reduced functions.
#[derive(Clone, Debug, PartialEq)]
pub struct ReducedGradients {
    /// `J = U(θ1)`, J.
    pub energy: f64,
    /// `dJ/d(θ0, K)`, `2N + 1` entries.
    pub energy_gradient: Vec<f64>,
    /// `X_{N+1}(θ2)`, m.
    pub end_x: f64,
    /// `dX_{N+1}/d(θ0, K)`, `2N + 1` entries.
    pub end_x_gradient: Vec<f64>,
}

impl ReducedGradients {
    fn at(
        problem: &DesignProblem,
        design: &Design,
        passive: &State,
        loaded: &State,
        energy_gradient: Vec<f64>,
        end_x_gradient: Vec<f64>,
    ) -> Self {
        ReducedGradients {
            energy: energy::strain_energy(&passive.theta, &design.theta0, &design.stiffness),
            energy_gradient,
            end_x: kinematics::end_x(&problem.structure.chain.spans, &design.theta0, &loaded.theta),
            end_x_gradient,
        }
    }
}

/// One adjoint gradient: `Aᵀψ = [∂F/∂θ; 0]` (the function does not depend on `λ`), then
/// `dF/dd = ∂F/∂d − ψᵀ ∂R/∂d`, with `ψᵀ ∂R/∂d` given by `design_product(ψ)`.
fn adjoint_gradient(
    state_jacobian: &BorderedTridiagonal,
    mut partial_state: Vec<f64>,
    mut partial_design: Vec<f64>,
    design_product: impl FnOnce(&[f64]) -> Vec<f64>,
) -> Result<Vec<f64>, SingularMatrix> {
    partial_state.push(0.0);
    let psi = BorderedLu::factor(state_jacobian)?.solve_transpose(&partial_state);
    for (g, p) in partial_design.iter_mut().zip(design_product(&psi)) {
        *g -= p;
    }
    Ok(partial_design)
}

/// The adjoint gradients from the hand-derived derivatives of Appendix I (corrected, errata E7).
pub fn adjoint_hand(
    problem: &DesignProblem,
    design: &Design,
    passive: &State,
    loaded: &State,
) -> Result<ReducedGradients, SingularMatrix> {
    let spans = &problem.structure.chain.spans;
    let hand_adjoint = |loads: &LinkLoads, state: &State, (by_state, by_design): (Vec<f64>, Vec<f64>)| {
        let a = hand::state_jacobian(spans, design, loads, state);
        adjoint_gradient(&a, by_state, by_design, |psi| {
            hand::design_jacobian_transpose_mul(spans, design, loads, state, psi)
        })
    };
    let energy_gradient =
        hand_adjoint(&problem.passive_loads(), passive, hand::strain_energy_partials(design, passive))?;
    let end_x_gradient = hand_adjoint(&problem.total_loads(), loaded, hand::end_x_partials(spans, design, loaded))?;
    Ok(ReducedGradients::at(problem, design, passive, loaded, energy_gradient, end_x_gradient))
}

/// The adjoint gradients with every partial derivative from forward AD (see the module docs):
/// one pass per joint and state ([`joint_derivatives`]) gives the state Jacobian, the design
/// partials kept per joint and, for the loaded state, `∂X/∂(θ, θ0)`; the adjoint is contracted
/// with the design partials joint by joint.
pub fn adjoint_ad(
    problem: &DesignProblem,
    design: &Design,
    passive: &State,
    loaded: &State,
) -> Result<ReducedGradients, SingularMatrix> {
    let spans = &problem.structure.chain.spans;
    let n = spans.len();
    let ad_adjoint = |rows: &[JointDerivatives], (by_state, by_design): (Vec<f64>, Vec<f64>)| {
        adjoint_gradient(&state_jacobian_of(rows), by_state, by_design, |psi| design_transpose_mul(rows, psi))
    };
    let rows = joint_derivatives(spans, design, &problem.passive_loads(), passive);
    let energy_gradient = ad_adjoint(&rows, energy_partials_ad(design, passive))?;
    let rows = joint_derivatives(spans, design, &problem.total_loads(), loaded);
    let mut end_x_partials = (vec![0.0; n], vec![0.0; 2 * n + 1]);
    for (i, row) in rows.iter().enumerate() {
        (end_x_partials.0[i], end_x_partials.1[i]) = (row.run.1[0], row.run.1[1]);
    }
    let end_x_gradient = ad_adjoint(&rows, end_x_partials)?;
    Ok(ReducedGradients::at(problem, design, passive, loaded, energy_gradient, end_x_gradient))
}

/// The direct (forward-sensitivity) gradients with the AD Jacobians: `∂u/∂d_k` for every design
/// variable `k`, then the chain rule. O(N²); a test oracle for the adjoints (feature `testing`).
#[cfg(any(test, feature = "testing"))]
pub fn forward_ad(
    problem: &DesignProblem,
    design: &Design,
    passive: &State,
    loaded: &State,
) -> Result<ReducedGradients, SingularMatrix> {
    use spine_model::jacobian::{design_jacobian, residual_and_state_jacobian};
    let spans = &problem.structure.chain.spans;
    let n = spans.len();
    let direct = |loads: &LinkLoads,
                  state: &State,
                  (by_state, by_design): (Vec<f64>, Vec<f64>)|
     -> Result<Vec<f64>, SingularMatrix> {
        let (_, jac) = residual_and_state_jacobian(spans, design, loads, state);
        let lu = BorderedLu::factor(&jac)?;
        let mut columns = vec![vec![0.0; n + 1]; 2 * n + 1];
        for &(r, c, v) in &design_jacobian(spans, design, loads, state).entries {
            columns[c][r] -= v;
        }
        Ok((0..2 * n + 1)
            .map(|k| by_design[k] + by_state.iter().zip(lu.solve(&columns[k])).map(|(a, b)| a * b).sum::<f64>())
            .collect())
    };
    let energy_gradient = direct(&problem.passive_loads(), passive, energy_partials_ad(design, passive))?;
    let end_x_gradient = direct(&problem.total_loads(), loaded, end_partials_ad(spans, design, loaded))?;
    Ok(ReducedGradients::at(problem, design, passive, loaded, energy_gradient, end_x_gradient))
}

/// The gradients by central differences: for each design variable `d_k`, both equilibria are
/// re-solved by Newton at `d ± h e_k` (from `passive` and `loaded`, which must be the equilibria at
/// `design`), `h = step · max(1, |d_k|)`. `None` when a re-solve fails. O(N²); a test oracle
/// (feature `testing`).
#[cfg(any(test, feature = "testing"))]
pub fn central_differences(
    problem: &DesignProblem,
    design: &Design,
    passive: &State,
    loaded: &State,
    step: f64,
    continuation: &ContinuationOptions,
) -> Option<ReducedGradients> {
    let n = problem.n_links();
    let spans = &problem.structure.chain.spans;
    let mut energy_gradient = Vec::with_capacity(2 * n + 1);
    let mut end_x_gradient = Vec::with_capacity(2 * n + 1);
    for k in 0..2 * n + 1 {
        let value = if k < n { design.theta0[k] } else { design.stiffness[k - n] };
        let h = step * value.abs().max(1.0);
        let at = |v: f64| -> Option<(f64, f64)> {
            let mut moved = design.clone();
            if k < n {
                moved.theta0[k] = v;
            } else {
                moved.stiffness[k - n] = v;
            }
            let (p, l) = problem.equilibria_near(&moved, passive, loaded, continuation)?;
            Some((
                energy::strain_energy(&p.theta, &moved.theta0, &moved.stiffness),
                kinematics::end_x(spans, &moved.theta0, &l.theta),
            ))
        };
        let (jp, xp) = at(value + h)?;
        let (jm, xm) = at(value - h)?;
        energy_gradient.push((jp - jm) / (2.0 * h));
        end_x_gradient.push((xp - xm) / (2.0 * h));
    }
    Some(ReducedGradients::at(problem, design, passive, loaded, energy_gradient, end_x_gradient))
}

/// `∂U/∂θ` and `∂U/∂(θ0, K)` from the AD gradients of the spring elements (eq. (31)), O(N).
fn energy_partials_ad(design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.theta.len();
    let spring = SpringEnergy { stiffness_scale: 1.0 };
    let (mut by_state, mut by_design) = (vec![0.0; n], vec![0.0; 2 * n + 1]);
    for j in 0..=n {
        let (prev, this) = spring_links(n, j);
        let pick = |v: &[f64], i: Option<usize>| i.map_or(0.0, |i| v[i]);
        let x = [
            pick(&state.theta, prev),
            pick(&design.theta0, prev),
            pick(&state.theta, this),
            pick(&design.theta0, this),
            design.stiffness[j],
        ];
        let (_, g) = local::gradient(&spring, &x);
        for (i, (d_theta, d_theta0)) in [(prev, (g[0], g[1])), (this, (g[2], g[3]))] {
            if let Some(i) = i {
                by_state[i] += d_theta;
                by_design[i] += d_theta0;
            }
        }
        by_design[n + j] += g[4];
    }
    (by_state, by_design)
}

/// `∂X/∂θ` and `∂X/∂(θ0, K)` from the AD gradients of the link runs `L_i cos θ_i`, O(N) (the
/// direct method's; the adjoint takes them from its joint pass).
#[cfg(any(test, feature = "testing"))]
fn end_partials_ad(spans: &[f64], design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.theta.len();
    let (mut by_state, mut by_design) = (vec![0.0; n], vec![0.0; 2 * n + 1]);
    for i in 0..n {
        let (_, g) =
            local::gradient(&LinkRun { span: spans[i], deflection: false }, &[state.theta[i], design.theta0[i]]);
        by_state[i] = g[0];
        by_design[i] = g[1];
    }
    (by_state, by_design)
}
