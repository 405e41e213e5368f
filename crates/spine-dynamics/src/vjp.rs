//! The accelerations' vector–Jacobian products `uᵀ ∂θ̈/∂θ`, `uᵀ ∂θ̈/∂θ̇` and `uᵀ ∂θ̈/∂p` (springs or
//! dampers) in `O(N)` each: what the discrete adjoint of the integrator needs at every stage
//! point ([`crate::integrator::adjoint`]), where the dense rates of [`crate::rates`] cost `O(N²)`.
//!
//! [`crate::rates`] writes every column as the bordered solve `∂θ̈/∂x_k = W dQ_k + M⁻¹∇Φ db_k /
//! (∇Φᵀ M⁻¹∇Φ)` with `W = M⁻¹ − M⁻¹∇Φ ∇Φᵀ M⁻¹ / (∇Φᵀ M⁻¹ ∇Φ)` (symmetric). So
//!
//! `uᵀ ∂θ̈/∂x_k = ξᵀ dQ_k + β db_k`, `ξ = W u`, `β = ∇Φᵀ M⁻¹ u / (∇Φᵀ M⁻¹ ∇Φ)`,
//!
//! one solve with `M` for all `k`. The columns' `dQ_k` (module docs of [`crate::rates`]) are local
//! but for the coupling of the mass matrix and the centrifugal terms, `c_ik = L_i L_k μ_max(i,k)`
//! times `cos(θ_i − θ_k)` or `sin(θ_i − θ_k)`; their contractions with `ξ`, `θ̇²` and `θ̈` are the
//! products `Ĉ x` and `Ŝ x` (`Ĉ_ki = c_ik cos(θ_i − θ_k)`, `Ŝ_ki = c_ik sin(θ_i − θ_k)`), `O(N)`
//! by prefix and suffix sums. Per angle `k`:
//!
//! `θ̇_k² (Ĉξ)_k − θ̈_k (Ŝξ)_k − ξ_k ((Ĉθ̇²)_k + (Ŝθ̈)_k) + ξ_k L_k (−sin θ_k V_k − cos θ_k X_k)
//! − (K_m ξ)_k − ξ_k L_k sin θ_k λ + β L_k (cos θ_k θ̇_k² + sin θ_k θ̈_k)`;
//!
//! per angular velocity `k`: `−(C_m ξ)_k − 2 θ̇_k (Ŝξ)_k + 2 β L_k sin θ_k θ̇_k`; per spring or
//! damper `k`: `r_k (ξ_{k−1} − ξ_k)` with the joint's relative deflection or rate `r_k`. The tests
//! hold all three to the transposed dense rates.

use crate::articulated::ArticulatedChain;
use crate::eom::Dynamics;
use crate::parameters::Parameters;
use crate::rates::Factored;
use std::cell::RefCell;

/// One state `(t, θ, θ̇)` prepared for any number of products (module docs); it borrows the
/// chain's lengths, springs and dampers from its [`Dynamics`].
pub struct AccelerationAdjoint<'a> {
    lengths: &'a [f64],
    /// `μ_j = ½ m_j + Σ_{k>j} m_k`, kg.
    coupling: Vec<f64>,
    trig: Vec<(f64, f64)>,
    omega: Vec<f64>,
    acc: Vec<f64>,
    chain: ArticulatedChain<f64>,
    mg: Vec<f64>,
    gmg: f64,
    /// The per-angle part that does not depend on `ξ`: `−(Ĉθ̇²)_k − (Ŝθ̈)_k + L_k (−sin θ_k V_k −
    /// cos θ_k X_k) − L_k sin θ_k λ` (multiplies `ξ_k`).
    own: Vec<f64>,
    stiffness: &'a [f64],
    damping: &'a [f64],
    /// The parameters' relative motions `r_k` (none without parameters).
    relative: Vec<f64>,
    /// `ξ`, `Ĉξ`, `Ŝξ` of the last product (kept, so that the products allocate nothing).
    scratch: RefCell<[Vec<f64>; 3]>,
}

