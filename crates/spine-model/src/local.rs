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

use crate::jet::{Elementary, Jet, Jet2};
use crate::kinematics::{link_length, link_rise};
use crate::residual::{slot, Joint, JointStencil, LinkTerms};
use nalgebra::{Const, U1};
use num_dual::{Dual2SVec64, DualSVec64, HyperDualSVec64};

/// A scalar function of `M` local variables.
pub trait Element<const M: usize> {
    /// Pairs `(a, b)` with `a ≥ b` of local slots whose second derivative can be nonzero; all other
    /// entries of the local Hessian are zero for every input (tested).
    const HESSIAN_PAIRS: &'static [(usize, usize)];

    /// The value at the local variables `x`.
    fn eval<D: Elementary>(&self, x: &[D; M]) -> D;

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

    /// `∂²r/∂K∂angle = ±C_K`: the eight stiffness × angle pairs, listed first above.
    const CONSTANT_PAIRS: &'static [(usize, usize)] = JointResidual::HESSIAN_PAIRS.split_at(8).0;

    /// The residual is linear in `θ_{i±1}`, `θ0_{i±1}`, `K_i`, `K_{i+1}` and `λ`, and its only
    /// products of these are `K × angle`: second-order jets over `(θ_i, λ, θ0_i)` give the
    /// nonlinear block, one hyper-dual pass (`ε₁` over the two stiffnesses, `ε₂` over the six
    /// angles) the bilinear block. About a third of the work of [`full_hessian`].
    fn hessian(&self, x: &[f64; slot::COUNT]) -> [[f64; slot::COUNT]; slot::COUNT] {
        use slot::*;
        let angles = [THETA_PREV, THETA, THETA_NEXT, THETA0_PREV, THETA0, THETA0_NEXT];
        let mut h = self.varying_hessian(x);
        mixed_block(self, x, &mut h, [STIFFNESS_LEFT, STIFFNESS_RIGHT], angles);
        h
    }

    /// The nonlinear block over `(θ_i, λ, θ0_i)` only: the springs are linear in these slots, so
    /// the block is that of the link's terms ([`Joint::link`]), by one pass of 3-lane
    /// second-order jets (tested against the full Hessian of [`Element::eval`]).
    fn varying_hessian(&self, x: &[f64; slot::COUNT]) -> [[f64; slot::COUNT]; slot::COUNT] {
        let joint = Joint { span: self.span, vertical: self.vertical, axial: self.axial };
        let link = joint.link(
            Jet2::variable(x[slot::THETA], 0),
            Jet2::variable(x[slot::THETA0], 2),
            Jet2::variable(x[slot::LAMBDA], 1),
        );
        link_block([slot::THETA, slot::LAMBDA, slot::THETA0], link)
    }

    fn eval<D: Elementary>(&self, x: &[D; slot::COUNT]) -> D {
        let mut values = *x;
        values[slot::STIFFNESS_LEFT] = x[slot::STIFFNESS_LEFT] * self.stiffness_scale;
        values[slot::STIFFNESS_RIGHT] = x[slot::STIFFNESS_RIGHT] * self.stiffness_scale;
        JointStencil { values, has_prev: true, has_next: true }.residual(self.span, self.vertical, self.axial)
    }
}

/// The local variables of a [`DeflectionJointResidual`] (link `i`): the deflections `u = θ − θ0` of links
/// `i − 1`, `i`, `i + 1` (rad; a missing neighbour holds zero), the slider reaction `λ` (N), the
/// link's unloaded angle `θ0_i` (rad) and the scaled springs `k_i`, `k_{i+1}` on either side.
pub mod joint_slot {
    pub const U_PREV: usize = 0;
    pub const U: usize = 1;
    pub const U_NEXT: usize = 2;
    pub const LAMBDA: usize = 3;
    pub const THETA0: usize = 4;
    pub const STIFFNESS_LEFT: usize = 5;
    pub const STIFFNESS_RIGHT: usize = 6;
    /// Number of slots.
    pub const COUNT: usize = 7;
}

/// [`JointResidual`] on deflections: joint row `i` of eq. (5), N·m, with the states entering as
/// `u = θ − θ0` and the stiffness slots holding `k = K / C_K` (eq. (34)); slots as in [`joint_slot`].
#[derive(Clone, Copy, Debug)]
pub struct DeflectionJointResidual {
    /// Horizontal span `a_i`, m.
    pub span: f64,
    /// Vertical and axial load resultants on link `i` (eq. (48)), N.
    pub vertical: f64,
    pub axial: f64,
    /// `C_K` of eq. (34), N·m/rad per unit of the stiffness variable.
    pub stiffness_scale: f64,
}

impl Element<{ joint_slot::COUNT }> for DeflectionJointResidual {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[
        (joint_slot::STIFFNESS_LEFT, joint_slot::U_PREV),
        (joint_slot::STIFFNESS_LEFT, joint_slot::U),
        (joint_slot::STIFFNESS_RIGHT, joint_slot::U),
        (joint_slot::STIFFNESS_RIGHT, joint_slot::U_NEXT),
        (joint_slot::U, joint_slot::U),
        (joint_slot::LAMBDA, joint_slot::U),
        (joint_slot::THETA0, joint_slot::U),
        (joint_slot::THETA0, joint_slot::LAMBDA),
        (joint_slot::THETA0, joint_slot::THETA0),
    ];

