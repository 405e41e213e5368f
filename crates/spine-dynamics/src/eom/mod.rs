//! Equations of motion of the chain, eq. (6) and `docs/model.md` "Dynamics":
//!
//! `M(θ) θ̈ + h(θ, θ̇) + C_m θ̇ + K_m (θ − θ0) − P(θ, t) − λ ∇Φ(θ) = 0`, `Φ(θ) = 0`.
//!
//! * Links are uniform rods: mass `m_k` (kg) at mid-length, centroidal inertia `m_k L_k² / 12`.
//! * `M` is the mass matrix in absolute angles (kg·m²), `h` the centrifugal terms (N·m), `C_m` and
//!   `K_m` the tridiagonal damper and spring matrices (N·m·s/rad, N·m/rad), `P` the generalised load
//!   (N·m) of the passive load plus `s(t)` times the actuation ([`crate::Forcing`]), `λ` the slider's
//!   vertical reaction (N).
//!
//! Every function is generic over [`Scalar`], so Jacobians and parameter sensitivities come from
//! forward-mode AD. The damper coefficients are a separate argument so that they can carry dual parts
//! (the sensitivities of the damping design, eq. (35)).

mod acceleration;
mod inertia;

pub(crate) use inertia::coupling_coefficients;

use crate::articulated::{ArticulatedChain, ChainNumber};
use crate::forcing::Forcing;
pub(crate) use acceleration::bordered;
use spine_model::kinematics::link_lengths;
use spine_model::{Chain, Design, LinkLoads, NodalLoads, Scalar};

/// A design with its masses, dampers and loads: everything the equations of motion need.
#[derive(Clone, Debug)]
pub struct Dynamics {
    /// Link lengths `L_i = a_i / cos θ0_i`, m.
    pub lengths: Vec<f64>,
    /// Link masses `m_i`, kg.
    pub masses: Vec<f64>,
    /// Unloaded design angles `θ0`, rad.
    pub theta0: Vec<f64>,
    /// Springs `K_1..K_{N+1}`, N·m/rad.
    pub stiffness: Vec<f64>,
    /// Dampers `C_1..C_{N+1}`, N·m·s/rad, at the same places as the springs.
    pub damping: Vec<f64>,
    /// Link load resultants of the passive load (transverse forces and self-weight).
    pub passive: LinkLoads,
    /// Link load resultants of the passive load plus the full actuation.
    pub loaded: LinkLoads,
    /// How much of the actuation acts at time `t`.
    pub forcing: Forcing,
}

impl Dynamics {
    /// The dynamics of a design under the passive load plus `forcing` times the actuation.
    pub fn new(
        chain: &Chain,
        design: &Design,
        damping: Vec<f64>,
        passive: &NodalLoads,
        actuation: &NodalLoads,
        forcing: Forcing,
    ) -> Self {
        Self {
            lengths: link_lengths(&chain.spans, &design.theta0),
            masses: chain.masses.clone(),
            theta0: design.theta0.clone(),
            stiffness: design.stiffness.clone(),
            damping,
            passive: LinkLoads::from_nodal(chain, passive, true),
            loaded: LinkLoads::from_nodal(chain, &passive.plus(actuation), true),
            forcing,
        }
    }

    /// Number of links `N`.
    pub fn n_links(&self) -> usize {
        self.lengths.len()
    }

    /// Mass matrix `M(θ)`, kg·m², row-major `N × N`:
    /// `M_ii = L_i² (m_i/3 + Σ_{k>i} m_k)`, `M_ij = L_i L_j cos(θ_i − θ_j) (½ m_j + Σ_{k>j} m_k)` for `i < j`.
    pub fn mass_matrix<D: Scalar>(&self, theta: &[D]) -> Vec<Vec<D>> {
        let n = self.n_links();
        let (coupling, diag) = self.inertia_coefficients();
        let mut m = vec![vec![D::zero(); n]; n];
        for i in 0..n {
            m[i][i] = D::from(diag[i]);
            for j in i + 1..n {
                let v = (theta[i] - theta[j]).cos() * (self.lengths[i] * self.lengths[j] * coupling[j]);
                m[i][j] = v;
                m[j][i] = v;
            }
        }
        m
    }

    /// Centrifugal terms `h_i(θ, θ̇) = Σ_j c_ij sin(θ_i − θ_j) θ̇_j²`, N·m (the Coriolis part cancels in
    /// absolute angles), with `c_ij = L_i L_j μ_{max(i,j)}` the off-diagonal coefficient of `M`, in
    /// `O(N)`: `h_i = L_i (sin θ_i A_i − cos θ_i B_i)` with `(A_i, B_i) = Σ_{j≠i} μ_{max(i,j)} L_j θ̇_j²
    /// (cos θ_j, sin θ_j)`, a prefix sum (scaled by `μ_i`) over `j < i` plus a `μ_j`-weighted suffix
    /// sum over `j > i`.
    pub fn velocity_terms<D: Scalar>(&self, theta: &[D], omega: &[D]) -> Vec<D> {
        let trig: Vec<(D, D)> = theta.iter().map(|t| t.sin_cos()).collect();
        self.velocity_terms_from(&trig, omega)
    }

