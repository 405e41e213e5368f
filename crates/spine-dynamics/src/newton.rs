//! The Newton matrix `σ I − J̃` of the implicit integrator for the chain, factored and solved in
//! `O(N)` for real and complex shifts `σ` (s⁻¹).
//!
//! **Choice: a structured approximate Jacobian, not Newton–Krylov.** With `y = (θ, θ̇)` and
//! `θ̈ = a(θ, θ̇)` from `M a = Q + λ ∇Φ`, `∇Φᵀ a = b`, the Jacobian's stiff part is that of the springs,
//! the dampers and the loads: `J̃ = [[0, I], [−W K̃, −W C_m]]`, where `W` is the constrained inverse
//! of `M` (`w = W v` solves `M w − μ ∇Φ = v`, `∇Φᵀ w = 0`), `C_m` the damper matrix and
//! `K̃ = K_m + diag(L_i (sin θ_i F^v_i + cos θ_i F^a_i) + λ L_i sin θ_i)` the springs plus the
//! stiffness of the link loads and of the slider's reaction (`θ`-derivatives of `−P` and `−λ∇Φ`). What is
//! left out are the centrifugal terms, `(∂M/∂θ) a` and the `θ̇`-terms of `Φ̈ = 0`: all vanish at rest
//! and none is stiff, so the simplified Newton iterations keep converging in a few iterations
//! (the integrator watches their rate and refreshes `J̃` when they slow). `J̃ = J` exactly at a state of
//! equilibrium at rest (the test). Newton–Krylov would need the same preconditioner to converge at
//! stiff steps and then several `J v` passes per iteration; the structured matrix needs none.
//!
//! **Solve.** Eliminating `x = (r₁ + u)/σ` from `(σ I − J̃) (x, u) = (r₁, r₂)` leaves the bordered system
//!
//! `[M + (C_m + K̃/σ)/σ, ∇Φ; ∇Φᵀ, 0] (u, μ) = ((M r₂ − K̃ r₁/σ)/σ, ∇Φᵀ r₂/σ)`.
//!
//! `C_m` and `K_m` act on the joints' relative angles (the last spring and damper, to the slider,
//! on the last link's absolute angle), and the load terms on absolute angles, so
//! `M + (C_m + K̃/σ)/σ` is the mass matrix of the same chain with a term added to each joint's pivot and
//! each link's rotational inertia: the articulated-body recursion factors it in `O(N)`
//! ([`ArticulatedChain::with_additions`]), in complex arithmetic for complex `σ`. `M r₂` is `O(N)` by
//! prefix and suffix sums (`M_ij = L_i L_j μ_{max(i,j)} cos(θ_i − θ_j)`).

use crate::articulated::{ArticulatedChain, ChainNumber};
use crate::eom::{joint_moments, Dynamics};
use crate::linearization::{Complex64, Linearization, ShiftedSolve};
use std::rc::Rc;

/// What `J̃` needs at one state, shared by its factorisations.
struct Chain {
    lengths: Vec<f64>,
    masses: Vec<f64>,
    /// `(sin θ_i, cos θ_i)`.
    trig: Vec<(f64, f64)>,
    /// `μ_j = ½ m_j + Σ_{k>j} m_k` (kg) and `M_ii` (kg·m²).
    coupling: Vec<f64>,
    diag: Vec<f64>,
    /// `∇Φ = (L_i cos θ_i)`, m.
    gradient: Vec<f64>,
    /// `C_1..C_{N+1}` (N·m·s/rad), `K_1..K_{N+1}` (N·m/rad).
    damping: Vec<f64>,
    stiffness: Vec<f64>,
    /// The diagonal (absolute-angle) stiffness of the loads and the reaction, N·m/rad.
    load_stiffness: Vec<f64>,
}

/// The chain's `J̃` at `(t, θ, θ̇)` ([`crate::SpineOde`]'s linearisation).
pub struct ChainLinearization(Rc<Chain>);

