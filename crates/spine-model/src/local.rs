//! Local elements: scalar functions of a few variables, written once over [`Elementary`], whose
//! gradients and Hessians come from forward AD with fixed-size duals.
//!
//! Every function of the design problem (eq. (33)) is a sum of such elements: a joint residual
//! touches nine variables ([`crate::residual::slot`]), a link's rise or run two, a spring's energy
//! five. Evaluating elements one by one with `DualSVec64<M>` (gradient) or `Dual2SVec64<M>`
//! (Hessian) costs O(M²) per element and O(N) in total, with no allocation.
//!
//! The states enter either as absolute angles `θ` ([`JointResidual`], [`SpringEnergy`], the link
//! elements with `deflection: false`) or as deflections `u = θ − θ0` from the unloaded shape
//! ([`DeflectionJointResidual`], [`DeflectionSpringEnergy`], `deflection: true`). The springs act
//! on the deflections; formed as `θ − θ0` from two angles of about 0.5 rad a deflection carries a
//! round-off of about 1e-16 rad, which a stiff spring turns into a residual above the solver's
//! tolerance ([`crate::residual::Joint::residual`]). Geometry uses `θ = θ0 + u`.

mod criteria;
mod joints;
mod links;

pub use criteria::{LinkWork, MomentPower, SpringStiffness};
pub use joints::{joint_slot, DeflectionJointResidual, JointResidual};
pub use links::{DeflectionSpringEnergy, Difference, HeightStep, LinkRise, LinkRun, SpringEnergy};

use crate::jet::{Elementary, Jet, Jet2};
use crate::residual::LinkTerms;
use crate::tangent::TangentJet;
use nalgebra::{Const, U1};
use num_dual::{Dual2SVec64, DualSVec64, HyperDualSVec64};

/// A scalar function of `M` local variables.
pub trait Element<const M: usize> {
    /// Pairs `(a, b)` with `a ≥ b` of local slots whose second derivative can be nonzero; all other
    /// entries of the local Hessian are zero for every input (tested).
    const HESSIAN_PAIRS: &'static [(usize, usize)];

    /// The value at the local variables `x`.
    fn eval<D: Elementary>(&self, x: &[D; M]) -> D;

    /// The value at `x` with each of the element's constants (span, load resultants, `C_K`)
    /// lifted into `D` by `lift(constant, rate)`, where `rates` holds, in the element's own shape,
    /// the constants' rates along a parameter of the problem. With [`TangentJet::moving`] as
    /// `lift`, one pass gives the exact rates of the value and the gradient ([`rates`]); with
    /// `|c, _| c` lifted plainly it is [`Element::eval`] (tested). An element without constants
    /// returns `self.eval(x)`.
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; M]) -> D;

    /// The local Hessian at `x`; entries outside [`Element::HESSIAN_PAIRS`] (and their mirror
    /// images) may be left zero. The default is one forward pass with second-order duals over all
    /// `M` slots ([`full_hessian`]); an element that knows it is linear in some slots may compute
    /// fewer derivatives, still by AD of [`Element::eval`] (tested against the default).
    fn hessian(&self, x: &[f64; M]) -> [[f64; M]; M]
    where
        Self: Sized,
    {
        full_hessian(self, x).2
    }

    /// Pairs of [`Element::HESSIAN_PAIRS`] whose second derivative is the same at every `x` (a
    /// bilinear `factor × angle` term): an assembly takes them once, when it registers the element,
    /// and [`Element::varying_hessian`] may leave them out (tested: constant at random points).
    const CONSTANT_PAIRS: &'static [(usize, usize)] = &[];

    /// The local Hessian at `x` without the [`Element::CONSTANT_PAIRS`] (they may be left zero);
    /// the default is [`Element::hessian`].
    fn varying_hessian(&self, x: &[f64; M]) -> [[f64; M]; M]
    where
        Self: Sized,
    {
        self.hessian(x)
    }
}

/// Value of an element.
pub fn value<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> f64 {
    element.eval(x)
}

/// Value and gradient of an element by one forward pass with a branch-free [`Jet<M>`] (every
/// slot seeded, so no lane is optional).
pub fn gradient<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> (f64, [f64; M]) {
    let seeded: [Jet<M>; M] = std::array::from_fn(|k| Jet::variable(x[k], k));
    let r = element.eval(&seeded);
    (r.re, r.eps)
}