    /// [`Self::velocity_terms`] from `(sin θ_i, cos θ_i)`.
    pub(crate) fn velocity_terms_from<D: Scalar>(&self, trig: &[(D, D)], omega: &[D]) -> Vec<D> {
        let mut h = Vec::new();
        self.velocity_terms_into(trig, omega, &mut Vec::new(), &mut h);
        h
    }

    /// [`Self::velocity_terms_from`] into `h` (overwritten), `links` scratch.
    fn velocity_terms_into<D: Scalar>(
        &self,
        trig: &[(D, D)],
        omega: &[D],
        links: &mut Vec<TipSums<D>>,
        h: &mut Vec<D>,
    ) {
        let n = self.n_links();
        // Per link, from the tip: μ_i = ½ m_i + Σ_{k>i} m_k ([`Self::inertia_coefficients`], the
        // same sums in the same order), w_i = L_i θ̇_i² (cos θ_i, sin θ_i) and the μ-weighted
        // suffix sum of w beyond link i.
        links.clear();
        let (mut beyond, mut sum) = (0.0, (D::zero(), D::zero()));
        for i in (0..n).rev() {
            if i + 1 < n {
                beyond += self.masses[i + 1];
            }
            let coupling = 0.5 * self.masses[i] + beyond;
            let (s, c) = trig[i];
            let a = omega[i] * omega[i] * self.lengths[i];
            let w = (a * c, a * s);
            links.push(TipSums { coupling, w, after: sum });
            sum = (sum.0 + w.0 * coupling, sum.1 + w.1 * coupling);
        }
        let mut before = (D::zero(), D::zero());
        h.clear();
        h.extend(links.iter().rev().enumerate().map(|(i, &TipSums { coupling, w, after })| {
            let (s, c) = trig[i];
            let a = before.0 * coupling + after.0;
            let b = before.1 * coupling + after.1;
            before = (before.0 + w.0, before.1 + w.1);
            (s * a - c * b) * self.lengths[i]
        }));
    }

    /// [`Self::velocity_terms`] by its defining double sum, `O(N²)`: the test oracle.
    pub fn velocity_terms_dense<D: Scalar>(&self, theta: &[D], omega: &[D]) -> Vec<D> {
        let n = self.n_links();
        let (coupling, _) = self.inertia_coefficients();
        let mut h = vec![D::zero(); n];
        for i in 0..n {
            for j in 0..n {
                if i == j {
                    continue;
                }
                let c = self.lengths[i] * self.lengths[j] * coupling[i.max(j)];
                h[i] += (theta[i] - theta[j]).sin() * omega[j] * omega[j] * c;
            }
        }
        h
    }

    /// Kinetic energy, J, from the centre-of-mass velocities and the rotations (independent of
    /// [`Self::mass_matrix`]; the tests compare the two).
    pub fn kinetic_energy<D: Scalar>(&self, theta: &[D], omega: &[D]) -> D {
        let (mut vx, mut vy) = (D::zero(), D::zero());
        let mut t = D::zero();
        for k in 0..self.n_links() {
            let (s, c) = theta[k].sin_cos();
            let l = self.lengths[k];
            let (cx, cy) = (vx - s * omega[k] * (0.5 * l), vy + c * omega[k] * (0.5 * l));
            t += (cx * cx + cy * cy) * (0.5 * self.masses[k]);
            t += omega[k] * omega[k] * (self.masses[k] * l * l / 24.0);
            vx -= s * omega[k] * l;
            vy += c * omega[k] * l;
        }
        t
    }

    /// Link load resultants at time `t` (`piece`: any time inside the forcing's current smooth piece).
    pub fn loads_at(&self, t: f64, piece: f64) -> LinkLoads {
        LinkLoads::lerp(&self.passive, &self.loaded, self.forcing.factor(t, piece))
    }

    /// Generalised load `P_i = L_i (cos θ_i · vertical_i − sin θ_i · axial_i)`, N·m, eq. (48).
    pub fn generalised_load<D: Scalar>(&self, loads: &LinkLoads, theta: &[D]) -> Vec<D> {
        (0..self.n_links())
            .map(|i| {
                let (s, c) = theta[i].sin_cos();
                (c * loads.vertical[i] - s * loads.axial[i]) * self.lengths[i]
            })
            .collect()
    }

