//! The equilibrium residual (paper eqs. (5), (33)), written once for every number type.
//!
//! Stationarity of `U + V − λΦ` gives `N + 1` equations in `(θ, λ)`:
//!
//! * joint rows `r_i = (K_m Δθ)_i − P_i(θ) − λ ∂Φ/∂θ_i`, N·m, `i = 0..N`;
//! * the constraint row `r_N = Φ(θ)`, m.
//!
//! Row `i` touches only `θ_{i−1}, θ_i, θ_{i+1}, λ` and the design entries `θ0_{i−1..=i+1}`,
//! `K_i, K_{i+1}`: the nine slots of a [`JointStencil`]. Derivatives seed some of these slots with
//! dual numbers (see [`crate::jacobian`]).

use crate::jet::Elementary;
use crate::kinematics::{end_constraint, link_length};
use crate::{Design, LinkLoads, State};
use std::ops::Mul;

/// Slot numbers of the local variables of one joint row.
pub mod slot {
    pub const THETA_PREV: usize = 0;
    pub const THETA: usize = 1;
    pub const THETA_NEXT: usize = 2;
    pub const LAMBDA: usize = 3;
    pub const THETA0_PREV: usize = 4;
    pub const THETA0: usize = 5;
    pub const THETA0_NEXT: usize = 6;
    pub const STIFFNESS_LEFT: usize = 7;
    pub const STIFFNESS_RIGHT: usize = 8;
    /// Number of slots.
    pub const COUNT: usize = 9;
}

/// The local variables of joint row `i`, indexed by [`slot`]. A missing neighbour (before link 0
/// or after link `N−1`) has `θ = θ0 = 0`, so its deviation `Δθ` is zero as the model requires.
#[derive(Clone, Copy, Debug)]
pub struct JointStencil<D> {
    pub values: [D; slot::COUNT],
    pub has_prev: bool,
    pub has_next: bool,
}

impl<D: Elementary> JointStencil<D> {
    /// Gathers row `i`'s slots from the global vectors, passing each `(slot, value)` through `lift`
    /// (identity for values, a seeded dual number for derivatives).
    pub fn gather(
        i: usize,
        theta: &[f64],
        lambda: f64,
        theta0: &[f64],
        stiffness: &[f64],
        lift: impl Fn(usize, f64) -> D,
    ) -> Self {
        let n = theta.len();
        let has_prev = i > 0;
        let has_next = i + 1 < n;
        let pick = |v: &[f64], j: Option<usize>| j.map_or(0.0, |j| v[j]);
        let prev = has_prev.then(|| i - 1);
        let next = has_next.then_some(i + 1);
        let raw = [
            pick(theta, prev),
            theta[i],
            pick(theta, next),
            lambda,
            pick(theta0, prev),
            theta0[i],
            pick(theta0, next),
            stiffness[i],
            stiffness[i + 1],
        ];
        let values = std::array::from_fn(|s| lift(s, raw[s]));
        Self { values, has_prev, has_next }
    }

    /// The joint residual `r_i`, N·m (eqs. (5), (47), (48)), from absolute angles: see
    /// `joint_residual`.
    pub fn residual<C: Copy>(&self, span: C, vertical: C, axial: C) -> D
    where
        D: Mul<C, Output = D>,
    {
        use slot::*;
        let v = &self.values;
        let deflections = [v[THETA_PREV] - v[THETA0_PREV], v[THETA] - v[THETA0], v[THETA_NEXT] - v[THETA0_NEXT]];
        let joint = Joint { span, vertical, axial };
        joint.residual(deflections, [v[STIFFNESS_LEFT], v[STIFFNESS_RIGHT]], v[THETA], v[THETA0], v[LAMBDA])
    }
}

/// Link `i`'s data in its joint residual: span `a_i` (m) and load resultants `V_i`, `A_i` (N,
/// eq. (48)). Plain numbers, or of the angles' number type where they move with a parameter of
/// the problem ([`crate::tangent`]).
#[derive(Clone, Copy, Debug)]
pub struct Joint<C = f64> {
    pub span: C,
    pub vertical: C,
    pub axial: C,
}

/// Joint row `i`'s deflections `[Δθ_{i−1}, Δθ_i, Δθ_{i+1}]`, rad (`Δθ = θ − θ0`, zero for a
/// missing neighbour): the first argument of [`spring_moment`].
#[inline]
pub fn joint_deflections(theta: &[f64], theta0: &[f64], i: usize) -> [f64; 3] {
    let deflection = |j: usize| theta[j] - theta0[j];
    let before = if i > 0 { deflection(i - 1) } else { 0.0 };
    let after = if i + 1 < theta.len() { deflection(i + 1) } else { 0.0 };
    [before, deflection(i), after]
}