/// `(Ĉ x, Ŝ x)` (module docs) in `O(N)`, into `c` and `s`: for `i < k` the coupling is `μ_k`, for `i > k` it is `μ_i`.
fn coupled_into(lengths: &[f64], coupling: &[f64], trig: &[(f64, f64)], x: &[f64], c: &mut [f64], s: &mut [f64]) {
    let n = x.len();
    // Suffix sums Σ_{i>k} μ_i L_i x_i (cos θ_i, sin θ_i).
    let mut after = (0.0, 0.0);
    for k in (0..n).rev() {
        let (sk, ck) = trig[k];
        let lk = lengths[k];
        c[k] = lk * (ck * after.0 + sk * after.1);
        s[k] = lk * (ck * after.1 - sk * after.0);
        let w = coupling[k] * lk * x[k];
        after = (after.0 + w * ck, after.1 + w * sk);
    }
    // Prefix sums Σ_{i<k} L_i x_i (cos θ_i, sin θ_i), times μ_k, and the diagonal `c_kk x_k`.
    let mut before = (0.0, 0.0);
    for k in 0..n {
        let (sk, ck) = trig[k];
        let (lk, mu) = (lengths[k], coupling[k]);
        c[k] += mu * lk * (ck * before.0 + sk * before.1) + lk * lk * mu * x[k];
        s[k] += mu * lk * (ck * before.1 - sk * before.0);
        before = (before.0 + lk * x[k] * ck, before.1 + lk * x[k] * sk);
    }
}

impl Dynamics {
    /// The state `y = (θ, θ̇)` at `(t, piece)` prepared for [`AccelerationAdjoint::products`] with
    /// the rates in `parameters`; `None` where `M(θ)` has no factorisation.
    pub fn acceleration_adjoint(
        &self,
        t: f64,
        piece: f64,
        y: &[f64],
        parameters: Parameters,
    ) -> Option<AccelerationAdjoint<'_>> {
        let n = self.n_links();
        let (theta, omega) = y.split_at(n);
        let loads = self.loads_at(t, piece);
        let at = self.rates_at(theta, omega);
        let (acc, lambda) = at.state_acceleration(&loads)?;
        let Factored { trig, chain, mg, gmg } = at.into_factored()?;
        let coupling = crate::eom::coupling_coefficients(&self.masses);
        // The per-angle part that does not depend on `ξ`, formed in the products' own scratch.
        let mut scratch: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
        let [input, c, s] = &mut scratch;
        input.iter_mut().zip(omega).for_each(|(x, w)| *x = w * w);
        coupled_into(&self.lengths, &coupling, &trig, input, c, s);
        let mut own: Vec<f64> = (0..n)
            .map(|k| {
                let (sk, ck) = trig[k];
                let lk = self.lengths[k];
                -c[k] + lk * (-sk * loads.vertical[k] - ck * loads.axial[k]) - lk * sk * lambda
            })
            .collect();
        coupled_into(&self.lengths, &coupling, &trig, &acc, c, s);
        own.iter_mut().zip(s.iter()).for_each(|(o, s_acc)| *o -= s_acc);
        let x: Vec<f64> = match parameters {
            Parameters::None => Vec::new(),
            Parameters::Springs => theta.iter().zip(&self.theta0).map(|(a, b)| a - b).collect(),
            Parameters::Dampers => omega.to_vec(),
        };
        let at = |i: isize| if i < 0 || i as usize >= n { 0.0 } else { x[i as usize] };
        let relative = if x.is_empty() { Vec::new() } else { (0..=n as isize).map(|k| at(k) - at(k - 1)).collect() };
        Some(AccelerationAdjoint {
            lengths: &self.lengths,
            coupling,
            trig,
            omega: omega.to_vec(),
            acc,
            chain,
            mg,
            gmg,
            own,
            stiffness: &self.stiffness,
            damping: &self.damping,
            relative,
            scratch: RefCell::new(scratch),
        })
    }
}