    /// `∂²r/∂k∂u = ±C_K`: the four stiffness × deflection pairs, listed first above.
    const CONSTANT_PAIRS: &'static [(usize, usize)] = DeflectionJointResidual::HESSIAN_PAIRS.split_at(4).0;

    /// The residual is linear in `u_{i±1}`, `k_i`, `k_{i+1}` and `λ`, and its only products of
    /// these are `k × u`: as [`JointResidual`]'s, with the three deflections as the angles.
    fn hessian(&self, x: &[f64; joint_slot::COUNT]) -> [[f64; joint_slot::COUNT]; joint_slot::COUNT] {
        use joint_slot::*;
        let mut h = self.varying_hessian(x);
        mixed_block(self, x, &mut h, [STIFFNESS_LEFT, STIFFNESS_RIGHT], [U_PREV, U, U_NEXT]);
        h
    }

    /// The nonlinear block over `(u_i, λ, θ0_i)` only, from the link's terms at `θ = θ0 + u`
    /// (the springs are linear in these slots).
    fn varying_hessian(&self, x: &[f64; joint_slot::COUNT]) -> [[f64; joint_slot::COUNT]; joint_slot::COUNT] {
        use joint_slot::*;
        let joint = Joint { span: self.span, vertical: self.vertical, axial: self.axial };
        let theta0 = Jet2::variable(x[THETA0], 2);
        let link = joint.link(theta0 + Jet2::variable(x[U], 0), theta0, Jet2::variable(x[LAMBDA], 1));
        link_block([U, LAMBDA, THETA0], link)
    }

    fn eval<D: Elementary>(&self, x: &[D; joint_slot::COUNT]) -> D {
        use joint_slot::*;
        let joint = Joint { span: self.span, vertical: self.vertical, axial: self.axial };
        let stiffness = [x[STIFFNESS_LEFT] * self.stiffness_scale, x[STIFFNESS_RIGHT] * self.stiffness_scale];
        joint.residual([x[U_PREV], x[U], x[U_NEXT]], stiffness, x[THETA0] + x[U], x[THETA0], x[LAMBDA])
    }
}

/// The Hessian block of a joint residual over its nonlinear slots `core` (lanes 0, 1, 2 of the
/// jets), from its link's terms: `r = springs − load − reaction`, the springs linear there.
fn link_block<const M: usize>(core: [usize; 3], link: LinkTerms<Jet2<3>>) -> [[f64; M]; M] {
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
fn mixed_block<const M: usize, const F: usize, const A: usize, E: Element<M>>(
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

/// A link's rise `L_i sin θ_i = a_i sin θ_i / cos θ0_i`, m; local variables `[θ_i, θ0_i]`, or
/// `[u_i, θ0_i]` with `θ_i = θ0_i + u_i` when `deflection`. Summed over the links it is `Φ(θ)`
/// (the end constraint).
#[derive(Clone, Copy, Debug)]
pub struct LinkRise {
    pub span: f64,
    pub deflection: bool,
}

/// `θ_i` from a link element's first local variable (`θ_i` itself, or `u_i` with `θ0_i` second).
fn link_angle<D: Elementary>(x: &[D; 2], deflection: bool) -> D {
    if deflection {
        x[1] + x[0]
    } else {
        x[0]
    }
}

impl Element<2> for LinkRise {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        link_rise(self.span, x[1], link_angle(x, self.deflection))
    }
}

/// A link's run `L_i cos θ_i = a_i cos θ_i / cos θ0_i`, m; local variables as [`LinkRise`]'s.
/// Summed over the links it is `X_{N+1}(θ)`.
#[derive(Clone, Copy, Debug)]
pub struct LinkRun {
    pub span: f64,
    pub deflection: bool,
}

impl Element<2> for LinkRun {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        link_length(self.span, x[1]) * link_angle(x, self.deflection).cos()
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
    fn eval<D: Elementary>(&self, x: &[D; 3]) -> D {
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
    fn eval<D: Elementary>(&self, x: &[D; 5]) -> D {
        let rel = (x[2] - x[3]) - (x[0] - x[1]);
        x[4] * self.stiffness_scale * rel * rel * 0.5
    }
}

/// [`SpringEnergy`] on deflections: `½ K_j (u_j − u_{j−1})²`, J, with `K_j = C_K k_j` and the
/// deflections `u = θ − θ0`; local variables `[u_{j−1}, u_j, k_j]` (a missing neighbour holds zero).
#[derive(Clone, Copy, Debug)]
pub struct DeflectionSpringEnergy {
    pub stiffness_scale: f64,
}

impl Element<3> for DeflectionSpringEnergy {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1), (2, 0), (2, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 3]) -> D {
        let rel = x[1] - x[0];
        x[2] * self.stiffness_scale * rel * rel * 0.5
    }
}

/// The difference of two variables `x_0 − x_1` (the relative angle `θ0_i − θ0_{i+1}`); linear.
#[derive(Clone, Copy, Debug)]
pub struct Difference;

impl Element<2> for Difference {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        x[0] - x[1]
    }
}
