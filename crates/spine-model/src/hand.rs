//! Derivatives written by hand from the paper's Appendix I (eqs. (46)–(53)), corrected for the
//! link length `L_i = a_i / cos θ0_i` of Sec. 5 (errata E7). They are the reference that the AD
//! derivatives of [`crate::jacobian`] and [`crate::local`] are tested and benchmarked against.
//!
//! Notation (0-based): link `i` has `Δ_i = θ_i − θ0_i` (`Δ_{−1} = Δ_N = 0`), spring `j` joins
//! links `j−1` and `j` with stiffness `K_j`, `L'_i = dL_i/dθ0_i = L_i tan θ0_i`, and `V_i`, `A_i`
//! are the vertical and axial load resultants of eq. (48).

use crate::kinematics::link_length;
use crate::residual::joint_deflections;
use crate::sparse::BorderedTridiagonal;
use crate::{Design, LinkLoads, State};

fn deviation(design: &Design, state: &State, i: isize) -> f64 {
    let n = state.theta.len() as isize;
    if i < 0 || i >= n {
        0.0
    } else {
        state.theta[i as usize] - design.theta0[i as usize]
    }
}

/// `∂r/∂(θ, λ)`, the bordered tridiagonal matrix of eq. (46):
/// `[K_m − ∂P/∂θ − λ ∂∇Φ/∂θ, −∇Φ; ∇Φᵀ, 0]` with `K_m` of eq. (47) and `∂P/∂θ` of eq. (49):
/// diagonal `K_i + K_{i+1} + L_i (V_i sin θ_i + A_i cos θ_i) + λ L_i sin θ_i`, off-diagonals
/// `−K_{i+1}`, border column `−L_i cos θ_i`, border row `L_i cos θ_i`.
pub fn state_jacobian(spans: &[f64], design: &Design, loads: &LinkLoads, state: &State) -> BorderedTridiagonal {
    let n = spans.len();
    let k = &design.stiffness;
    let mut jac = BorderedTridiagonal::zeros(n);
    for i in 0..n {
        let length = link_length(spans[i], design.theta0[i]);
        jacobian_row(
            &mut jac,
            i,
            k,
            (loads.vertical[i], loads.axial[i]),
            state.lambda,
            length,
            state.theta[i].sin_cos(),
        );
    }
    jac
}

/// Row `i` of [`state_jacobian`] and its border entries, from `L_i` and `(sin θ_i, cos θ_i)`.
#[inline]
fn jacobian_row(
    jac: &mut BorderedTridiagonal,
    i: usize,
    k: &[f64],
    (vertical, axial): (f64, f64),
    lambda: f64,
    length: f64,
    (s, c): (f64, f64),
) {
    jac.diag[i] = k[i] + k[i + 1] + length * (vertical * s + axial * c) + lambda * length * s;
    if i + 1 < jac.block_size() {
        jac.upper[i] = -k[i + 1];
        jac.lower[i] = -k[i + 1];
    }
    jac.column[i] = -length * c;
    jac.row[i] = length * c;
}

/// The residual of eq. (5) and [`state_jacobian`] in one loop, written by hand: one `sin_cos` of
/// `θ_i` and one `L_i` per joint shared by `r_i`, its row and the border. The best hand code the
/// AD Jacobian ([`crate::jacobian::residual_and_state_jacobian`]) is benchmarked against
/// (`jacobian/hand_fused`); the residual is the same expression, to the bit.
pub fn residual_and_state_jacobian(
    spans: &[f64],
    design: &Design,
    loads: &LinkLoads,
    state: &State,
) -> (Vec<f64>, BorderedTridiagonal) {
    let n = spans.len();
    let k = &design.stiffness;
    let mut jac = BorderedTridiagonal::zeros(n);
    let mut r = Vec::with_capacity(n + 1);
    let mut phi = 0.0;
    for i in 0..n {
        let length = link_length(spans[i], design.theta0[i]);
        let (s, c) = state.theta[i].sin_cos();
        let [before, here, after] = joint_deflections(&state.theta, &design.theta0, i);
        let load = (c * loads.vertical[i] - s * loads.axial[i]) * length;
        r.push((here - before) * k[i] - (after - here) * k[i + 1] - load - state.lambda * length * c);
        phi += length * s;
        jacobian_row(&mut jac, i, k, (loads.vertical[i], loads.axial[i]), state.lambda, length, (s, c));
    }
    r.push(phi);
    (r, jac)
}

