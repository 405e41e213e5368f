//! The accelerations' rates in the angles, the angular velocities, the dampers and the springs,
//! `∂θ̈/∂θ`, `∂θ̈/∂θ̇`, `∂θ̈/∂C` and `∂θ̈/∂K`, from one real factorisation of `M(θ)` and one `O(N)`
//! solve per column.
//!
//! The index-1 form ([`Dynamics::acceleration`]) is `θ̈ = M⁻¹Q + λ M⁻¹∇Φ`,
//! `λ = (b − ∇Φᵀ M⁻¹Q) / (∇Φᵀ M⁻¹∇Φ)`. `M` and `∇Φ` depend on `θ` only, so a change of `θ̇` or of a
//! damper changes `Q` and `b` alone, and the accelerations change by the same bordered solve with
//! `(dQ, db)` in place of `(Q, b)`:
//!
//! * damper `C_k` (joint `k`, between links `k − 1` and `k`): `dQ = −r_k (e_k − e_{k−1})` with the
//!   joint's relative rate `r_k = θ̇_k − θ̇_{k−1}` (`θ̇_{−1} = θ̇_N = 0`), `db = 0`;
//! * spring `K_k`: the same with the joint's relative deflection `r_k = Δθ_k − Δθ_{k−1}`,
//!   `Δθ = θ − θ0` (`Δθ_{−1} = Δθ_N = 0`);
//! * angular velocity `θ̇_k`: `dQ = −∂h/∂θ̇_k − C_m e_k` with the centrifugal terms' rate
//!   `∂h_i/∂θ̇_k = 2 L_i L_k μ_{max(i,k)} sin(θ_i − θ_k) θ̇_k` (`i ≠ k`), and
//!   `db = 2 L_k sin θ_k θ̇_k`.
//!
//! * angle `θ_k`, where `M`, `∇Φ` and `b` move too: differentiating `M θ̈ − ∇Φ λ = Q`,
//!   `∇Φᵀ θ̈ = b` gives the same bordered solve with `dQ = ∂Q/∂θ_k − (∂M/∂θ_k) θ̈ + (∂∇Φ/∂θ_k) λ`
//!   and `db = ∂b/∂θ_k − (∂∇Φ/∂θ_k)ᵀ θ̈`, from the state's own `θ̈` and `λ`. `∂M/∂θ_k` and
//!   `∂h/∂θ_k` touch row `k` (a sum over the links) and column `k`: `O(N)` per column.
//!
//! The dual passes of the whole right-hand side ([`crate::system::reference`]) are the reference
//! the tests hold these to. Where `M(θ)` has no factorisation (a non-finite trial state) the rates
//! are NaN, as the accelerations are.

use crate::articulated::ArticulatedChain;
use crate::eom::{bordered, coupling_coefficients, joint_moments, Dynamics, LoadsAt};
use nalgebra::DMatrix;
use spine_model::LinkLoads;

/// Which rates [`RatesAt::rates`] computes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RatesIn<'a> {
    /// `∂θ̈/∂θ` under these link loads (they enter through `P(θ)`), `N × N`, 1/s².
    Angles(&'a LinkLoads),
    /// `∂θ̈/∂θ̇`, `N × N`, 1/s.
    AngularVelocities,
    /// `∂θ̈/∂C`, `N × (N + 1)`, rad/s² per N·m·s/rad.
    Dampers,
    /// `∂θ̈/∂K`, `N × (N + 1)`, rad/s² per N·m/rad.
    Springs,
}

/// One state `(θ, θ̇)` with `M(θ)` factorised once and `M⁻¹∇Φ`: every block of rates at it.
pub struct RatesAt<'a> {
    dynamics: &'a Dynamics,
    theta: &'a [f64],
    omega: &'a [f64],
    trig: Vec<(f64, f64)>,
    /// `None` where `M(θ)` has no factorisation: the rates are NaN.
    chain: Option<ArticulatedChain<f64>>,
    g: Vec<f64>,
    mg: Vec<f64>,
    gmg: f64,
}

impl Dynamics {
    /// The state `(θ, θ̇)` prepared for its rates (one factorisation of `M(θ)`).
    pub fn rates_at<'a>(&'a self, theta: &'a [f64], omega: &'a [f64]) -> RatesAt<'a> {
        let n = self.n_links();
        let trig: Vec<(f64, f64)> = theta.iter().map(|t| t.sin_cos()).collect();
        let chain = ArticulatedChain::from_trig(&self.lengths, &self.masses, &trig);
        let g: Vec<f64> = (0..n).map(|i| trig[i].1 * self.lengths[i]).collect();
        let mg = chain.as_ref().map_or_else(|| vec![f64::NAN; n], |c| c.solve(&g));
        let gmg = g.iter().zip(&mg).map(|(a, b)| a * b).sum();
        RatesAt { dynamics: self, theta, omega, trig, chain, g, mg, gmg }
    }
}