impl ChainLinearization {
    /// `J̃` of `d` at `(t, y)` (`piece`: a time inside the forcing's current smooth piece).
    pub fn new(d: &Dynamics, t: f64, piece: f64, y: &[f64]) -> Self {
        let n = d.n_links();
        let (theta, omega) = y.split_at(n);
        let loads = d.loads_at(t, piece);
        let (_, lambda) = d.acceleration(&loads, theta, omega, &d.damping);
        let (coupling, diag) = d.inertia_coefficients();
        let trig: Vec<(f64, f64)> = theta.iter().map(|t| t.sin_cos()).collect();
        let load_stiffness = (0..n)
            .map(|i| {
                let (s, c) = trig[i];
                d.lengths[i] * (s * loads.vertical[i] + c * loads.axial[i] + lambda * s)
            })
            .collect();
        Self(Rc::new(Chain {
            lengths: d.lengths.clone(),
            masses: d.masses.clone(),
            gradient: (0..n).map(|i| d.lengths[i] * trig[i].1).collect(),
            trig,
            coupling,
            diag,
            damping: d.damping.clone(),
            stiffness: d.stiffness.clone(),
            load_stiffness,
        }))
    }

    /// `σ I − J̃` factored, or `None` when a pivot of the recursion fails `pivot_ok`.
    fn factor<T: ChainNumber + 'static>(&self, sigma: T, pivot_ok: &dyn Fn(&T) -> bool) -> Option<ChainFactor<T>> {
        let c = &self.0;
        let n = c.trig.len();
        let inv = T::from(1.0) / sigma;
        let element = |k: usize| (sigma * T::from(c.damping[k]) + T::from(c.stiffness[k])) * inv * inv;
        let joint: Vec<T> = (0..n).map(element).collect();
        let mut body: Vec<T> = c.load_stiffness.iter().map(|&k| T::from(k) * inv * inv).collect();
        if n > 0 {
            body[n - 1] += element(n);
        }
        let chain = ArticulatedChain::with_additions(&c.lengths, &c.masses, &c.trig, &joint, &body, pivot_ok)?;
        let g: Vec<T> = c.gradient.iter().map(|&v| T::from(v)).collect();
        let ag = chain.solve(&g);
        let gag = dot(&g, &ag);
        let stiffness = c.stiffness.iter().map(|&v| T::from(v)).collect();
        let damping = c.damping.iter().map(|&v| T::from(v)).collect();
        Some(ChainFactor { data: Rc::clone(&self.0), inv, chain, g, ag, gag, sigma, stiffness, damping })
    }
}

fn dot<T: ChainNumber>(a: &[T], b: &[T]) -> T {
    a.iter().zip(b).fold(T::from(0.0), |s, (&x, &y)| s + x * y)
}

impl Chain {
    /// `M(θ) r` in `O(N)`.
    fn mass_times<T: ChainNumber>(&self, r: &[T]) -> Vec<T> {
        let n = r.len();
        let zero = T::from(0.0);
        // Per link, from the tip: w_j = L_j r_j (cos θ_j, sin θ_j) and the μ-weighted sum of w
        // beyond link j; then M r from the base, written over the same storage.
        let mut sums: Vec<((T, T), (T, T))> = Vec::with_capacity(n);
        let mut sum = (zero, zero);
        for i in (0..n).rev() {
            let (s, c) = self.trig[i];
            let a = r[i] * T::from(self.lengths[i]);
            let w = (a * T::from(c), a * T::from(s));
            sums.push((w, sum));
            let mu = T::from(self.coupling[i]);
            sum = (sum.0 + w.0 * mu, sum.1 + w.1 * mu);
        }
        sums.reverse();
        let mut before = (zero, zero);
        (0..n)
            .map(|i| {
                let (s, c) = self.trig[i];
                let (w, after) = sums[i];
                let mu = T::from(self.coupling[i]);
                let a = before.0 * mu + after.0;
                let b = before.1 * mu + after.1;
                before = (before.0 + w.0, before.1 + w.1);
                r[i] * T::from(self.diag[i]) + (a * T::from(c) + b * T::from(s)) * T::from(self.lengths[i])
            })
            .collect()
    }