impl AccelerationAdjoint<'_> {
    /// The number of parameters of [`Self::products_into`]'s third output.
    pub fn n_params(&self) -> usize {
        self.relative.len()
    }

    /// `(uᵀ ∂θ̈/∂θ, uᵀ ∂θ̈/∂θ̇, uᵀ ∂θ̈/∂p)` (module docs).
    pub fn products(&self, u: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let n = u.len();
        let (mut angles, mut velocities, mut params) = (vec![0.0; n], vec![0.0; n], vec![0.0; self.n_params()]);
        self.products_into(u, &mut angles, &mut velocities, &mut params);
        (angles, velocities, params)
    }

    /// [`Self::products`] into `angles`, `velocities` (`N` each) and `params`
    /// ([`Self::n_params`]).
    pub fn products_into(&self, u: &[f64], angles: &mut [f64], velocities: &mut [f64], params: &mut [f64]) {
        let n = u.len();
        let mut scratch = self.scratch.borrow_mut();
        let [xi, c_xi, s_xi] = &mut *scratch;
        xi.copy_from_slice(u);
        self.chain.solve_in_place([xi.as_mut_slice()]);
        let beta = self.mg.iter().zip(u).map(|(a, b)| a * b).sum::<f64>() / self.gmg;
        for (x, m) in xi.iter_mut().zip(&self.mg) {
            *x -= beta * m;
        }
        coupled_into(self.lengths, &self.coupling, &self.trig, xi, c_xi, s_xi);
        let at = |i: isize| if i < 0 || i as usize >= n { 0.0 } else { xi[i as usize] };
        // `(K_m ξ)_k` and `(C_m ξ)_k` ([`joint_moments`]) from the joints' relative `ξ`.
        let moment = |c: &[f64], k: usize| {
            let k = k as isize;
            c[k as usize] * (at(k) - at(k - 1)) - c[k as usize + 1] * (at(k + 1) - at(k))
        };
        for k in 0..n {
            let (sk, ck) = self.trig[k];
            let (lk, wk, ak) = (self.lengths[k], self.omega[k], self.acc[k]);
            angles[k] = wk * wk * c_xi[k] - ak * s_xi[k] + xi[k] * self.own[k] - moment(self.stiffness, k)
                + beta * lk * (ck * wk * wk + sk * ak);
            velocities[k] = -moment(self.damping, k) - 2.0 * wk * s_xi[k] + 2.0 * beta * lk * sk * wk;
        }
        for (k, (p, r)) in params.iter_mut().zip(&self.relative).enumerate() {
            *p = r * (at(k as isize - 1) - at(k as isize));
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::fixtures::arch_problem;
    use crate::integrator::{integrate, Extras, Options};
    use crate::ode::OdeSystem;
    use crate::{Forcing, Parameters, SpineOde};

    /// In motion (the step response after 30 ms, every term of the accelerations at work), the
    /// products equal the transposed dense rates (`∂f/∂y` and `∂f/∂p` of [`SpineOde`], themselves
    /// held to dual passes) for springs and dampers.
    #[test]
    fn the_products_are_the_transposed_rates() {
        for n in [1, 2, 5, 12] {
            let problem = arch_problem(n, 30.0);
            let ends = problem.static_ends(&Default::default()).unwrap();
            let d = problem.dynamics(Forcing::Step);
            let plain = SpineOde { dynamics: &d, parameters: Parameters::None };
            let run = integrate(&plain, 0.0, &ends.rest_state(), 0.03, &Options::default(), Extras::default());
            let y = run.end().to_vec();
            for parameters in [Parameters::Springs, Parameters::Dampers] {
                let ode = SpineOde { dynamics: &d, parameters };
                let (jac, params) = ode.jacobian_and_params(0.03, 0.03, &y);
                let at = d.acceleration_adjoint(0.03, 0.03, &y, parameters).unwrap();
                let u: Vec<f64> = (0..n).map(|i| ((i as f64 + 1.0) * 0.77).sin()).collect();
                let (angles, velocities, p) = at.products(&u);
                let got: Vec<f64> = angles.iter().chain(&velocities).chain(&p).copied().collect();
                let want: Vec<f64> = (0..2 * n)
                    .map(|c| (0..n).map(|r| u[r] * jac[(n + r, c)]).sum())
                    .chain((0..params.ncols()).map(|c| (0..n).map(|r| u[r] * params[(n + r, c)]).sum()))
                    .collect();
                // A single link cannot move (all rates 0): its products are round-off.
                let scale = want.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for (i, (a, b)) in got.iter().zip(&want).enumerate() {
                    assert!((a - b).abs() <= 1e-10 * scale, "N = {n} {parameters:?} [{i}]: {a:e} vs {b:e}");
                }
            }
        }
    }
}
