//! The small-deflection two-link system of eqs. (25)–(30): springs `K1` (base) and `K2` (middle
//! node), no `K3`, links of lengths `L1`, `L2` at design angles `θ0,1`, `θ0,2`, `P_Y,2` at the
//! middle node and `P_X,3` at the slider.
//!
//! Eq. (26) gives the deflections `Δθ_k` linearly in the loads; with them the paper writes the
//! Lagrangian `ℒ = J + Λ1 Φ1 + Λ2 Φ2` of eq. (22), `J = ½ Δθ1ᵀ K_m Δθ1` (eq. (21), `K_m` of
//! eq. (25)), `Φ1 = L1 sin θ0,1 + L2 sin θ0,2`, `Φ2 = Σ L_i (cos θ2,i − cos θ0,i) − δ`, and its
//! gradient in `(K1, K2, θ0,1, θ0,2)` as eqs. (27)–(30). Here the model is written once over the
//! number type, so its exact gradient comes from forward AD ([`SmallDeflection::lagrangian_gradient`]),
//! and eqs. (27)–(30) are evaluated as printed, with exact ingredients
//! ([`SmallDeflection::gradient_eqs_27_30`]): (29) and (30) are the chain rule; (27) and (28) lack
//! the term `Δθ1ᵀ K_m ∂θ1/∂K_i` that eq. (23) has (erratum E10).

use crate::Scalar;
use nalgebra::{Const, U1};
use num_dual::DualSVec64;

/// The system's geometry, design and loads (eqs. (25), (26)).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SmallDeflection {
    pub lengths: [f64; 2],
    pub theta0: [f64; 2],
    pub stiffness: [f64; 2],
    pub p_y2: f64,
    pub p_x3: f64,
}

/// The design `(K1, K2, θ0,1, θ0,2)` in the order of eqs. (27)–(30).
type DesignOf<D> = [D; 4];

impl SmallDeflection {
    /// Eq. (26): `[K_m, c; cᵀ, 0] [Δθ; λ] = [Q; −Φ1(θ0)]`, with `K_m` of eq. (25),
    /// `c = (L1 cos θ0,1, L2 cos θ0,2)` and the generalised loads at `θ0`,
    /// `Q = (P_Y,2 L1 cos θ0,1 − P_X,3 L1 sin θ0,1, −P_X,3 L2 sin θ0,2)` (what `−∂V/∂θ` gives, the
    /// model's `P_i = L_i (cos θ_i V_i − sin θ_i A_i)`). `printed = true` takes the paper's second
    /// row, `+P_X,3 L2 sin θ0,2` (erratum E8). Returns `Δθ` (rad) and `λ`, or `None` when the
    /// matrix is singular.
    pub fn delta_theta(&self, printed: bool) -> Option<([f64; 2], f64)> {
        let [k1, k2] = self.stiffness;
        let [t1, t2] = self.theta0;
        self.delta_theta_at([k1, k2, t1, t2], self.p_x3, printed)
    }

    /// [`SmallDeflection::delta_theta`] at the design `(K1, K2, θ0,1, θ0,2)` in any number type,
    /// with the axial force `p_x3` (zero for `Δθ1`, the passive load alone).
    fn delta_theta_at<D: Scalar>(&self, design: DesignOf<D>, p_x3: f64, printed: bool) -> Option<([D; 2], D)> {
        let [l1, l2] = self.lengths;
        let [k1, k2, t1, t2] = design;
        let [(s1, c1), (s2, c2)] = [t1.sin_cos(), t2.sin_cos()];
        let q2 = if printed { s2 * (p_x3 * l2) } else { -s2 * (p_x3 * l2) };
        let zero = D::zero();
        let a = [[k1 + k2, -k2, c1 * l1], [-k2, k2, c2 * l2], [c1 * l1, c2 * l2, zero]];
        let b = [c1 * (self.p_y2 * l1) - s1 * (p_x3 * l1), q2, -(s1 * l1) - s2 * l2];
        let det = |m: &[[D; 3]; 3]| {
            m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
        };
        let d = det(&a);
        if d.re() == 0.0 || !d.re().is_finite() {
            return None;
        }
        // Cramer's rule: column j replaced by b.
        let solve = |j: usize| {
            let mut m = a;
            for (row, v) in m.iter_mut().zip(b) {
                row[j] = v;
            }
            det(&m) / d
        };
        Some(([solve(0), solve(1)], solve(2)))
    }