    /// Potential of constant link loads, J, up to a constant: `V = −Σ L_i (vertical_i sin θ_i + axial_i cos θ_i)`,
    /// so that `P = −∂V/∂θ`.
    pub fn load_potential<D: Scalar>(&self, loads: &LinkLoads, theta: &[D]) -> D {
        (0..self.n_links())
            .map(|i| {
                let (s, c) = theta[i].sin_cos();
                -(s * loads.vertical[i] + c * loads.axial[i]) * self.lengths[i]
            })
            .sum()
    }

    /// End constraint `Φ(θ) = Σ L_i sin θ_i`, m.
    pub fn constraint<D: Scalar>(&self, theta: &[D]) -> D {
        theta.iter().zip(&self.lengths).map(|(&t, &l)| t.sin() * l).sum()
    }

    /// `∇Φ = (L_i cos θ_i)`, m.
    pub fn constraint_gradient<D: Scalar>(&self, theta: &[D]) -> Vec<D> {
        theta.iter().zip(&self.lengths).map(|(&t, &l)| t.cos() * l).collect()
    }

    /// `Φ̇ = ∇Φ · θ̇`, m/s.
    pub fn constraint_rate<D: Scalar>(&self, theta: &[D], omega: &[D]) -> D {
        self.constraint_gradient(theta).iter().zip(omega).map(|(&g, &w)| g * w).sum()
    }

    /// X of the end node, `Σ L_i cos θ_i`, m.
    pub fn end_x<D: Scalar>(&self, theta: &[D]) -> D {
        theta.iter().zip(&self.lengths).map(|(&t, &l)| t.cos() * l).sum()
    }

    /// `∂X_{N+1}/∂y` for the state `y = (θ, θ̇)`: `(−L_i sin θ_i, 0)`, m/rad (events on the end's X).
    pub fn end_x_state_gradient(&self, y: &[f64]) -> Vec<f64> {
        let n = self.n_links();
        (0..2 * n).map(|i| if i < n { -self.lengths[i] * y[i].sin() } else { 0.0 }).collect()
    }

    /// Weights `w` with `|X_{N+1}(y) − X_{N+1}(z)| ≤ Σ_i w_i |y_i − z_i|` for states `y = (θ, θ̇)`:
    /// `L_i` (m/rad) on `θ_i`, since `|cos a − cos b| ≤ |a − b|`, and 0 on `θ̇` (the Lipschitz bound
    /// of events on the end's X, [`crate::integrator::EventFunction::lipschitz`]).
    pub fn end_x_lipschitz(&self) -> Vec<f64> {
        let n = self.n_links();
        (0..2 * n).map(|i| if i < n { self.lengths[i] } else { 0.0 }).collect()
    }

    /// Right-hand side of the first-order system in `y = (θ, θ̇)`: `(θ̇, θ̈)`.
    pub fn rhs<D: Scalar>(&self, t: f64, piece: f64, y: &[D], damping: &[D]) -> Vec<D> {
        let mut out = vec![D::zero(); y.len()];
        self.rhs_into(t, piece, y, damping, &mut out, &mut Scratch::default());
        out
    }

    /// [`Self::rhs`] into `out` (of `y`'s length), with the buffers of the evaluation in `scratch`:
    /// no allocation once `scratch` has served a chain of this size.
    pub fn rhs_into<D: Scalar>(
        &self,
        t: f64,
        piece: f64,
        y: &[D],
        damping: &[D],
        out: &mut [D],
        scratch: &mut Scratch<D>,
    ) {
        let n = self.n_links();
        let (theta, omega) = y.split_at(n);
        let loads = LoadsAt::Blend { from: &self.passive, to: &self.loaded, s: self.forcing.factor(t, piece) };
        let (rate, acc) = out.split_at_mut(n);
        rate.copy_from_slice(omega);
        self.acceleration_into(loads, theta, omega, damping, acc, scratch);
    }

    /// Projects `y = (θ, θ̇)` onto `Φ(θ) = 0` (Gauss–Newton along `∇Φ`, a fixed number of sweeps so that
    /// dual parts follow one smooth map) and then `θ̇` onto `Φ̇ = 0` (orthogonally, along `∇Φ`).
    pub fn project<D: Scalar>(&self, y: &mut [D]) {
        let n = self.n_links();
        let (theta, omega) = y.split_at_mut(n);
        let mut trig: Vec<(D, D)> = Vec::with_capacity(n);
        let mut g: Vec<D> = Vec::with_capacity(n);
        for _ in 0..PROJECTION_SWEEPS {
            // Φ ([`Self::constraint`]) and ∇Φ ([`Self::constraint_gradient`]) from one sin/cos per
            // link.
            trig.clear();
            trig.extend(theta.iter().map(|t| t.sin_cos()));
            let phi: D = trig.iter().zip(&self.lengths).map(|(&(s, _), &l)| s * l).sum();
            g.clear();
            g.extend(trig.iter().zip(&self.lengths).map(|(&(_, c), &l)| c * l));
            let gg: D = g.iter().map(|&v| v * v).sum();
            let step = phi / gg;
            for i in 0..n {
                theta[i] -= g[i] * step;
            }
        }
        let g = self.constraint_gradient(theta);
        let gg: D = g.iter().map(|&v| v * v).sum();
        let rate: D = g.iter().zip(omega.iter()).map(|(&a, &b)| a * b).sum::<D>() / gg;
        for i in 0..n {
            omega[i] -= g[i] * rate;
        }
    }