/// A state's `(sin θ_i, cos θ_i)`, the factorisation of `M(θ)`, `M⁻¹∇Φ` and `∇Φᵀ M⁻¹∇Φ`, taken
/// out of its [`RatesAt`].
pub(crate) struct Factored {
    pub(crate) trig: Vec<(f64, f64)>,
    pub(crate) chain: ArticulatedChain<f64>,
    pub(crate) mg: Vec<f64>,
    pub(crate) gmg: f64,
}

/// What one column of rates is driven by: `(dQ, db, k)`, written into column `k`.
type Respond<'r> = dyn FnMut(&[f64], f64, usize) + 'r;

impl RatesAt<'_> {
    /// One block of rates (module docs): each column's `(dQ, db)`, then one solve for all columns
    /// and the bordered correction `M⁻¹dQ + M⁻¹∇Φ dλ`.
    pub fn rates(&self, what: RatesIn<'_>) -> DMatrix<f64> {
        let d = self.dynamics;
        let n = d.n_links();
        let columns = match what {
            RatesIn::Angles(_) | RatesIn::AngularVelocities => n,
            RatesIn::Dampers => d.damping.len(),
            RatesIn::Springs => d.stiffness.len(),
        };
        let mut rates = DMatrix::zeros(n, columns);
        let Some(chain) = &self.chain else {
            rates.fill(f64::NAN);
            return rates;
        };
        let mut dbs = vec![0.0; columns];
        let mut respond = |dq: &[f64], db: f64, k: usize| {
            rates.column_mut(k).copy_from_slice(dq);
            dbs[k] = db;
        };
        match what {
            RatesIn::Dampers => self.joint_forcing(self.omega, columns, &mut respond),
            RatesIn::Springs => {
                let deflection: Vec<f64> = self.theta.iter().zip(&d.theta0).map(|(t, t0)| t - t0).collect();
                self.joint_forcing(&deflection, columns, &mut respond);
            }
            RatesIn::AngularVelocities => self.velocity_forcing(&mut respond),
            RatesIn::Angles(loads) => self.angle_forcing(chain, loads, &mut respond),
        }
        chain.solve_columns(&mut rates);
        let (g, mg) = (&self.g, &self.mg);
        for (k, mut column) in rates.column_iter_mut().enumerate() {
            let dlambda = (dbs[k] - g.iter().zip(column.iter()).map(|(a, b)| a * b).sum::<f64>()) / self.gmg;
            for i in 0..n {
                column[i] += mg[i] * dlambda;
            }
        }
        rates
    }

    /// `c_ij = L_i L_j μ_max(i,j)`: `M_ij = c_ij cos(θ_i − θ_j)`, `h_i = Σ_j c_ij θ̇_j² sin(θ_i − θ_j)`.
    fn coupling(&self) -> impl Fn(usize, usize) -> f64 + '_ {
        let l = &self.dynamics.lengths;
        let coupling = coupling_coefficients(&self.dynamics.masses);
        move |i, j| l[i] * l[j] * coupling[i.max(j)]
    }

    /// A damper's or a spring's column: `dQ = −r_k (e_k − e_{k−1})` with the joint's relative
    /// motion `r_k = x_k − x_{k−1}` (`x`: `θ̇` for a damper, `θ − θ0` for a spring), `db = 0`.
    fn joint_forcing(&self, x: &[f64], columns: usize, respond: &mut Respond<'_>) {
        let n = x.len();
        let at = |i: isize| if i < 0 || i as usize >= n { 0.0 } else { x[i as usize] };
        let mut dq = vec![0.0; n];
        for k in 0..columns {
            dq.fill(0.0);
            let r = at(k as isize) - at(k as isize - 1);
            if k < n {
                dq[k] -= r;
            }
            if k > 0 {
                dq[k - 1] += r;
            }
            respond(&dq, 0.0, k);
        }
    }

    /// An angular velocity's column: the centrifugal terms' and the dampers' rates.
    fn velocity_forcing(&self, respond: &mut Respond<'_>) {
        let d = self.dynamics;
        let (n, trig, omega, l) = (d.n_links(), &self.trig, self.omega, &d.lengths);
        let c = self.coupling();
        let (mut dq, mut unit) = (vec![0.0; n], vec![0.0; n]);
        for k in 0..n {
            unit[k] = 1.0;
            let damper = joint_moments(&d.damping, &unit);
            unit[k] = 0.0;
            let (sk, ck) = trig[k];
            for i in 0..n {
                let centrifugal = if i == k {
                    0.0
                } else {
                    let (si, ci) = trig[i];
                    2.0 * c(i, k) * (si * ck - ci * sk) * omega[k]
                };
                dq[i] = -centrifugal - damper[i];
            }
            respond(&dq, 2.0 * l[k] * sk * omega[k], k);
        }
    }

    /// The state's own `θ̈` and `λ` under `loads`, from the factorisation of `M(θ)`.
    fn acceleration_with(&self, chain: &ArticulatedChain<f64>, loads: &LinkLoads) -> (Vec<f64>, f64) {
        let d = self.dynamics;
        let h = d.velocity_terms_from(&self.trig, self.omega);
        let (q, _, b) = d.index1_terms(LoadsAt::Given(loads), (self.theta, &self.trig), self.omega, &d.damping, h);
        bordered(chain.solve(&q), &self.mg, &self.g, b)
    }

    /// The state's own `θ̈` and `λ` under `loads`; `None` where `M(θ)` has no factorisation.
    pub(crate) fn state_acceleration(&self, loads: &LinkLoads) -> Option<(Vec<f64>, f64)> {
        self.chain.as_ref().map(|chain| self.acceleration_with(chain, loads))
    }

    /// What the prepared state keeps ([`Factored`]); `None` where `M(θ)` has no factorisation.
    pub(crate) fn into_factored(self) -> Option<Factored> {
        Some(Factored { trig: self.trig, chain: self.chain?, mg: self.mg, gmg: self.gmg })
    }

    /// An angle's column, where `M`, `∇Φ` and `b` move too, from the state's own `θ̈` and `λ`.
    fn angle_forcing(&self, chain: &ArticulatedChain<f64>, loads: &LinkLoads, respond: &mut Respond<'_>) {
        let d = self.dynamics;
        let (n, trig, omega, l, k_m) = (d.n_links(), &self.trig, self.omega, &d.lengths, &d.stiffness);
        let c = self.coupling();
        let (acc, lambda) = self.acceleration_with(chain, loads);
        let mut dq = vec![0.0; n];
        for k in 0..n {
            let (sk, ck) = trig[k];
            dq.fill(0.0);
            // P_k = (cos θ_k V_k − sin θ_k X_k) L_k.
            dq[k] += (-sk * loads.vertical[k] - ck * loads.axial[k]) * l[k];
            for i in (0..n).filter(|&i| i != k) {
                let (si, ci) = trig[i];
                let (cos_ik, sin_ik) = (ci * ck + si * sk, si * ck - ci * sk);
                let cik = c(i, k);
                // −∂h/∂θ_k and −(∂M/∂θ_k) θ̈, row i ≠ k and their row-k sums.
                dq[i] += cik * omega[k] * omega[k] * cos_ik - cik * sin_ik * acc[k];
                dq[k] += -cik * omega[i] * omega[i] * cos_ik - cik * sin_ik * acc[i];
            }
            // −∂(K_m (θ − θ0))/∂θ_k: the two springs at the link's ends.
            dq[k] -= k_m[k] + k_m[k + 1];
            if k > 0 {
                dq[k - 1] += k_m[k];
            }
            if k + 1 < n {
                dq[k + 1] += k_m[k + 1];
            }
            // + (∂∇Φ/∂θ_k) λ, and the constraint row's `∂b/∂θ_k − (∂∇Φ/∂θ_k)ᵀ θ̈`.
            dq[k] -= l[k] * sk * lambda;
            respond(&dq, l[k] * ck * omega[k] * omega[k] + l[k] * sk * acc[k], k);
        }
    }
}