    /// `ℒ = J + Λ1 Φ1 + Λ2 Φ2` (eqs. (21), (22)) at a design, with the corrected eq. (26); `δ` the
    /// desired end displacement (m), `multipliers` `(Λ1, Λ2)`.
    fn lagrangian<D: Scalar>(&self, design: DesignOf<D>, delta: f64, multipliers: [f64; 2]) -> Option<D> {
        let (passive, _) = self.delta_theta_at(design, 0.0, false)?;
        let (loaded, _) = self.delta_theta_at(design, self.p_x3, false)?;
        let [k1, k2, t1, t2] = design;
        let [l1, l2] = self.lengths;
        let strain = (k1 * passive[0] * passive[0] + k2 * (passive[0] - passive[1]) * (passive[0] - passive[1])) * 0.5;
        let rise = t1.sin() * l1 + t2.sin() * l2;
        let shortening = ((t1 + loaded[0]).cos() - t1.cos()) * l1 + ((t2 + loaded[1]).cos() - t2.cos()) * l2 - delta;
        Some(strain + rise * multipliers[0] + shortening * multipliers[1])
    }

    /// The design as plain numbers.
    fn design(&self) -> DesignOf<f64> {
        [self.stiffness[0], self.stiffness[1], self.theta0[0], self.theta0[1]]
    }

    /// The exact gradient of `ℒ` in `(K1, K2, θ0,1, θ0,2)` by forward AD through eq. (26):
    /// J·rad/(N·m) for the springs, J/rad for the angles.
    pub fn lagrangian_gradient(&self, delta: f64, multipliers: [f64; 2]) -> Option<[f64; 4]> {
        let seeded: DesignOf<DualSVec64<4>> =
            std::array::from_fn(|k| DualSVec64::from_re(self.design()[k]).derivative(k));
        let l = self.lagrangian(seeded, delta, multipliers)?;
        let g = l.eps.unwrap_generic(Const::<4>, U1);
        Some(std::array::from_fn(|k| g[k]))
    }

    /// `ℒ` itself (for differences).
    pub fn lagrangian_value(&self, delta: f64, multipliers: [f64; 2]) -> Option<f64> {
        self.lagrangian(self.design(), delta, multipliers)
    }

    /// `Δθ_k` and its derivatives in `(K1, K2, θ0,1, θ0,2)`: `([Δθ_k,1, Δθ_k,2], [∂Δθ_k,i/∂x_j])`.
    fn deflections_with_derivatives(&self, p_x3: f64) -> Option<([f64; 2], [[f64; 4]; 2])> {
        let seeded: DesignOf<DualSVec64<4>> =
            std::array::from_fn(|k| DualSVec64::from_re(self.design()[k]).derivative(k));
        let (d, _) = self.delta_theta_at(seeded, p_x3, false)?;
        let rates = |x: &DualSVec64<4>| {
            let g = x.eps.unwrap_generic(Const::<4>, U1);
            std::array::from_fn(|k| g[k])
        };
        Some(([d[0].re, d[1].re], [rates(&d[0]), rates(&d[1])]))
    }

