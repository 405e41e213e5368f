//! The joint residuals of eq. (5) as local elements, on absolute angles or on deflections.

use super::{link_block, mixed_block, Element};
use crate::jet::{Elementary, Jet2};
use crate::residual::{slot, Joint, JointStencil};
use std::ops::Mul;

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
    /// angles) the bilinear block. About a third of the work of `full_hessian`.
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
        joint_residual(x, [self.span, self.vertical, self.axial, self.stiffness_scale])
    }

    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; slot::COUNT]) -> D {
        let constants = |e: &Self| [e.span, e.vertical, e.axial, e.stiffness_scale];
        joint_residual(x, lifted(constants(self), constants(rates), lift))
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
        deflection_joint_residual(x, [self.span, self.vertical, self.axial, self.stiffness_scale])
    }

    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; joint_slot::COUNT]) -> D {
        let constants = |e: &Self| [e.span, e.vertical, e.axial, e.stiffness_scale];
        deflection_joint_residual(x, lifted(constants(self), constants(rates), lift))
    }
}

/// The constants `[a_i, V_i, A_i, C_K]` of a joint element, each lifted into `D` with its rate.
fn lifted<D>(constants: [f64; 4], rates: [f64; 4], lift: impl Fn(f64, f64) -> D) -> [D; 4] {
    std::array::from_fn(|k| lift(constants[k], rates[k]))
}

/// Joint row `i` from absolute angles (slots as in [`slot`]) with the constants
/// `[a_i, V_i, A_i, C_K]` plain or lifted.
fn joint_residual<D, C>(x: &[D; slot::COUNT], [span, vertical, axial, scale]: [C; 4]) -> D
where
    D: Elementary + Mul<C, Output = D>,
    C: Copy,
{
    let mut values = *x;
    values[slot::STIFFNESS_LEFT] = x[slot::STIFFNESS_LEFT] * scale;
    values[slot::STIFFNESS_RIGHT] = x[slot::STIFFNESS_RIGHT] * scale;
    JointStencil { values, has_prev: true, has_next: true }.residual(span, vertical, axial)
}

/// Joint row `i` from deflections (slots as in [`joint_slot`]) with the constants
/// `[a_i, V_i, A_i, C_K]` plain or lifted.
fn deflection_joint_residual<D, C>(x: &[D; joint_slot::COUNT], [span, vertical, axial, scale]: [C; 4]) -> D
where
    D: Elementary + Mul<C, Output = D>,
    C: Copy,
{
    use joint_slot::*;
    let joint = Joint { span, vertical, axial };
    let stiffness = [x[STIFFNESS_LEFT] * scale, x[STIFFNESS_RIGHT] * scale];
    joint.residual([x[U_PREV], x[U], x[U_NEXT]], stiffness, x[THETA0] + x[U], x[THETA0], x[LAMBDA])
}
