//! Local elements: scalar functions of a few variables, written once over [`Scalar`], whose
//! gradients and Hessians come from forward AD with fixed-size duals.
//!
//! Every function of the design problem (eq. (33)) is a sum of such elements: a joint residual
//! touches nine variables ([`crate::residual::slot`]), a link's rise or run two, a spring's energy
//! five. Evaluating elements one by one with `DualSVec64<M>` (gradient) or `Dual2SVec64<M>`
//! (Hessian) costs O(M²) per element and O(N) in total, with no allocation.

use crate::kinematics::{link_length, link_rise};
use crate::residual::{slot, JointStencil};
use crate::Scalar;
use nalgebra::{Const, U1};
use num_dual::{Dual2SVec64, DualSVec64, HyperDualSVec64};

/// A scalar function of `M` local variables.
pub trait Element<const M: usize> {
    /// Pairs `(a, b)` with `a ≥ b` of local slots whose second derivative can be nonzero; all other
    /// entries of the local Hessian are zero for every input (tested).
    const HESSIAN_PAIRS: &'static [(usize, usize)];

    /// The value at the local variables `x`.
    fn eval<D: Scalar>(&self, x: &[D; M]) -> D;

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
}

/// Value of an element.
pub fn value<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> f64 {
    element.eval(x)
}

/// Value and gradient of an element by one forward pass with `DualSVec64<M>`.
pub fn gradient<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> (f64, [f64; M]) {
    let seeded: [DualSVec64<M>; M] = std::array::from_fn(|k| DualSVec64::from_re(x[k]).derivative(k));
    let r = element.eval(&seeded);
    let g = r.eps.unwrap_generic(Const::<M>, U1);
    (r.re, std::array::from_fn(|k| g[k]))
}

/// The local Hessian by the element's own method ([`Element::hessian`]).
pub fn hessian<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> [[f64; M]; M] {
    element.hessian(x)
}

/// Value, gradient and Hessian of an element by one forward pass with `Dual2SVec64<M>` over all
/// its slots: the reference for every specialised [`Element::hessian`].
pub fn full_hessian<const M: usize, E: Element<M>>(element: &E, x: &[f64; M]) -> (f64, [f64; M], [[f64; M]; M]) {
    let seeded: [Dual2SVec64<M>; M] = std::array::from_fn(|k| Dual2SVec64::from_re(x[k]).derivative(k));
    let r = element.eval(&seeded);
    let g = r.v1.unwrap_generic(U1, Const::<M>);
    let h = r.v2.unwrap_generic(Const::<M>, Const::<M>);
    (r.re, std::array::from_fn(|k| g[k]), std::array::from_fn(|a| std::array::from_fn(|b| h[(a, b)])))
}

/// Joint row `i` of the equilibrium residual (eq. (5)) with the stiffness slots holding the scaled
/// variable `k = K / C_K` (eq. (34)): slots as in [`slot`]. Missing neighbours hold zero.
#[derive(Clone, Copy, Debug)]
pub struct JointResidual {
    /// Horizontal span `a_i`, m.
    pub span: f64,
    /// Vertical and axial load resultants on link `i` (eq. (48)), N.
    pub vertical: f64,
    pub axial: f64,
    /// `C_K` of eq. (34), N·m/rad per unit of the stiffness variable.
    pub stiffness_scale: f64,
}

impl Element<{ slot::COUNT }> for JointResidual {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[
        (slot::STIFFNESS_LEFT, slot::THETA_PREV),
        (slot::STIFFNESS_LEFT, slot::THETA),
        (slot::STIFFNESS_LEFT, slot::THETA0_PREV),
        (slot::STIFFNESS_LEFT, slot::THETA0),
        (slot::STIFFNESS_RIGHT, slot::THETA),
        (slot::STIFFNESS_RIGHT, slot::THETA_NEXT),
        (slot::STIFFNESS_RIGHT, slot::THETA0),
        (slot::STIFFNESS_RIGHT, slot::THETA0_NEXT),
        (slot::THETA, slot::THETA),
        (slot::LAMBDA, slot::THETA),
        (slot::THETA0, slot::THETA),
        (slot::THETA0, slot::LAMBDA),
        (slot::THETA0, slot::THETA0),
    ];

