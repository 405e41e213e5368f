//! The problem an integrator solves: a first-order system `ẏ = f(t, y; p)` ([`OdeSystem`]),
//! apart from any method.

use crate::linearization::{DenseJacobian, Linearization};
use nalgebra::{DMatrix, DVector};

/// A first-order system `ẏ = f(t, y; p)`.
pub trait OdeSystem {
    /// Length of `y`.
    fn dim(&self) -> usize;
    /// `f(t, y)`. `piece` is a time inside the current smooth piece (see [`OdeSystem::breakpoints`]).
    fn rhs(&self, t: f64, piece: f64, y: &[f64]) -> Vec<f64>;
    /// [`OdeSystem::rhs`] into `out` (of length [`OdeSystem::dim`]); the implicit stages call this
    /// one, so an implementation can spare the allocation (default: through `rhs`).
    fn rhs_into(&self, t: f64, piece: f64, y: &[f64], out: &mut [f64]) {
        out.copy_from_slice(&self.rhs(t, piece, y));
    }
    /// `∂f/∂y`, `dim × dim`.
    fn jacobian(&self, t: f64, piece: f64, y: &[f64]) -> DMatrix<f64>;
    /// `J̃ ≈ ∂f/∂y` at `(t, y)` for the Newton matrices of the implicit stages (default: the dense
    /// [`OdeSystem::jacobian`]). An approximation changes how fast the stages converge, not to what.
    fn linearize(&self, t: f64, piece: f64, y: &[f64]) -> Box<dyn Linearization> {
        Box::new(DenseJacobian(self.jacobian(t, piece, y)))
    }
    /// `(∂f/∂y) v`, exact (default: through [`OdeSystem::jacobian`]); sensitivities use it.
    fn jacobian_times(&self, t: f64, piece: f64, y: &[f64], v: &[f64]) -> Vec<f64> {
        (self.jacobian(t, piece, y) * DVector::from_column_slice(v)).as_slice().to_vec()
    }
    /// Number of parameters `p` whose sensitivities can be propagated.
    fn n_params(&self) -> usize {
        0
    }
    /// `∂f/∂p`, `dim × n_params`.
    fn rhs_params(&self, _t: f64, _piece: f64, _y: &[f64]) -> DMatrix<f64> {
        DMatrix::zeros(self.dim(), 0)
    }
    /// [`OdeSystem::jacobian`] and [`OdeSystem::rhs_params`] at one point, where computing them
    /// together shares work (default: one after the other).
    fn jacobian_and_params(&self, t: f64, piece: f64, y: &[f64]) -> (DMatrix<f64>, DMatrix<f64>) {
        (self.jacobian(t, piece, y), self.rhs_params(t, piece, y))
    }
    /// `f`'s vector–Jacobian products at `(t, y)`, for any number of vectors (the adjoint's,
    /// [`crate::integrator::adjoint`]; default: through the dense
    /// [`OdeSystem::jacobian_and_params`]).
    fn vector_jacobian(&self, t: f64, piece: f64, y: &[f64]) -> Box<dyn VectorJacobian + '_> {
        let (jac, params) = self.jacobian_and_params(t, piece, y);
        Box::new(DenseProducts::new(&jac, &params))
    }
    /// Moves `y` onto the invariant manifold (default: nothing).
    fn project(&self, _y: &mut [f64]) {}
    /// `S ← (∂ project / ∂y) S` at the unprojected `y` (default: identity).
    fn project_sensitivities(&self, _y: &[f64], _s: &mut DMatrix<f64>) {}
    /// `a ← (∂ project / ∂y)ᵀ a` at the unprojected `y`, the transpose of
    /// [`OdeSystem::project_sensitivities`] (default: identity; a system that projects supplies
    /// both).
    fn project_adjoint(&self, _y: &[f64], _a: &mut [f64]) {}
    /// Instants in `(t0, t1)` where `f` is discontinuous in `t`, increasing.
    fn breakpoints(&self, _t0: f64, _t1: f64) -> Vec<f64> {
        Vec::new()
    }
}

/// `(vᵀ ∂f/∂y, vᵀ ∂f/∂p)` at one point ([`OdeSystem::vector_jacobian`]).
pub trait VectorJacobian {
    /// The number of parameters `p`.
    fn n_params(&self) -> usize;
    /// `vᵀ ∂f/∂y` into `state` (of `v`'s length) and `vᵀ ∂f/∂p` into `params`.
    fn products_into(&self, v: &[f64], state: &mut [f64], params: &mut [f64]);
    /// Both, allocated.
    fn products(&self, v: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (mut state, mut params) = (vec![0.0; v.len()], vec![0.0; self.n_params()]);
        self.products_into(v, &mut state, &mut params);
        (state, params)
    }
}

/// The dense products: `(∂f/∂y)ᵀ v` and `(∂f/∂p)ᵀ v`.
pub struct DenseProducts {
    jac_t: DMatrix<f64>,
    params_t: DMatrix<f64>,
}

impl DenseProducts {
    /// From `∂f/∂y` and `∂f/∂p`.
    pub fn new(jacobian: &DMatrix<f64>, params: &DMatrix<f64>) -> Self {
        Self { jac_t: jacobian.transpose(), params_t: params.transpose() }
    }
}

impl VectorJacobian for DenseProducts {
    fn n_params(&self) -> usize {
        self.params_t.nrows()
    }

    fn products_into(&self, v: &[f64], state: &mut [f64], params: &mut [f64]) {
        let v = DVector::from_column_slice(v);
        state.copy_from_slice((&self.jac_t * &v).as_slice());
        params.copy_from_slice((&self.params_t * &v).as_slice());
    }
}