    /// `K̃ r`, with the springs `stiffness` already in the number type of `r`.
    fn stiffness_times<T: ChainNumber>(&self, stiffness: &[T], r: &[T]) -> Vec<T> {
        let mut springs = joint_moments(stiffness, r);
        for ((s, &x), &l) in springs.iter_mut().zip(r).zip(&self.load_stiffness) {
            *s += x * T::from(l);
        }
        springs
    }
}

/// `σ I − J̃` factored for one shift.
struct ChainFactor<T> {
    data: Rc<Chain>,
    /// `1/σ`.
    inv: T,
    /// `M + (C_m + K̃/σ)/σ` by the articulated-body recursion.
    chain: ArticulatedChain<T>,
    /// `∇Φ`, `A⁻¹ ∇Φ` and `∇Φᵀ A⁻¹ ∇Φ`.
    g: Vec<T>,
    ag: Vec<T>,
    gag: T,
    /// `σ`; `K_1..K_{N+1}` and `C_1..C_{N+1}` in the number type.
    sigma: T,
    stiffness: Vec<T>,
    damping: Vec<T>,
}

impl<T: ChainNumber> ShiftedSolve<T> for ChainFactor<T> {
    fn solve(&self, rhs: &mut [T]) {
        let c = &self.data;
        let n = c.trig.len();
        let (r1, r2) = rhs.split_at_mut(n);
        let kr1 = c.stiffness_times(&self.stiffness, r1);
        // (M r2 − K̃ r1/σ)/σ, then A⁻¹ of it, in one buffer.
        let mut au = c.mass_times(r2);
        for (m, &k) in au.iter_mut().zip(&kr1) {
            *m = (*m - k * self.inv) * self.inv;
        }
        self.chain.solve_in_place([&mut au]);
        let mu = (dot(&self.g, &au) - dot(&self.g, r2) * self.inv) / self.gag;
        for i in 0..n {
            let u = au[i] - mu * self.ag[i];
            r1[i] = (r1[i] + u) * self.inv;
            r2[i] = u;
        }
    }

    /// `(σ I − J̃)ᵀ = [[σ I, K̃ W], [−I, σ I + C_m W]]` (`W`, `K̃`, `C_m` symmetric): with `w = W u`
    /// the second row gives `x = σ u + C_m w − r₂` and the first `u + B w = b`, `B = (C_m +
    /// K̃/σ)/σ`, `b = (r₁/σ + r₂)/σ`; `w = W u` is `M w − μ ∇Φ = u`, `∇Φᵀ w = 0`, so `(M + B) w − μ
    /// ∇Φ = b`: the bordered system of [`Self::solve`] with another right-hand side, then `u = b −
    /// B w`.
    fn solve_transpose(&self, rhs: &mut [T]) {
        let c = &self.data;
        let n = c.trig.len();
        let (r1, r2) = rhs.split_at_mut(n);
        let mut w: Vec<T> = (0..n).map(|i| (r1[i] * self.inv + r2[i]) * self.inv).collect();
        let b = w.clone();
        self.chain.solve_in_place([&mut w]);
        let mu = dot(&self.g, &w) / self.gag;
        for (wi, &agi) in w.iter_mut().zip(&self.ag) {
            *wi -= mu * agi;
        }
        let damped = joint_moments(&self.damping, &w);
        let sprung = c.stiffness_times(&self.stiffness, &w);
        for i in 0..n {
            let u = b[i] - (damped[i] + sprung[i] * self.inv) * self.inv;
            r1[i] = self.sigma * u + damped[i] - r2[i];
            r2[i] = u;
        }
    }
}

impl Linearization for ChainLinearization {
    fn factor_real(&self, shift: f64) -> Option<Box<dyn ShiftedSolve<f64>>> {
        let ok = |d: &f64| d.is_finite() && d.abs() > f64::MIN_POSITIVE;
        self.factor(shift, &ok).map(|f| Box::new(f) as Box<dyn ShiftedSolve<f64>>)
    }