    /// Energies `(T, U, V)` in J: kinetic, strain and the potential of the loads at time `t` (the
    /// latter up to a constant; meaningful for constant loads).
    pub fn energies(&self, t: f64, piece: f64, y: &[f64]) -> (f64, f64, f64) {
        let n = self.n_links();
        let (theta, omega) = y.split_at(n);
        let kinetic = self.kinetic_energy(theta, omega);
        let strain = spine_model::energy::strain_energy(theta, &self.theta0, &self.stiffness);
        let potential = self.load_potential(&self.loads_at(t, piece), theta);
        (kinetic, strain, potential)
    }

    /// Dissipated power `θ̇ᵀ C_m θ̇ = Σ C_i (θ̇_i − θ̇_{i−1})²`, W.
    pub fn dissipation(&self, omega: &[f64]) -> f64 {
        let n = omega.len();
        (0..=n)
            .map(|i| {
                let right = if i < n { omega[i] } else { 0.0 };
                let left = if i > 0 { omega[i - 1] } else { 0.0 };
                self.damping[i] * (right - left).powi(2)
            })
            .sum()
    }
}

/// The link loads at one instant: given, or blended between the passive load and the passive
/// load plus the full actuation without writing the blend out ([`LinkLoads::lerp_at`], what
/// [`Dynamics::loads_at`] writes out).
#[derive(Clone, Copy)]
pub(crate) enum LoadsAt<'a> {
    Given(&'a LinkLoads),
    Blend { from: &'a LinkLoads, to: &'a LinkLoads, s: f64 },
}

impl LoadsAt<'_> {
    /// `(vertical_i, axial_i)`, N.
    fn at(&self, i: usize) -> (f64, f64) {
        match *self {
            LoadsAt::Given(l) => (l.vertical[i], l.axial[i]),
            LoadsAt::Blend { from, to, s } => LinkLoads::lerp_at(from, to, s, i),
        }
    }
}

/// One link's terms of the centrifugal sums ([`Dynamics::velocity_terms`]): `μ_i`, `w_i` and the
/// `μ`-weighted sum of `w` beyond the link.
#[derive(Clone, Copy)]
struct TipSums<D> {
    coupling: f64,
    w: (D, D),
    after: (D, D),
}

/// The buffers of one evaluation of the accelerations ([`Dynamics::rhs_into`]), kept from one
/// evaluation to the next: `(sin θ_i, cos θ_i)`, the centrifugal sums, `Q`, `∇Φ`, `M⁻¹∇Φ` and the
/// articulated-body factors of `M`.
pub struct Scratch<D> {
    trig: Vec<(D, D)>,
    tip: Vec<TipSums<D>>,
    q: Vec<D>,
    g: Vec<D>,
    mg: Vec<D>,
    chain: ArticulatedChain<D>,
}

impl<D> Default for Scratch<D> {
    fn default() -> Self {
        Self {
            trig: Vec::new(),
            tip: Vec::new(),
            q: Vec::new(),
            g: Vec::new(),
            mg: Vec::new(),
            chain: ArticulatedChain::default(),
        }
    }
}

/// Gauss–Newton sweeps of [`Dynamics::project`]; the first leaves `|Φ|` at the square of the step's
/// drift, the second at round-off.
pub(crate) const PROJECTION_SWEEPS: usize = 3;

/// Moments of joint elements with coefficients `c_0..c_N` acting on the relative motion of
/// neighbouring links: `(c_i (x_i − x_{i−1}) − c_{i+1} (x_{i+1} − x_i))` with `x_{−1} = x_N = 0`
/// (ground and slider). For springs `x = θ − θ0` (the `K_m Δθ` of eq. (47)); for dampers `x = θ̇`.
pub fn joint_moments<D: ChainNumber>(coefficients: &[D], x: &[D]) -> Vec<D> {
    let n = x.len();
    let at = |i: isize| if i < 0 || i as usize >= n { D::from(0.0) } else { x[i as usize] };
    (0..n)
        .map(|i| {
            let i = i as isize;
            coefficients[i as usize] * (at(i) - at(i - 1)) - coefficients[i as usize + 1] * (at(i + 1) - at(i))
        })
        .collect()
}
