//! Gradients of the reduced functions `J(θ0, K) = U(θ1(θ0, K); θ0, K)` and
//! `X(θ0, K) = X_{N+1}(θ2(θ0, K); θ0)` with respect to the design `d = (θ0, K)`, where the states
//! `u_s = (θ_s, λ_s)` solve the equilibrium `R_s(u_s, d) = 0` (paper Sec. 3, eqs. (22)–(24),
//! Appendices I and II).
//!
//! * [`adjoint_hand`]: the adjoint method with the paper's hand-derived derivatives
//!   ([`spine_model::hand`]): one transposed solve per function,
//!   `Aᵀψ = ∂F/∂u`, `dF/dd = ∂F/∂d − ψᵀ ∂R/∂d` (Appendix II chooses the multipliers `Λ` "to eliminate
//!   `∂θ/∂K`": that is `ψ`). O(N) per gradient.
//! * [`forward_ad`]: the direct method of eqs. (23), (24), (46) with the AD Jacobians: one solve
//!   `A ∂u/∂d_k = −∂R/∂d_k` per design variable, O(N²). It is the independent check of the
//!   adjoint (and what the paper's Appendix I literally writes).
//!
//! Both return `K`-gradients in physical units (per N·m/rad); multiply by `C_K` for `k = K / C_K`.

use crate::problem::DesignProblem;
use spine_model::jacobian::{design_jacobian, residual_and_state_jacobian};
use spine_model::{energy, hand, kinematics, Design, State};
use num_dual::Dual64;
use spine_solve::linalg::{BorderedLu, SingularMatrix};

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

fn with_zero_constraint_entry(mut v: Vec<f64>) -> Vec<f64> {
    v.push(0.0);
    v
}

/// The adjoint gradients from the hand-derived derivatives of Appendix I (corrected, errata E7).
pub fn adjoint_hand(problem: &DesignProblem, design: &Design, passive: &State, loaded: &State) -> Result<ReducedGradients, SingularMatrix> {
    let spans = &problem.chain.spans;
    let (passive_loads, total_loads) = (problem.passive_loads(), problem.total_loads());

    let (du_dtheta, mut energy_gradient) = hand::strain_energy_partials(design, passive);
    let a1 = BorderedLu::factor(&hand::state_jacobian(spans, design, &passive_loads, passive))?;
    let psi1 = a1.solve_transpose(&with_zero_constraint_entry(du_dtheta));
    let product = hand::design_jacobian_transpose_mul(spans, design, &passive_loads, passive, &psi1);
    for (g, p) in energy_gradient.iter_mut().zip(product) {
        *g -= p;
    }

    let (dx_dtheta, mut end_x_gradient) = hand::end_x_partials(spans, design, loaded);
    let a2 = BorderedLu::factor(&hand::state_jacobian(spans, design, &total_loads, loaded))?;
    let psi2 = a2.solve_transpose(&with_zero_constraint_entry(dx_dtheta));
    let product = hand::design_jacobian_transpose_mul(spans, design, &total_loads, loaded, &psi2);
    for (g, p) in end_x_gradient.iter_mut().zip(product) {
        *g -= p;
    }

    Ok(ReducedGradients {
        energy: energy::strain_energy(&passive.theta, &design.theta0, &design.stiffness),
        energy_gradient,
        end_x: kinematics::end_x(spans, &design.theta0, &loaded.theta),
        end_x_gradient,
    })
}

/// The direct (forward-sensitivity) gradients with the AD Jacobians: `∂u/∂d_k` for every design
/// variable `k`, then the chain rule. O(N²); a test oracle for [`adjoint_hand`].
pub fn forward_ad(problem: &DesignProblem, design: &Design, passive: &State, loaded: &State) -> Result<ReducedGradients, SingularMatrix> {
    let spans = &problem.chain.spans;
    let n = spans.len();
    let sensitivities = |loads, state: &State| -> Result<Vec<Vec<f64>>, SingularMatrix> {
        let (_, jac) = residual_and_state_jacobian(spans, design, loads, state);
        let lu = BorderedLu::factor(&jac)?;
        let dr_dd = design_jacobian(spans, design, loads, state).to_dense();
        Ok((0..2 * n + 1)
            .map(|k| {
                let column: Vec<f64> = dr_dd.iter().map(|row| -row[k]).collect();
                lu.solve(&column)
            })
            .collect())
    };
    let (passive_loads, total_loads) = (problem.passive_loads(), problem.total_loads());
    let s1 = sensitivities(&passive_loads, passive)?;
    let s2 = sensitivities(&total_loads, loaded)?;
    let (du_dtheta, du_ddesign) = energy_partials_ad(design, passive);
    let (dx_dtheta, dx_ddesign) = end_partials_ad(spans, design, loaded);
    let chain = |partial_state: &[f64], partial_design: &[f64], s: &[Vec<f64>]| -> Vec<f64> {
        (0..2 * n + 1)
            .map(|k| partial_design[k] + partial_state.iter().zip(&s[k]).map(|(a, b)| a * b).sum::<f64>())
            .collect()
    };
    Ok(ReducedGradients {
        energy: energy::strain_energy(&passive.theta, &design.theta0, &design.stiffness),
        energy_gradient: chain(&du_dtheta, &du_ddesign, &s1),
        end_x: kinematics::end_x(spans, &design.theta0, &loaded.theta),
        end_x_gradient: chain(&dx_dtheta, &dx_ddesign, &s2),
    })
}

/// The gradient of `f` at `values` by forward AD, one `Dual64` pass per entry (O(N²) for the
/// functions here; test oracle only).
fn dual_gradient(values: &[f64], f: impl Fn(&[Dual64]) -> Dual64) -> Vec<f64> {
    (0..values.len())
        .map(|k| {
            let v: Vec<Dual64> =
                values.iter().enumerate().map(|(i, &x)| if i == k { Dual64::from(x).derivative() } else { Dual64::from(x) }).collect();
            f(&v).eps
        })
        .collect()
}

/// `∂U/∂θ` and `∂U/∂(θ0, K)` by forward AD of [`energy::strain_energy`].
fn energy_partials_ad(design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.theta.len();
    let all: Vec<f64> = state.theta.iter().chain(&design.theta0).chain(&design.stiffness).copied().collect();
    let grad = dual_gradient(&all, |v| energy::strain_energy(&v[..n], &v[n..2 * n], &v[2 * n..]));
    (grad[..n].to_vec(), grad[n..].to_vec())
}

/// `∂X/∂θ` and `∂X/∂(θ0, K)` by forward AD of [`kinematics::end_x`].
fn end_partials_ad(spans: &[f64], design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.theta.len();
    let all: Vec<f64> = state.theta.iter().chain(&design.theta0).copied().collect();
    let grad = dual_gradient(&all, |v| kinematics::end_x(spans, &v[n..], &v[..n]));
    let mut by_design = grad[n..].to_vec();
    by_design.extend(std::iter::repeat_n(0.0, n + 1));
    (grad[..n].to_vec(), by_design)
}