    fn factor_complex(&self, shift: Complex64) -> Option<Box<dyn ShiftedSolve<Complex64>>> {
        // A pivot is usable when its larger part is a normal number (`|d|` itself would cost a
        // `hypot` per link).
        let ok = |d: &Complex64| d.is_finite() && d.re.abs().max(d.im.abs()) > f64::MIN_POSITIVE;
        self.factor(shift, &ok).map(|f| Box::new(f) as Box<dyn ShiftedSolve<Complex64>>)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::arch_problem;
    use crate::forcing::Forcing;
    use crate::integrator::OdeSystem;
    use crate::linearization::DenseJacobian;
    use crate::{Parameters, SpineOde};

    /// A state of equilibrium at rest under the passive load (a pulse train that starts later, so
    /// the actuation is off at t = 0), where `J̃` is the exact Jacobian.
    fn at_rest(n: usize) -> (Dynamics, Vec<f64>) {
        let problem = arch_problem(n, 7.0);
        let ends = problem.static_ends(&Default::default()).expect("stable ends");
        let d = problem.dynamics(Forcing::PulseTrain { period: 1.0, duty: 0.5, delay: 0.5 });
        (d, ends.rest_state())
    }

    /// A state in motion: the step response of an `n`-link arch with dampers `damping` after 20 ms.
    fn in_motion(n: usize, damping: f64) -> (Dynamics, Vec<f64>) {
        let problem = arch_problem(n, damping);
        let ends = problem.static_ends(&Default::default()).expect("stable ends");
        let d = problem.dynamics(Forcing::Step);
        let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
        let extras = crate::integrator::Extras::default();
        let y = crate::integrate(&ode, 0.0, &ends.rest_state(), 0.02, &Default::default(), extras).end().to_vec();
        (d, y)
    }

    fn pattern(len: usize, k: f64) -> Vec<f64> {
        (0..len).map(|i| ((i as f64 + 1.0) * k).sin()).collect()
    }

    #[test]
    fn the_mass_product_equals_the_dense_mass_matrix() {
        let (d, y) = at_rest(9);
        let lin = ChainLinearization::new(&d, 0.0, 0.0, &y);
        let r = pattern(9, 0.7);
        let m = d.mass_matrix(&y[..9]);
        let fast = lin.0.mass_times(&r);
        for i in 0..9 {
            let dense: f64 = (0..9).map(|j| m[i][j] * r[j]).sum();
            assert!((fast[i] - dense).abs() < 1e-13, "row {i}: {} vs {dense}", fast[i]);
        }
    }

    /// At equilibrium and at rest `J̃ = J`: the O(N) solve equals the dense LU of `σ I − J` (AD
    /// Jacobian), for real and complex shifts across the scales the integrator uses.
    #[test]
    fn at_rest_the_structured_solve_equals_the_dense_one() {
        for n in [1, 2, 3, 10, 25] {
            let (d, y) = at_rest(n);
            let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
            let dense = DenseJacobian(ode.jacobian(0.0, 0.0, &y));
            let fast = ChainLinearization::new(&d, 0.0, 0.0, &y);
            let r = pattern(2 * n, 1.3);
            for sigma in [3.0, 4e2, 1e5] {
                let (mut a, mut b) = (r.clone(), r.clone());
                fast.factor_real(sigma).unwrap().solve(&mut a);
                dense.factor_real(sigma).unwrap().solve(&mut b);
                let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..2 * n {
                    assert!((a[i] - b[i]).abs() < 1e-9 * scale, "N={n} σ={sigma} [{i}]: {} vs {}", a[i], b[i]);
                }
                let shift = Complex64::new(0.6 * sigma, -0.8 * sigma);
                let rc: Vec<Complex64> =
                    r.iter().zip(pattern(2 * n, 0.4)).map(|(&x, y)| Complex64::new(x, y)).collect();
                let (mut a, mut b) = (rc.clone(), rc);
                fast.factor_complex(shift).unwrap().solve(&mut a);
                dense.factor_complex(shift).unwrap().solve(&mut b);
                let scale = b.iter().fold(0.0f64, |m, v| m.max(v.norm()));
                for i in 0..2 * n {
                    assert!((a[i] - b[i]).norm() < 1e-9 * scale, "N={n} σ={shift} [{i}]: {} vs {}", a[i], b[i]);
                }
            }
        }
    }

    /// The transposed solve is the transpose of the solve: `aᵀ (F⁻¹ b) = (F⁻ᵀ a)ᵀ b` for the
    /// structured factor in motion (where `J̃` is not symmetric in any sense), real and complex,
    /// and the dense LU's transposed solve agrees with the structured one at rest.
    #[test]
    fn the_transposed_solve_is_the_transpose_of_the_solve() {
        let (d, y) = in_motion(7, 30.0);
        let fast = ChainLinearization::new(&d, 0.02, 0.02, &y);
        let (a, b) = (pattern(14, 0.37), pattern(14, 1.9));
        let dot_r = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
        for sigma in [5.0, 3e2, 4e4] {
            let f = fast.factor_real(sigma).unwrap();
            let (mut fb, mut fa) = (b.clone(), a.clone());
            f.solve(&mut fb);
            f.solve_transpose(&mut fa);
            let (left, right) = (dot_r(&a, &fb), dot_r(&fa, &b));
            assert!((left - right).abs() <= 1e-12 * left.abs().max(right.abs()), "σ = {sigma}: {left} vs {right}");
            let shift = Complex64::new(0.6 * sigma, -0.8 * sigma);
            let f = fast.factor_complex(shift).unwrap();
            let ac: Vec<Complex64> = a.iter().zip(&b).map(|(&x, &y)| Complex64::new(x, y)).collect();
            let bc: Vec<Complex64> = b.iter().zip(pattern(14, 0.2)).map(|(&x, y)| Complex64::new(x, y)).collect();
            let (mut fb, mut fa) = (bc.clone(), ac.clone());
            f.solve(&mut fb);
            f.solve_transpose(&mut fa);
            let dot_c = |x: &[Complex64], y: &[Complex64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<Complex64>();
            let (left, right) = (dot_c(&ac, &fb), dot_c(&fa, &bc));
            assert!((left - right).norm() <= 1e-12 * left.norm().max(right.norm()), "σ = {shift}: {left} vs {right}");
        }
        let (d, y) = at_rest(6);
        let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
        let dense = DenseJacobian(ode.jacobian(0.0, 0.0, &y));
        let fast = ChainLinearization::new(&d, 0.0, 0.0, &y);
        let (mut p, mut q) = (pattern(12, 0.8), pattern(12, 0.8));
        fast.factor_real(50.0).unwrap().solve_transpose(&mut p);
        dense.factor_real(50.0).unwrap().solve_transpose(&mut q);
        let scale = q.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..12 {
            assert!((p[i] - q[i]).abs() < 1e-9 * scale, "[{i}]: {} vs {}", p[i], q[i]);
        }
    }

    /// In motion `J̃` leaves out non-stiff terms: `(σ I − J̃)⁻¹ (σ I − J)` stays near the identity, so
    /// simplified Newton contracts fast (measured contraction below 0.05 at the step sizes used).
    #[test]
    fn in_motion_the_structured_matrix_is_a_close_preconditioner() {
        let (d, y) = in_motion(8, 50.0);
        let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
        let j = ode.jacobian(0.02, 0.02, &y);
        let fast = ChainLinearization::new(&d, 0.02, 0.02, &y);
        for sigma in [1e2, 1e3, 1e4] {
            let factor = fast.factor_real(sigma).unwrap();
            let mut worst = 0.0f64;
            for k in 0..16 {
                let v = pattern(16, 0.3 + k as f64);
                let jv = &j * nalgebra::DVector::from_column_slice(&v);
                let mut w: Vec<f64> = (0..16).map(|i| sigma * v[i] - jv[i]).collect();
                factor.solve(&mut w);
                let err = (0..16).map(|i| (w[i] - v[i]).abs()).fold(0.0, f64::max);
                worst = worst.max(err / v.iter().fold(0.0f64, |m, x| m.max(x.abs())));
            }
            assert!(worst < 0.05, "σ = {sigma}: ‖(σI − J̃)⁻¹(σI − J) − I‖ ≈ {worst}");
        }
    }
}