/// The springs' moment on link `i`, N·m: `K_i (Δθ_i − Δθ_{i−1}) − K_{i+1} (Δθ_{i+1} − Δθ_i)`
/// (eq. (47)). `deflections` are `[Δθ_{i−1}, Δθ_i, Δθ_{i+1}]` (rad, `Δθ = θ − θ0`, zero for a
/// missing neighbour), `stiffness` `[K_i, K_{i+1}]` (N·m/rad). Linear in the deflections,
/// bilinear in the stiffnesses and the deflections.
///
/// The spring term takes the deflections themselves: formed as `θ − θ0` from angles of about
/// 0.5 rad, a deflection carries a round-off of about 1e-16 rad, which a stiffness of 1e8
/// N·m/rad turns into 1e-8 N·m (the floor that kept eq. (33) at N = 1000 from converging while its
/// variables were absolute angles; docs/design.md).
///
/// The stiffnesses may be of another number type than the deflections (plain numbers where only
/// the deflections' derivatives are wanted).
#[inline]
pub fn spring_moment<D, K>(deflections: [D; 3], stiffness: [K; 2]) -> D
where
    D: Elementary + Mul<K, Output = D>,
    K: Copy,
{
    let [d_prev, d_self, d_next] = deflections;
    (d_self - d_prev) * stiffness[0] - (d_next - d_self) * stiffness[1]
}

/// What link `i` contributes, from one `sin_cos` of `θ_i` and one length `L_i = a_i / cos θ0_i`:
/// the load's moment and the slider's reaction moment in joint row `i`, and the link's terms of
/// `Φ` and of `X_{N+1}`.
#[derive(Clone, Copy, Debug)]
pub struct LinkTerms<D> {
    /// `L_i (cos θ_i V_i − sin θ_i A_i)`, N·m (eq. (48)).
    pub load: D,
    /// `λ L_i cos θ_i = λ ∂Φ/∂θ_i`, N·m.
    pub reaction: D,
    /// `L_i sin θ_i`, m: the link's term of `Φ` (eq. (2)).
    pub rise: D,
    /// `L_i cos θ_i`, m: the link's term of `X_{N+1}`, and `∂Φ/∂θ_i`.
    pub run: D,
}

impl<C: Copy> Joint<C> {
    /// Link `i`'s terms at angle `θ_i`, unloaded angle `θ0_i` (rad) and slider reaction `λ` (N).
    /// `θ0_i` may be of another number type than `θ_i` and `λ` (a plain number where its
    /// derivatives are not wanted: then `L_i` costs one plain `cos`).
    #[inline(always)]
    pub fn link<D, T>(&self, theta: D, theta0: T, lambda: D) -> LinkTerms<D>
    where
        D: Elementary + Mul<T, Output = D> + Mul<C, Output = D>,
        T: Elementary + Mul<C, Output = T>,
    {
        let length = link_length(self.span, theta0);
        let (s, c) = theta.sin_cos();
        LinkTerms {
            load: (c * self.vertical - s * self.axial) * length,
            reaction: lambda * length * c,
            rise: s * length,
            run: c * length,
        }
    }

    /// The joint residual `r_i`, N·m (eqs. (5), (47), (48)):
    /// `K_i (Δθ_i − Δθ_{i−1}) − K_{i+1} (Δθ_{i+1} − Δθ_i) − L_i (cos θ_i V_i − sin θ_i A_i) − λ L_i cos θ_i`
    /// with `L_i = a_i / cos θ0_i`: [`spring_moment`] less [`Joint::link`]'s load and reaction.
    #[inline]
    pub fn residual<D>(&self, deflections: [D; 3], stiffness: [D; 2], theta: D, theta0: D, lambda: D) -> D
    where
        D: Elementary + Mul<C, Output = D>,
    {
        let link = self.link(theta, theta0, lambda);
        spring_moment(deflections, stiffness) - link.load - link.reaction
    }
}

/// The full residual `[r_0, …, r_{N−1}, Φ]` of eq. (5) at `state` for `design` under `loads`.
/// Joint rows in N·m, the last row in m. Plain `f64`; the generic pieces are
/// [`JointStencil::residual`] and [`crate::kinematics::end_constraint`].
pub fn equilibrium_residual(spans: &[f64], design: &Design, loads: &LinkLoads, state: &State) -> Vec<f64> {
    let n = spans.len();
    let mut r = Vec::with_capacity(n + 1);
    for i in 0..n {
        let st =
            JointStencil::<f64>::gather(i, &state.theta, state.lambda, &design.theta0, &design.stiffness, |_, v| v);
        r.push(st.residual(spans[i], loads.vertical[i], loads.axial[i]));
    }
    r.push(end_constraint(spans, &design.theta0, &state.theta));
    r
}