/// `∇Φ = (L_i cos θ_i)`, its diagonal derivative `(−L_i sin θ_i)` and `Φ = Σ L_i sin θ_i`: what
/// each sweep of [`Dynamics::project`] uses.
fn constraint_terms(lengths: &[f64], theta: &[f64]) -> (Vec<f64>, Vec<f64>, f64) {
    let n = theta.len();
    let (mut g, mut curvature, mut phi) = (vec![0.0; n], vec![0.0; n], 0.0);
    for i in 0..n {
        let (si, ci) = theta[i].sin_cos();
        phi += lengths[i] * si;
        g[i] = lengths[i] * ci;
        curvature[i] = -lengths[i] * si;
    }
    (g, curvature, phi)
}

impl Dynamics {
    /// `a ← (∂ project/∂y)ᵀ a` at the unprojected `y`: the transpose of [`Self::project_tangent`]
    /// for one row vector (the adjoint of a step, [`crate::integrator::adjoint`]), in reverse
    /// order: the velocity projection, then the sweeps from the last to the first.
    pub fn project_adjoint(&self, y: &[f64], a: &mut [f64]) {
        let n = self.n_links();
        let l = &self.lengths;
        let omega = &y[n..];
        // Each sweep's `∇Φ`, `∂∇Φ` (diagonal), `s = Φ/|∇Φ|²` and `|∇Φ|²`, then the final angles'.
        let mut theta = y[..n].to_vec();
        let mut sweeps: Vec<(Vec<f64>, Vec<f64>, f64, f64)> = Vec::with_capacity(crate::eom::PROJECTION_SWEEPS + 1);
        for k in 0..=crate::eom::PROJECTION_SWEEPS {
            let (g, curvature, phi) = constraint_terms(l, &theta);
            let gg: f64 = g.iter().map(|v| v * v).sum();
            let step = phi / gg;
            if k < crate::eom::PROJECTION_SWEEPS {
                for i in 0..n {
                    theta[i] -= g[i] * step;
                }
            }
            sweeps.push((g, curvature, step, gg));
        }
        let (a_theta, a_omega) = a.split_at_mut(n);
        // Invariant: the loop above pushes one sweep per iteration and runs at least once.
        let (g, curvature, _, gg) = sweeps.pop().expect("the final angles");
        let rate = g.iter().zip(omega).map(|(x, w)| x * w).sum::<f64>() / gg;
        let b: f64 = g.iter().zip(a_omega.iter()).map(|(x, w)| x * w).sum();
        for i in 0..n {
            a_theta[i] -= a_omega[i] * rate * curvature[i]
                + b * (curvature[i] * omega[i] - 2.0 * rate * g[i] * curvature[i]) / gg;
            a_omega[i] -= b * g[i] / gg;
        }
        for (g, curvature, step, gg) in sweeps.iter().rev() {
            let b: f64 = g.iter().zip(a_theta.iter()).map(|(x, w)| x * w).sum();
            for i in 0..n {
                a_theta[i] -= curvature[i] * step * a_theta[i] + b * (g[i] - 2.0 * step * g[i] * curvature[i]) / gg;
            }
        }
    }