/// Value and gradient of an element by one forward pass with num-dual's `DualSVec64<M>`: the
/// reference [`gradient`] is tested against.
pub fn gradient_num_dual<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> (f64, [f64; M]) {
    let seeded: [DualSVec64<M>; M] = std::array::from_fn(|k| DualSVec64::from_re(x[k]).derivative(k));
    let r = element.eval(&seeded);
    let g = r.eps.unwrap_generic(Const::<M>, U1);
    (r.re, std::array::from_fn(|k| g[k]))
}

/// The rates along a parameter of the problem of an element's value and gradient at `x`, when
/// its constants move at `rates` (the element's shape holding `dc/dp`): `(∂e/∂p, ∂∇e/∂p)`, exact,
/// by one pass of a [`TangentJet`] (`ε₁` over the slots, `ε₂` the parameter).
pub fn rates<const M: usize, E: Element<M>>(element: &E, rates: &E, x: &[f64; M]) -> (f64, [f64; M]) {
    let seeded: [TangentJet<M>; M] = std::array::from_fn(|k| TangentJet::variable(x[k], k));
    let r = element.eval_moving(rates, TangentJet::moving, &seeded);
    (r.rate, r.eps_rate)
}

/// The local Hessian by the element's own method ([`Element::hessian`]).
pub fn hessian<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> [[f64; M]; M] {
    element.hessian(x)
}

/// Value, gradient and Hessian of an element by one forward pass with a branch-free second-order
/// [`Jet2<M>`] over all its slots: the default [`Element::hessian`].
pub fn full_hessian<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> (f64, [f64; M], [[f64; M]; M]) {
    let seeded: [Jet2<M>; M] = std::array::from_fn(|k| Jet2::variable(x[k], k));
    let r = element.eval(&seeded);
    (r.re, r.grad, r.hess)
}

/// Value, gradient and Hessian of an element by one forward pass with num-dual's
/// `Dual2SVec64<M>` over all its slots: the reference for [`full_hessian`] and every specialised
/// [`Element::hessian`].
pub fn full_hessian_num_dual<const M: usize, E: Element<M>>(
    element: &E,
    x: &[f64; M],
) -> (f64, [f64; M], [[f64; M]; M]) {
    let seeded: [Dual2SVec64<M>; M] = std::array::from_fn(|k| Dual2SVec64::from_re(x[k]).derivative(k));
    let r = element.eval(&seeded);
    let g = r.v1.unwrap_generic(U1, Const::<M>);
    let h = r.v2.unwrap_generic(Const::<M>, Const::<M>);
    (r.re, std::array::from_fn(|k| g[k]), std::array::from_fn(|a| std::array::from_fn(|b| h[(a, b)])))
}

/// The Hessian block of a joint residual over its nonlinear slots `core` (lanes 0, 1, 2 of the
/// jets), from its link's terms: `r = springs − load − reaction`, the springs linear there.
pub(crate) fn link_block<const M: usize>(core: [usize; 3], link: LinkTerms<Jet2<3>>) -> [[f64; M]; M] {
    let mut h = [[0.0; M]; M];
    let terms = link.load + link.reaction;
    for (a, &sa) in core.iter().enumerate() {
        for (b, &sb) in core.iter().enumerate() {
            h[sa][sb] = -terms.hess[a][b];
        }
    }
    h
}

/// The bilinear block `∂²/∂factor∂angle` of an element whose only nonlinearity outside its core
/// slots is `factor × angle`, written into `h` (both triangles), by one hyper-dual pass (`ε₁` over
/// `factors`, `ε₂` over `angles`).
pub(crate) fn mixed_block<const M: usize, const F: usize, const A: usize, E: Element<M>>(
    element: &E,
    x: &[f64; M],
    h: &mut [[f64; M]; M],
    factors: [usize; F],
    angles: [usize; A],
) {
    let mixed: [HyperDualSVec64<F, A>; M] = std::array::from_fn(|k| {
        let mut d = HyperDualSVec64::from_re(x[k]);
        if let Some(p) = factors.iter().position(|&f| f == k) {
            d = d.derivative1(p);
        }
        if let Some(q) = angles.iter().position(|&a| a == k) {
            d = d.derivative2(q);
        }
        d
    });
    let e12 = element.eval(&mixed).eps1eps2.unwrap_generic(Const::<F>, Const::<A>);
    for (a, &sa) in factors.iter().enumerate() {
        for (b, &sb) in angles.iter().enumerate() {
            h[sa][sb] = e12[(a, b)];
            h[sb][sa] = e12[(a, b)];
        }
    }
}