    /// Eqs. (27)–(30) as printed, `(∂ℒ/∂K1, ∂ℒ/∂K2, ∂ℒ/∂θ0,1, ∂ℒ/∂θ0,2)`, with exact ingredients:
    /// `Δθ` and its derivatives from the corrected eq. (26) by AD, `∂Φ1/∂K_i = 0` (`Φ1` does not
    /// depend on `K`), `∂Φ2/∂x = Σ_i (−L_i sin θ2,i) ∂θ2,i/∂x` (the paper's list after eq. (30)) plus
    /// `L_i sin θ0,i` for `x = θ0,i` (as in eq. (24)), and `∂θ_k/∂θ0,i = e_i + ∂Δθ_k/∂θ0,i`.
    pub fn gradient_eqs_27_30(&self, multipliers: [f64; 2]) -> Option<[f64; 4]> {
        let (d1, r1) = self.deflections_with_derivatives(0.0)?;
        let (d2, r2) = self.deflections_with_derivatives(self.p_x3)?;
        let [l1, l2] = self.lengths;
        let [k1, k2] = self.stiffness;
        let theta2 = [self.theta0[0] + d2[0], self.theta0[1] + d2[1]];
        // `∂θ2,i/∂x`: `∂Δθ2,i/∂x`, plus 1 for `x = θ0,i`.
        let dtheta2 = |i: usize, x: usize| r2[i][x] + if x == 2 + i { 1.0 } else { 0.0 };
        let dphi2 = |x: usize| -> f64 {
            let own = if x >= 2 { self.lengths[x - 2] * self.theta0[x - 2].sin() } else { 0.0 };
            -l1 * theta2[0].sin() * dtheta2(0, x) - l2 * theta2[1].sin() * dtheta2(1, x) + own
        };
        // `Δθ1ᵀ K_m v` with `K_m` of eq. (25).
        let km = |v: [f64; 2]| (k1 + k2) * d1[0] * v[0] - k2 * (d1[0] * v[1] + d1[1] * v[0]) + k2 * d1[1] * v[1];
        let [lambda1, lambda2] = multipliers;
        let eq27 = 0.5 * d1[0] * d1[0] + lambda2 * dphi2(0);
        let eq28 = 0.5 * (d1[0] - d1[1]).powi(2) + lambda2 * dphi2(1);
        let dtheta1 = |i: usize| -> [f64; 2] {
            let x = 2 + i;
            let unit = |j: usize| if j == i { 1.0 } else { 0.0 };
            [unit(0) + r1[0][x], unit(1) + r1[1][x]]
        };
        let eq29 = km(dtheta1(0)) - km([1.0, 0.0]) + lambda1 * l1 * self.theta0[0].cos() + lambda2 * dphi2(2);
        let eq30 = km(dtheta1(1)) - km([0.0, 1.0]) + lambda1 * l2 * self.theta0[1].cos() + lambda2 * dphi2(3);
        Some([eq27, eq28, eq29, eq30])
    }

    /// The multipliers `(Λ1, Λ2)` that make the exact gradient stationary in both angles
    /// (`∂ℒ/∂θ0,1 = ∂ℒ/∂θ0,2 = 0`; `ℒ` is affine in them), so that `∂ℒ/∂K_i` is the rate of `J`
    /// along the constraints; `None` where that 2×2 system is singular.
    pub fn angle_stationary_multipliers(&self) -> Option<[f64; 2]> {
        let g0 = self.lagrangian_gradient(0.0, [0.0, 0.0])?;
        let g1 = self.lagrangian_gradient(0.0, [1.0, 0.0])?;
        let g2 = self.lagrangian_gradient(0.0, [0.0, 1.0])?;
        let (a, b, c, d) = (g1[2] - g0[2], g2[2] - g0[2], g1[3] - g0[3], g2[3] - g0[3]);
        let det = a * d - b * c;
        (det != 0.0 && det.is_finite()).then(|| [(-g0[2] * d + b * g0[3]) / det, (-a * g0[3] + c * g0[2]) / det])
    }

    /// The term eqs. (27), (28) leave out: `Δθ1ᵀ K_m ∂θ1/∂K_i`, `i = 1, 2` (J per N·m/rad).
    pub fn missing_stiffness_terms(&self) -> Option<[f64; 2]> {
        let (d1, r1) = self.deflections_with_derivatives(0.0)?;
        let [k1, k2] = self.stiffness;
        let km = |v: [f64; 2]| (k1 + k2) * d1[0] * v[0] - k2 * (d1[0] * v[1] + d1[1] * v[0]) + k2 * d1[1] * v[1];
        Some([km([r1[0][0], r1[1][0]]), km([r1[0][1], r1[1][1]])])
    }
}
