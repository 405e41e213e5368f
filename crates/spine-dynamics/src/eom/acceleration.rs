//! The accelerations of eq. (6) in index-1 form: `Q`, `∇Φ` and the `Φ̈ = 0` row, then `θ̈` and `λ`
//! from the bordered system, by the `O(N)` articulated-body recursion or, as the test oracle,
//! through the dense mass matrix.

use super::{Dynamics, LoadsAt, Scratch};
use crate::cholesky::{chol_solve, cholesky};
use spine_model::{LinkLoads, Scalar};

impl Dynamics {
    /// The index-1 form's parts at `(θ, θ̇)` given the centrifugal terms `h`: `Q = P − h − C_m θ̇ −
    /// K_m (θ − θ0)` (N·m), `∇Φ` (m) and `Σ L_i sin θ_i θ̇_i²` (m/s², the `Φ̈ = 0` row).
    /// `h` is overwritten with `Q`.
    pub(crate) fn index1_terms<D: Scalar>(
        &self,
        loads: LoadsAt<'_>,
        theta_trig: (&[D], &[(D, D)]),
        omega: &[D],
        damping: &[D],
        mut h: Vec<D>,
    ) -> (Vec<D>, Vec<D>, D) {
        let mut g = Vec::new();
        let b = self.index1_terms_into(loads, theta_trig, omega, damping, &mut h, &mut g);
        (h, g, b)
    }

    /// [`Self::index1_terms`] in place: `h` overwritten with `Q`, `∇Φ` into `g`; returns the
    /// `Φ̈ = 0` row's right-hand side.
    pub(super) fn index1_terms_into<D: Scalar>(
        &self,
        loads: LoadsAt<'_>,
        (theta, trig): (&[D], &[(D, D)]),
        omega: &[D],
        damping: &[D],
        h: &mut [D],
        g: &mut Vec<D>,
    ) -> D {
        let n = self.n_links();
        // The springs' and dampers' joint moments ([`joint_moments`], term by term in its order,
        // without its intermediate vectors).
        let zero = D::from(0.0);
        let delta = |i: usize| if i < n { theta[i] - self.theta0[i] } else { zero };
        let rate = |i: usize| if i < n { omega[i] } else { zero };
        let moment = |c: D, c_next: D, x: &dyn Fn(usize) -> D, i: usize| {
            let before = if i == 0 { zero } else { x(i - 1) };
            c * (x(i) - before) - c_next * (x(i + 1) - x(i))
        };
        let l = &self.lengths;
        // P_i (eq. (48)), Q, ∇Φ_i = L_i cos θ_i and Σ L_i sin θ_i θ̇_i², from one sin/cos per link.
        for (i, q) in h.iter_mut().enumerate() {
            let (s, c) = trig[i];
            let (vertical, axial) = loads.at(i);
            let p = (c * vertical - s * axial) * l[i];
            let spring = moment(D::from(self.stiffness[i]), D::from(self.stiffness[i + 1]), &delta, i);
            let damper = moment(damping[i], damping[i + 1], &rate, i);
            *q = p - *q - damper - spring;
        }
        g.clear();
        g.extend((0..n).map(|i| trig[i].1 * l[i]));
        (0..n).map(|i| trig[i].0 * omega[i] * omega[i] * l[i]).sum()
    }

    /// Accelerations `θ̈` (rad/s²) and reaction `λ` (N) at `(t, θ, θ̇)` with dampers `damping`, from
    /// the index-1 form: `[M −∇Φ; ∇Φᵀ 0] [θ̈; λ] = [Q; Σ L_i sin θ_i θ̇_i²]` with
    /// `Q = P − h − C_m θ̇ − K_m (θ − θ0)` (the second row is `Φ̈ = 0`), in `O(N)`: `M⁻¹Q` and `M⁻¹∇Φ`
    /// by the articulated-body recursion (`ArticulatedChain`, one factorisation for both), then
    /// `λ = (b − ∇Φᵀ M⁻¹ Q) / (∇Φᵀ M⁻¹ ∇Φ)`. [`Self::acceleration_dense`] is the dense reference.
    pub fn acceleration<D: Scalar>(&self, loads: &LinkLoads, theta: &[D], omega: &[D], damping: &[D]) -> (Vec<D>, D) {
        self.acceleration_at(LoadsAt::Given(loads), theta, omega, damping)
    }

