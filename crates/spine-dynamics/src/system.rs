//! The spine's equations of motion as an [`OdeSystem`] in `y = (θ, θ̇)`, with exact Jacobians and
//! damper rates ([`Dynamics::rates_at`]: real factorisations and `O(N)` solves) and
//! exact Jacobian–vector products (one [`num_dual::Dual64`] directional pass each).

use crate::eom::{Dynamics, Scratch};
use crate::integrator::OdeSystem;
use crate::linearization::Linearization;
use crate::newton::ChainLinearization;
use crate::ode::{DenseProducts, VectorJacobian};
pub use crate::parameters::Parameters;
use crate::rates::{RatesAt, RatesIn};
use crate::vjp::AccelerationAdjoint;
use nalgebra::DMatrix;
use num_dual::Dual64;
use spine_model::Scalar;
use std::cell::RefCell;

/// Index-1 form of the constrained equations of motion with projection onto `Φ = 0`, `Φ̇ = 0`
/// after every step, with the sensitivities to `parameters`.
pub struct SpineOde<'a> {
    pub dynamics: &'a Dynamics,
    pub parameters: Parameters,
}

impl SpineOde<'_> {
    fn damping<D: Scalar>(&self) -> Vec<D> {
        self.dynamics.damping.iter().map(|&c| D::from(c)).collect()
    }
}

fn seeded(y: &[f64], direction: usize) -> Vec<Dual64> {
    y.iter()
        .enumerate()
        .map(|(i, &v)| if i == direction { Dual64::from(v).derivative() } else { Dual64::from(v) })
        .collect()
}

impl SpineOde<'_> {
    /// `[0 I; ∂θ̈/∂θ ∂θ̈/∂θ̇]` at a prepared state.
    fn jacobian_from(&self, at: &RatesAt<'_>, t: f64, piece: f64) -> DMatrix<f64> {
        let n = self.dynamics.n_links();
        let loads = self.dynamics.loads_at(t, piece);
        let mut jac = DMatrix::zeros(2 * n, 2 * n);
        for k in 0..n {
            jac[(k, n + k)] = 1.0;
        }
        for (block, what) in [(0, RatesIn::Angles(&loads)), (n, RatesIn::AngularVelocities)] {
            jac.view_mut((n, block), (n, n)).copy_from(&at.rates(what));
        }
        jac
    }

    /// `∂f/∂p` at a prepared state (`dim` rows; no columns without parameters).
    fn params_from(&self, at: &RatesAt<'_>, dim: usize) -> DMatrix<f64> {
        let p = self.n_params();
        let n = self.dynamics.n_links();
        let mut out = DMatrix::zeros(dim, p);
        let what = match self.parameters {
            Parameters::None => return out,
            Parameters::Dampers => RatesIn::Dampers,
            Parameters::Springs => RatesIn::Springs,
        };
        out.view_mut((n, 0), (n, p)).copy_from(&at.rates(what));
        out
    }
}

impl OdeSystem for SpineOde<'_> {
    fn dim(&self) -> usize {
        2 * self.dynamics.n_links()
    }

    fn rhs(&self, t: f64, piece: f64, y: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; y.len()];
        self.rhs_into(t, piece, y, &mut out);
        out
    }

    /// [`Dynamics::rhs_into`] with this thread's buffers ([`Scratch`], kept from call to call): the
    /// stages' evaluations allocate nothing.
    fn rhs_into(&self, t: f64, piece: f64, y: &[f64], out: &mut [f64]) {
        thread_local! {
            static SCRATCH: RefCell<Scratch<f64>> = RefCell::new(Scratch::default());
        }
        SCRATCH.with_borrow_mut(|scratch| self.dynamics.rhs_into(t, piece, y, &self.dynamics.damping, out, scratch));
    }

    /// `[0 I; ∂θ̈/∂θ ∂θ̈/∂θ̇]` from [`Dynamics::rates_at`] (real factorisations of
    /// `M`, an `O(N)` solve per column).
    fn jacobian(&self, t: f64, piece: f64, y: &[f64]) -> DMatrix<f64> {
        let n = self.dynamics.n_links();
        let at = self.dynamics.rates_at(&y[..n], &y[n..]);
        self.jacobian_from(&at, t, piece)
    }

    /// Both from one factorisation of `M` ([`Dynamics::rates_at`]).
    fn jacobian_and_params(&self, t: f64, piece: f64, y: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.dynamics.n_links();
        let at = self.dynamics.rates_at(&y[..n], &y[n..]);
        (self.jacobian_from(&at, t, piece), self.params_from(&at, y.len()))
    }

    /// The structured `J̃` of [`crate::newton`]: `O(N)` per factorisation.
    fn linearize(&self, t: f64, piece: f64, y: &[f64]) -> Box<dyn Linearization> {
        Box::new(ChainLinearization::new(self.dynamics, t, piece, y))
    }

    /// One directional dual pass, `O(N)`.
    fn jacobian_times(&self, t: f64, piece: f64, y: &[f64], v: &[f64]) -> Vec<f64> {
        let yd: Vec<Dual64> = y.iter().zip(v).map(|(&a, &b)| Dual64::new(a, b)).collect();
        self.dynamics.rhs(t, piece, &yd, &self.damping()).iter().map(|f| f.eps).collect()
    }

    fn n_params(&self) -> usize {
        match self.parameters {
            Parameters::None => 0,
            Parameters::Dampers => self.dynamics.damping.len(),
            Parameters::Springs => self.dynamics.stiffness.len(),
        }
    }

    /// `∂f/∂p`: zero for `θ`, [`Dynamics::rates_at`] for `θ̈` (all dampers or springs through one
    /// real factorisation of `M`; the loads depend on neither, so `t` does not enter).
    fn rhs_params(&self, _t: f64, _piece: f64, y: &[f64]) -> DMatrix<f64> {
        let n = self.dynamics.n_links();
        self.params_from(&self.dynamics.rates_at(&y[..n], &y[n..]), y.len())
    }

    fn project(&self, y: &mut [f64]) {
        self.dynamics.project(y);
    }

    /// All columns at once in real arithmetic ([`Dynamics::project_tangent`]).
    fn project_sensitivities(&self, y: &[f64], s: &mut DMatrix<f64>) {
        self.dynamics.project_tangent(y, s);
    }

    /// `O(N)` per product ([`crate::vjp`]): `(vᵀ ∂f/∂y, vᵀ ∂f/∂p)` with `f = (θ̇, θ̈)`, so `vᵀ
    /// ∂f/∂θ = v_θ̇ᵀ ∂θ̈/∂θ` and `vᵀ ∂f/∂θ̇ = v_θ + v_θ̇ᵀ ∂θ̈/∂θ̇`. Where `M(θ)` has no factorisation,
    /// the dense path (NaN).
    fn vector_jacobian(&self, t: f64, piece: f64, y: &[f64]) -> Box<dyn VectorJacobian + '_> {
        match self.dynamics.acceleration_adjoint(t, piece, y, self.parameters) {
            Some(at) => Box::new(ChainProducts(at)),
            None => {
                let (jac, params) = self.jacobian_and_params(t, piece, y);
                Box::new(DenseProducts::new(&jac, &params))
            }
        }
    }

    fn project_adjoint(&self, y: &[f64], a: &mut [f64]) {
        self.dynamics.project_adjoint(y, a);
    }

    fn breakpoints(&self, t0: f64, t1: f64) -> Vec<f64> {
        self.dynamics.forcing.breakpoints(t0, t1)
    }
}

