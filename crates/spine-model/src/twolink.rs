//! The two-link analysis of Sec. 3, in closed form.
//!
//! Two links of equal length `L` (m, held fixed as in the paper's Sec. 3), one spring `K` (N·m/rad)
//! at the middle node (`K_1 = K_3 = 0`), a transverse force `P_Y` (N) at the middle node and an
//! axial force `P_X` (N) at the slider. Symmetry gives `θ_{·,1} = −θ_{·,2} = θ`, strain energy
//! `2K(θ − θ0)²` and the scalar equilibrium
//!
//! `g(θ) = 4K(θ − θ0) − P_Y L cos θ + 2 P_X L sin θ = 0`   (eqs. (7), (8)),
//!
//! and the end displacement `δ = 2L (cos θ2 − cos θ0)` (eq. (9)).
//!
//! The paper's printed eqs. (10), (16) and (17) contain slips; both the printed and the corrected
//! forms are here so the tests can show the difference (see `docs/errata.md`, items E2–E5).

use crate::Scalar;

mod small_deflection;
pub use small_deflection::SmallDeflection;

/// Loads and geometry of the Sec. 3 problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoLink {
    /// Link length `L`, m.
    pub length: f64,
    /// Transverse force at the middle node, N (negative: down).
    pub p_y: f64,
    /// Axial force at the slider, N (negative: compression).
    pub p_x: f64,
}

impl TwoLink {
    /// Left side of eqs. (7)/(8) minus the right side, N·m: zero at equilibrium.
    /// `axial = false` drops `P_X` (eq. (7), passive load only).
    pub fn equilibrium<D: Scalar>(&self, theta: D, theta0: D, stiffness: D, axial: bool) -> D {
        let p_x = if axial { self.p_x } else { 0.0 };
        let (s, c) = theta.sin_cos();
        stiffness * (theta - theta0) * 4.0 - c * (self.p_y * self.length) + s * (2.0 * p_x * self.length)
    }

    /// End displacement, eq. (9): `δ = 2L (cos θ2 − cos θ0)`, m.
    pub fn end_displacement<D: Scalar>(&self, theta2: D, theta0: D) -> D {
        (theta2.cos() - theta0.cos()) * (2.0 * self.length)
    }

    /// Strain energy under the passive load, eq. (12): `J = 2K (θ1 − θ0)²`, J.
    pub fn strain_energy<D: Scalar>(&self, theta1: D, theta0: D, stiffness: D) -> D {
        let d = theta1 - theta0;
        stiffness * d * d * 2.0
    }

    /// `√(P_Y² + 4 P_X²)`, N.
    fn load_norm(&self) -> f64 {
        self.p_y.hypot(2.0 * self.p_x)
    }

    /// Eq. (10) exactly as printed: `θ0 = ½ [asin((2P_X − 4Kδ/L²)/√(P_Y² + 4P_X²)) − atan(2P_X/P_Y)]`.
    /// With `P_Y < 0` the principal `atan` picks the wrong branch (erratum E2).
    pub fn theta0_eq10_printed(&self, stiffness: f64, delta: f64) -> f64 {
        let l = self.length;
        0.5 * (((2.0 * self.p_x - 4.0 * stiffness * delta / (l * l)) / self.load_norm()).asin()
            - (2.0 * self.p_x / self.p_y).atan())
    }

    /// Eq. (10) on the right branch: `atan2(2P_X, P_Y)` in place of `atan(2P_X/P_Y)`.
    /// It neglects the term `−(δ/2L)(P_Y L sin θ0 + 2P_X L cos θ0)` that eq. (11) keeps, so its
    /// error is first order in `δ` (erratum E3).
    pub fn theta0_eq10(&self, stiffness: f64, delta: f64) -> f64 {
        self.theta0_small_delta(stiffness, delta)
    }

    /// The zero-moment angle `θ*` where the loads alone bend nothing (`δ → 0` limit of eq. (10)):
    /// `P_Y cos θ* = 2 P_X sin θ*`, on the branch of eq. (10).
    pub fn zero_moment_angle(&self) -> f64 {
        self.theta0_small_delta(0.0, 0.0)
    }

    fn theta0_small_delta(&self, stiffness: f64, delta: f64) -> f64 {
        let l = self.length;
        0.5 * (((2.0 * self.p_x - 4.0 * stiffness * delta / (l * l)) / self.load_norm()).asin()
            - (2.0 * self.p_x).atan2(self.p_y))
    }

    /// Eq. (10) made consistent with eq. (11) to first order in `δ`: eq. (10) with the effective
    /// stiffness `K + (L/4)(P_Y sin θ* + 2 P_X cos θ*)`. Its error is second order in `δ`.
    pub fn theta0_first_order(&self, stiffness: f64, delta: f64) -> f64 {
        let t = self.zero_moment_angle();
        let k_eff = stiffness + 0.25 * self.length * (self.p_y * t.sin() + 2.0 * self.p_x * t.cos());
        self.theta0_small_delta(k_eff, delta)
    }

    /// Eq. (11): the stiffness that gives end displacement `δ` for design angle `θ0`, N·m/rad.
    /// `K = (L/2δ)(2P_X L sin²θ0 − P_Y L sin θ0 cos θ0 − (δ/2L)[2P_X L cos θ0 + P_Y L sin θ0])`.
    /// Consistent to first order: its relative error is `O(δ)`.
    pub fn stiffness_eq11(&self, theta0: f64, delta: f64) -> f64 {
        let (l, px, py) = (self.length, self.p_x, self.p_y);
        let (s, c) = theta0.sin_cos();
        l / (2.0 * delta)
            * (2.0 * px * l * s * s - py * l * s * c - delta / (2.0 * l) * (2.0 * px * l * c + py * l * s))
    }