    /// [`Self::acceleration`] with the loads given as [`LoadsAt`].
    pub(super) fn acceleration_at<D: Scalar>(
        &self,
        loads: LoadsAt<'_>,
        theta: &[D],
        omega: &[D],
        damping: &[D],
    ) -> (Vec<D>, D) {
        let mut acc = vec![D::zero(); self.n_links()];
        let lambda = self.acceleration_into(loads, theta, omega, damping, &mut acc, &mut Scratch::default());
        (acc, lambda)
    }

    /// [`Self::acceleration_at`] with `θ̈` into `acc`, the intermediate vectors in `scratch`;
    /// returns `λ`.
    pub(super) fn acceleration_into<D: Scalar>(
        &self,
        loads: LoadsAt<'_>,
        theta: &[D],
        omega: &[D],
        damping: &[D],
        acc: &mut [D],
        scratch: &mut Scratch<D>,
    ) -> D {
        let Scratch { trig, tip, q, g, mg, chain } = scratch;
        trig.clear();
        trig.extend(theta.iter().map(|t| t.sin_cos()));
        self.velocity_terms_into(trig, omega, tip, q);
        let b = self.index1_terms_into(loads, (theta, trig), omega, damping, q, g);
        // M is positive definite for links with mass; a non-finite trial state (a diverging Newton
        // iterate) gives NaN accelerations, which the integrator rejects.
        if !chain.refactor_from_trig(&self.lengths, &self.masses, trig) {
            acc.fill(D::from(f64::NAN));
            return D::from(f64::NAN);
        }
        // M⁻¹Q and M⁻¹∇Φ in one pair of sweeps.
        acc.copy_from_slice(q);
        mg.clear();
        mg.extend_from_slice(g);
        chain.solve_in_place([&mut *acc, mg]);
        bordered_in_place(acc, mg, g, b)
    }

    /// [`Self::acceleration`] through the dense mass matrix ([`Self::mass_matrix`], Cholesky) and
    /// the `O(N²)` centrifugal sum: `O(N³)`, the test oracle of the recursion.
    pub fn acceleration_dense<D: Scalar>(
        &self,
        loads: &LinkLoads,
        theta: &[D],
        omega: &[D],
        damping: &[D],
    ) -> (Vec<D>, D) {
        let h = self.velocity_terms_dense(theta, omega);
        let trig: Vec<(D, D)> = theta.iter().map(|t| t.sin_cos()).collect();
        let (q, g, b) = self.index1_terms(LoadsAt::Given(loads), (theta, &trig), omega, damping, h);
        let Some(chol) = cholesky(self.mass_matrix(theta)) else {
            return nan_accelerations(self.n_links());
        };
        bordered(chol_solve(&chol, &q), &chol_solve(&chol, &g), &g, b)
    }
}

/// NaN accelerations and reaction: what a state without a regular mass matrix gives.
pub(super) fn nan_accelerations<D: Scalar>(n: usize) -> (Vec<D>, D) {
    (vec![D::from(f64::NAN); n], D::from(f64::NAN))
}

/// `θ̈ = M⁻¹Q + λ M⁻¹∇Φ` with `λ = (b − ∇Φᵀ M⁻¹Q) / (∇Φᵀ M⁻¹∇Φ)` (the Schur complement of the
/// bordered system), from `mq = M⁻¹Q` (overwritten with `θ̈`) and `mg = M⁻¹∇Φ`.
pub(crate) fn bordered<D: Scalar>(mut mq: Vec<D>, mg: &[D], g: &[D], b: D) -> (Vec<D>, D) {
    let lambda = bordered_in_place(&mut mq, mg, g, b);
    (mq, lambda)
}

/// [`bordered`] in place; returns `λ`.
fn bordered_in_place<D: Scalar>(mq: &mut [D], mg: &[D], g: &[D], b: D) -> D {
    let gmq: D = g.iter().zip(mq.iter()).map(|(&a, &c)| a * c).sum();
    let gmg: D = g.iter().zip(mg).map(|(&a, &c)| a * c).sum();
    let lambda = (b - gmq) / gmg;
    for (x, &m) in mq.iter_mut().zip(mg) {
        *x += m * lambda;
    }
    lambda
}