/// [`SpineOde`]'s vector–Jacobian products by [`AccelerationAdjoint`].
struct ChainProducts<'a>(AccelerationAdjoint<'a>);

impl VectorJacobian for ChainProducts<'_> {
    fn n_params(&self) -> usize {
        self.0.n_params()
    }

    fn products_into(&self, v: &[f64], state: &mut [f64], params: &mut [f64]) {
        let n = v.len() / 2;
        let (v_theta, v_omega) = v.split_at(n);
        let (angles, velocities) = state.split_at_mut(n);
        self.0.products_into(v_omega, angles, velocities, params);
        for (s, t) in velocities.iter_mut().zip(v_theta) {
            *s += t;
        }
    }
}

/// The reference path of [`SpineOde`]'s `∂f/∂y` and `∂f/∂C`: a dual pass of the whole right-hand
/// side per column. The tests hold the fast path ([`Dynamics::rates_at`]) to it.
pub mod reference {
    use super::*;

    /// `∂f/∂y` by `2N` dual passes.
    pub fn jacobian(ode: &SpineOde<'_>, t: f64, piece: f64, y: &[f64]) -> DMatrix<f64> {
        let n = y.len();
        let damping: Vec<Dual64> = ode.damping();
        let mut jac = DMatrix::zeros(n, n);
        for k in 0..n {
            let f = ode.dynamics.rhs(t, piece, &seeded(y, k), &damping);
            for i in 0..n {
                jac[(i, k)] = f[i].eps;
            }
        }
        jac
    }

    /// `∂f/∂p` by `N + 1` dual passes (dampers), or by central differences of the right-hand side
    /// in each spring (the equations of motion take the springs as plain numbers; `f` is affine in
    /// `K`, so the differences are exact to round-off).
    pub fn rhs_params(ode: &SpineOde<'_>, t: f64, piece: f64, y: &[f64]) -> DMatrix<f64> {
        let p = ode.n_params();
        let mut out = DMatrix::zeros(y.len(), p);
        let yd: Vec<Dual64> = y.iter().map(|&v| Dual64::from(v)).collect();
        for k in 0..p {
            let column: Vec<f64> = match ode.parameters {
                Parameters::None => unreachable!("no columns without parameters"),
                Parameters::Dampers => {
                    let damping = seeded(&ode.dynamics.damping, k);
                    ode.dynamics.rhs(t, piece, &yd, &damping).iter().map(|f| f.eps).collect()
                }
                Parameters::Springs => {
                    let h = 1e-3 * ode.dynamics.stiffness[k].abs().max(1.0);
                    let at = |sign: f64| {
                        let mut d = ode.dynamics.clone();
                        d.stiffness[k] += sign * h;
                        d.rhs(t, piece, y, &d.damping)
                    };
                    at(1.0).iter().zip(at(-1.0)).map(|(a, b)| (a - b) / (2.0 * h)).collect()
                }
            };
            out.column_mut(k).copy_from_slice(&column);
        }
        out
    }

    /// The projection's tangent map by a dual pass per column.
    pub fn project_sensitivities(ode: &SpineOde<'_>, y: &[f64], s: &mut DMatrix<f64>) {
        for k in 0..s.ncols() {
            let mut yd: Vec<Dual64> = y.iter().enumerate().map(|(i, &v)| Dual64::new(v, s[(i, k)])).collect();
            ode.dynamics.project(&mut yd);
            for i in 0..y.len() {
                s[(i, k)] = yd[i].eps;
            }
        }
    }
}