    /// `∂J/∂K` as printed in eq. (16): `2(θ1−θ0)² (1 − 2P_Y L sin θ1 / (4K + P_Y L sin θ1))`.
    /// Its sign is wrong (erratum E4): a stiffer spring stores less energy under the same load.
    pub fn dj_dk_eq16_printed(&self, theta1: f64, theta0: f64, stiffness: f64) -> f64 {
        let e = theta1 - theta0;
        let d = 4.0 * stiffness + self.p_y * self.length * theta1.sin();
        2.0 * e * e * (1.0 - 2.0 * self.p_y * self.length * theta1.sin() / d)
    }

    /// `∂J/∂K` from eqs. (13) and (15): `2(θ1−θ0)² (1 − 8K / (4K + P_Y L sin θ1))`, J·rad/(N·m).
    pub fn dj_dk(&self, theta1: f64, theta0: f64, stiffness: f64) -> f64 {
        let e = theta1 - theta0;
        let d = 4.0 * stiffness + self.p_y * self.length * theta1.sin();
        2.0 * e * e * (1.0 - 8.0 * stiffness / d)
    }

    /// `∂J/∂θ0`, eq. (16) (correct as printed): `4K(θ1−θ0)(−P_Y L sin θ1) / (4K + P_Y L sin θ1)`, J/rad.
    pub fn dj_dtheta0(&self, theta1: f64, theta0: f64, stiffness: f64) -> f64 {
        let ps = self.p_y * self.length * theta1.sin();
        4.0 * stiffness * (theta1 - theta0) * (-ps) / (4.0 * stiffness + ps)
    }

    /// Ratio `R` of eq. (17) as printed: `2K / (cot θ1 + 2(θ1 − θ0))`.
    pub fn ratio_eq17_printed(theta1: f64, theta0: f64, stiffness: f64) -> f64 {
        2.0 * stiffness / (1.0 / theta1.tan() + 2.0 * (theta1 - theta0))
    }

    /// `R = (∂J/∂θ0) / (∂J/∂K)` from the corrected eq. (16), with eq. (7) substituted:
    /// `R = 2K / (cot θ1 − (θ1 − θ0))`, N·m/rad per rad (erratum E5). Agrees with the printed
    /// eq. (17) to leading order in `θ1 − θ0`.
    pub fn ratio(theta1: f64, theta0: f64, stiffness: f64) -> f64 {
        2.0 * stiffness / (1.0 / theta1.tan() - (theta1 - theta0))
    }
    /// Derivatives of an equilibrium angle with respect to the design, from eq. (7)
    /// (`axial = false`) or eq. (8): `(∂θ/∂K, ∂θ/∂θ0) = (−4(θ − θ0), 4K) / g′(θ)` with
    /// `g′(θ) = 4K + P_Y L sin θ + 2 P_X L cos θ` (eq. (15) for `θ1`; the same differentiation of
    /// eq. (8) for `θ2`, as the paper's "obtained from equation (8)" after eq. (20) says).
    pub fn angle_derivatives(&self, theta: f64, theta0: f64, stiffness: f64, axial: bool) -> (f64, f64) {
        let p_x = if axial { self.p_x } else { 0.0 };
        let slope = 4.0 * stiffness + self.p_y * self.length * theta.sin() + 2.0 * p_x * self.length * theta.cos();
        (-4.0 * (theta - theta0) / slope, 4.0 * stiffness / slope)
    }

    /// The constraint of eq. (12) and its partials `(c, ∂c/∂K, ∂c/∂θ0)` at the equilibria `θ2`
    /// of the design: `c = cos θ2 − cos θ0 − δ/(2L)`.
    fn constraint(&self, theta0: f64, stiffness: f64, theta2: f64, delta: f64) -> (f64, f64, f64) {
        let (d2_dk, d2_dt0) = self.angle_derivatives(theta2, theta0, stiffness, true);
        let c = theta2.cos() - theta0.cos() - delta / (2.0 * self.length);
        (c, -theta2.sin() * d2_dk, -theta2.sin() * d2_dt0 + theta0.sin())
    }

    /// Eqs. (19) and (20): the gradient `(∂ℒ/∂K, ∂ℒ/∂θ0)` of the Lagrangian (18),
    /// `ℒ = J + λ1 (cos θ2 − cos θ0 − δ/2L)`, with `∂J` from eqs. (13), (14) and the angle
    /// derivatives of [`TwoLink::angle_derivatives`]; J·rad/(N·m) and J/rad.
    pub fn lagrangian_gradient(
        &self,
        theta0: f64,
        stiffness: f64,
        theta1: f64,
        theta2: f64,
        lambda: f64,
    ) -> (f64, f64) {
        let e = theta1 - theta0;
        let (d1_dk, d1_dt0) = self.angle_derivatives(theta1, theta0, stiffness, false);
        let (_, c_k, c_t0) = self.constraint(theta0, stiffness, theta2, 0.0);
        let dj_dk = 2.0 * e * e + 4.0 * stiffness * e * d1_dk; // eq. (13)
        let dj_dt0 = 4.0 * stiffness * e * (d1_dt0 - 1.0); // eq. (14)
        (dj_dk + lambda * c_k, dj_dt0 + lambda * c_t0)
    }

    /// The multiplier `λ1` that makes eq. (20) zero (stationarity in `θ0`), J.
    pub fn multiplier_eq20(&self, theta0: f64, stiffness: f64, theta1: f64, theta2: f64) -> f64 {
        let (_, dl_dt0) = self.lagrangian_gradient(theta0, stiffness, theta1, theta2, 0.0);
        let (_, _, c_t0) = self.constraint(theta0, stiffness, theta2, 0.0);
        -dl_dt0 / c_t0
    }
}