    /// `S ← (∂ project/∂y) S` at the unprojected `y` ([`Dynamics::project`]: Gauss–Newton sweeps
    /// of `θ` onto `Φ = 0`, then `θ̇` onto `Φ̇ = 0`), for all columns of `S` at once in real
    /// arithmetic: each sweep `θ ← θ − ∇Φ s`, `s = Φ/|∇Φ|²`, moves a direction `dθ` by
    /// `−(∂∇Φ dθ) s − ∇Φ ds` with `ds = (∇Φᵀdθ − 2 s ∇Φᵀ(∂∇Φ dθ)) / |∇Φ|²`, and `∂∇Φ` is diagonal
    /// (`−L_i sin θ_i`).
    pub fn project_tangent(&self, y: &[f64], s: &mut DMatrix<f64>) {
        let n = self.n_links();
        let l = &self.lengths;
        let mut theta = y[..n].to_vec();
        let omega = &y[n..];
        let at = |theta: &[f64]| constraint_terms(l, theta);
        let mut dg = vec![0.0; n];
        for _ in 0..crate::eom::PROJECTION_SWEEPS {
            let (g, curvature, phi) = at(&theta);
            let gg: f64 = g.iter().map(|v| v * v).sum();
            let step = phi / gg;
            for mut column in s.column_iter_mut() {
                let mut dphi = 0.0;
                let mut dgg = 0.0;
                for i in 0..n {
                    dphi += g[i] * column[i];
                    dg[i] = curvature[i] * column[i];
                    dgg += 2.0 * g[i] * dg[i];
                }
                let dstep = (dphi - step * dgg) / gg;
                for i in 0..n {
                    column[i] -= dg[i] * step + g[i] * dstep;
                }
            }
            for i in 0..n {
                theta[i] -= g[i] * step;
            }
        }
        let (g, curvature, _) = at(&theta);
        let gg: f64 = g.iter().map(|v| v * v).sum();
        let rate = g.iter().zip(omega).map(|(a, b)| a * b).sum::<f64>() / gg;
        for mut column in s.column_iter_mut() {
            let (mut dgg, mut dnum) = (0.0, 0.0);
            for i in 0..n {
                dg[i] = curvature[i] * column[i];
                dgg += 2.0 * g[i] * dg[i];
                dnum += dg[i] * omega[i] + g[i] * column[n + i];
            }
            let drate = (dnum - rate * dgg) / gg;
            for i in 0..n {
                column[n + i] -= dg[i] * rate + g[i] * drate;
            }
        }
    }
}