    /// The residual is linear in `θ_{i±1}`, `θ0_{i±1}`, `K_i`, `K_{i+1}` and `λ`, and its only
    /// products of these are `K × angle`: second-order duals over `(θ_i, λ, θ0_i)` give the
    /// nonlinear block, one hyper-dual pass (`ε₁` over the two stiffnesses, `ε₂` over the six
    /// angles) the bilinear block. About a third of the work of [`full_hessian`].
    fn hessian(&self, x: &[f64; slot::COUNT]) -> [[f64; slot::COUNT]; slot::COUNT] {
        use slot::*;
        const CORE: [usize; 3] = [THETA, LAMBDA, THETA0];
        const FACTORS: [usize; 2] = [STIFFNESS_LEFT, STIFFNESS_RIGHT];
        const ANGLES: [usize; 6] = [THETA_PREV, THETA, THETA_NEXT, THETA0_PREV, THETA0, THETA0_NEXT];
        let mut h = [[0.0; slot::COUNT]; slot::COUNT];

        let core: [Dual2SVec64<3>; slot::COUNT] = std::array::from_fn(|k| {
            let d = Dual2SVec64::from_re(x[k]);
            CORE.iter().position(|&c| c == k).map_or(d, |p| d.derivative(p))
        });
        let r = self.eval(&core);
        let v2 = r.v2.unwrap_generic(Const::<3>, Const::<3>);
        for (a, &sa) in CORE.iter().enumerate() {
            for (b, &sb) in CORE.iter().enumerate() {
                h[sa][sb] = v2[(a, b)];
            }
        }

        let mixed: [HyperDualSVec64<2, 6>; slot::COUNT] = std::array::from_fn(|k| {
            let mut d = HyperDualSVec64::from_re(x[k]);
            if let Some(p) = FACTORS.iter().position(|&f| f == k) {
                d = d.derivative1(p);
            }
            if let Some(q) = ANGLES.iter().position(|&a| a == k) {
                d = d.derivative2(q);
            }
            d
        });
        let r = self.eval(&mixed);
        let e12 = r.eps1eps2.unwrap_generic(Const::<2>, Const::<6>);
        for (a, &sa) in FACTORS.iter().enumerate() {
            for (b, &sb) in ANGLES.iter().enumerate() {
                h[sa][sb] = e12[(a, b)];
                h[sb][sa] = e12[(a, b)];
            }
        }
        h
    }

    fn eval<D: Scalar>(&self, x: &[D; slot::COUNT]) -> D {
        let mut values = *x;
        values[slot::STIFFNESS_LEFT] = x[slot::STIFFNESS_LEFT] * self.stiffness_scale;
        values[slot::STIFFNESS_RIGHT] = x[slot::STIFFNESS_RIGHT] * self.stiffness_scale;
        JointStencil { values, has_prev: true, has_next: true }.residual(self.span, self.vertical, self.axial)
    }
}

/// A link's rise `L_i sin θ_i = a_i sin θ_i / cos θ0_i`, m; local variables `[θ_i, θ0_i]`.
/// Summed over the links it is `Φ(θ)` (the end constraint).
#[derive(Clone, Copy, Debug)]
pub struct LinkRise {
    pub span: f64,
}

impl Element<2> for LinkRise {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Scalar>(&self, x: &[D; 2]) -> D {
        link_rise(self.span, x[1], x[0])
    }
}

/// A link's run `L_i cos θ_i = a_i cos θ_i / cos θ0_i`, m; local variables `[θ_i, θ0_i]`.
/// Summed over the links it is `X_{N+1}(θ)`.
#[derive(Clone, Copy, Debug)]
pub struct LinkRun {
    pub span: f64,
}

impl Element<2> for LinkRun {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Scalar>(&self, x: &[D; 2]) -> D {
        link_length(self.span, x[1]) * x[0].cos()
    }
}

/// One step of the unloaded node heights, `Y0_{j+1} − Y0_j − a_j tan θ0_j` (m), local variables
/// `[Y0_{j+1}, Y0_j, θ0_j]`. Zero for every link is the lifted form of the node heights
/// `Y0_j = Σ_{k<j} a_k tan θ0_k`; with `Y0_1 = Y0_{N+1} = 0` it contains `Φ(θ0) = 0`.
#[derive(Clone, Copy, Debug)]
pub struct HeightStep {
    pub span: f64,
}

impl Element<3> for HeightStep {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(2, 2)];
    fn eval<D: Scalar>(&self, x: &[D; 3]) -> D {
        x[0] - x[1] - x[2].tan() * self.span
    }
}

/// Spring `j`'s strain energy `½ K_j (Δθ_j − Δθ_{j−1})²`, J, with `K_j = C_K k_j`; local
/// variables `[θ_{j−1}, θ0_{j−1}, θ_j, θ0_j, k_j]` (a missing neighbour holds zero).
#[derive(Clone, Copy, Debug)]
pub struct SpringEnergy {
    pub stiffness_scale: f64,
}

impl Element<5> for SpringEnergy {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[
        (0, 0),
        (1, 0),
        (1, 1),
        (2, 0),
        (2, 1),
        (2, 2),
        (3, 0),
        (3, 1),
        (3, 2),
        (3, 3),
        (4, 0),
        (4, 1),
        (4, 2),
        (4, 3),
    ];
    fn eval<D: Scalar>(&self, x: &[D; 5]) -> D {
        let rel = (x[2] - x[3]) - (x[0] - x[1]);
        x[4] * self.stiffness_scale * rel * rel * 0.5
    }
}

/// The difference of two variables `x_0 − x_1` (the relative angle `θ0_i − θ0_{i+1}`); linear.
#[derive(Clone, Copy, Debug)]
pub struct Difference;

impl Element<2> for Difference {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[];
    fn eval<D: Scalar>(&self, x: &[D; 2]) -> D {
        x[0] - x[1]
    }
}