/// `ψᵀ ∂r/∂(θ0, K)` for a vector `ψ` of `N + 1` entries (joint rows, then the Φ row), without
/// forming the matrix: the right-hand sides of eq. (46) with the `θ0`-dependence of `L_i` added.
/// Returns `2N + 1` values, `θ0` first, then `K`.
///
/// Row `i`: `∂r_i/∂θ0_{i−1} = K_i`, `∂r_i/∂θ0_{i+1} = K_{i+1}`,
/// `∂r_i/∂θ0_i = −(K_i + K_{i+1}) − L'_i (V_i cos θ_i − A_i sin θ_i + λ cos θ_i)`,
/// `∂r_i/∂K_i = Δ_i − Δ_{i−1}`, `∂r_i/∂K_{i+1} = −(Δ_{i+1} − Δ_i)`; Φ row: `∂Φ/∂θ0_i = L'_i sin θ_i`.
pub fn design_jacobian_transpose_mul(
    spans: &[f64],
    design: &Design,
    loads: &LinkLoads,
    state: &State,
    psi: &[f64],
) -> Vec<f64> {
    let n = spans.len();
    let k = &design.stiffness;
    let row = |i: isize| if i >= 0 && (i as usize) < n { psi[i as usize] } else { 0.0 };
    let mut out = vec![0.0; 2 * n + 1];
    for i in 0..n {
        let length = link_length(spans[i], design.theta0[i]);
        let dlength = length * design.theta0[i].tan();
        let (s, c) = state.theta[i].sin_cos();
        let own = -(k[i] + k[i + 1]) - dlength * (loads.vertical[i] * c - loads.axial[i] * s + state.lambda * c);
        let ii = i as isize;
        out[i] = psi[i] * own + row(ii + 1) * k[i + 1] + row(ii - 1) * k[i] + psi[n] * dlength * s;
    }
    for j in 0..=n {
        let jj = j as isize;
        let rel = deviation(design, state, jj) - deviation(design, state, jj - 1);
        out[n + j] = (row(jj) - row(jj - 1)) * rel;
    }
    out
}

/// Partial derivatives of the stored energy `U(θ; θ0, K)` (eq. (38)):
/// `∂U/∂θ = K_m Δθ`, `∂U/∂θ0 = −K_m Δθ`, `∂U/∂K_j = ½ (Δ_j − Δ_{j−1})²`.
/// Returns `(∂U/∂θ, [∂U/∂θ0, ∂U/∂K])`.
pub fn strain_energy_partials(design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = state.theta.len();
    let k = &design.stiffness;
    let d = |i: isize| deviation(design, state, i);
    let km_delta: Vec<f64> =
        (0..n as isize).map(|i| k[i as usize] * (d(i) - d(i - 1)) - k[i as usize + 1] * (d(i + 1) - d(i))).collect();
    let mut by_design: Vec<f64> = km_delta.iter().map(|v| -v).collect();
    by_design.extend((0..=n as isize).map(|j| 0.5 * (d(j) - d(j - 1)).powi(2)));
    (km_delta, by_design)
}

/// Partial derivatives of the end position `X_{N+1}(θ; θ0) = Σ L_i cos θ_i` (eq. (40)):
/// `∂X/∂θ_i = −L_i sin θ_i`, `∂X/∂θ0_i = L'_i cos θ_i` (and zero for `K`). The paper's
/// `+Λ2 L_i sin θ0_i` of eqs. (24), (45) is the derivative of `−Σ L_i cos θ0_i` with `L_i` held
/// fixed; with `L_i = a_i / cos θ0_i` that sum is the constant `L_x` (errata E7).
/// Returns `(∂X/∂θ, [∂X/∂θ0, ∂X/∂K])`.
pub fn end_x_partials(spans: &[f64], design: &Design, state: &State) -> (Vec<f64>, Vec<f64>) {
    let n = spans.len();
    let mut by_state = Vec::with_capacity(n);
    let mut by_design = vec![0.0; 2 * n + 1];
    for i in 0..n {
        let length = link_length(spans[i], design.theta0[i]);
        let (s, c) = state.theta[i].sin_cos();
        by_state.push(-length * s);
        by_design[i] = length * design.theta0[i].tan() * c;
    }
    (by_state, by_design)
}
