//! The elements of design criteria other than the paper's strain energy (eq. (33)'s `J`): the
//! springs' total stiffness, a power of a joint moment (summed: a smooth maximum of the moments),
//! and the work of a load on a link's displacement (summed: the compliance under that load).

use super::links::{link_angle, SPRING_SLOT_PAIRS};
use super::Element;
use crate::jet::Elementary;
use crate::kinematics::link_length;
use std::ops::Mul;

/// Spring `j`'s stiffness `K_j = C_K k_j`, N·m/rad; local variable `[k_j]`. Summed over the springs
/// it is the total stiffness `Σ K` (a measure of the material a design uses); linear.
#[derive(Clone, Copy, Debug)]
pub struct SpringStiffness {
    pub stiffness_scale: f64,
}

impl Element<1> for SpringStiffness {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[];
    fn eval<D: Elementary>(&self, x: &[D; 1]) -> D {
        x[0] * self.stiffness_scale
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 1]) -> D {
        x[0] * lift(self.stiffness_scale, rates.stiffness_scale)
    }
}

/// Spring `j`'s moment `M_j = K_j (Δθ_j − Δθ_{j−1})` in units of a reference moment, raised to an
/// even power: `(M_j / M_ref)^p`, dimensionless, with `K_j = C_K k_j`. Local variables
/// `[θ_{j−1}, θ0_{j−1}, θ_j, θ0_j, k_j]` as [`super::SpringEnergy`]'s; on deflections the `θ0`
/// slots hold zero (no variable), so that `[u_{j−1}, −, u_j, −, k_j]` gives `K_j (u_j − u_{j−1})`.
/// Summed over springs and load states, `(Σ (M/M_ref)^p)^{1/p}` is a smooth maximum of `|M|/M_ref`
/// (the `p`-norm: at least the largest term, at most `(count)^{1/p}` times it).
#[derive(Clone, Copy, Debug)]
pub struct MomentPower {
    pub stiffness_scale: f64,
    /// `M_ref`, N·m (> 0).
    pub reference: f64,
    /// `p`, even and ≥ 2.
    pub exponent: u32,
}

/// `x^p` by repeated squaring, in any number type (`x^0 = 1`).
fn power<D: Elementary>(x: D, p: u32) -> D {
    let (mut result, mut base, mut p) = (None::<D>, x, p);
    loop {
        if p & 1 == 1 {
            result = Some(result.map_or(base, |r| r * base));
        }
        p >>= 1;
        if p == 0 {
            // `p = 0` (the case format allows only even `p ≥ 2`, the struct any): `x^0 = 1`, the
            // constant written in `D` as `cos(0 · x)`, with zero derivatives.
            return result.unwrap_or_else(|| (x * 0.0).cos());
        }
        base = base * base;
    }
}

impl MomentPower {
    /// The power at `x` with `factor = C_K / M_ref` (1/rad) in `C`.
    fn eval_with<D: Elementary + Mul<C, Output = D>, C>(&self, factor: C, x: &[D; 5]) -> D {
        let rel = (x[2] - x[3]) - (x[0] - x[1]);
        power(x[4] * rel * factor, self.exponent)
    }
}

impl Element<5> for MomentPower {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &SPRING_SLOT_PAIRS;
    fn eval<D: Elementary>(&self, x: &[D; 5]) -> D {
        // As `eval_moving` forms it (`C_K · (1 / M_ref)`), so that a plain lift gives the same bits.
        self.eval_with(self.stiffness_scale * (1.0 / self.reference), x)
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 5]) -> D {
        let factor = lift(self.stiffness_scale, rates.stiffness_scale) * lift(self.reference, rates.reference).recip();
        self.eval_with(factor, x)
    }
}

/// The work of the loads beyond link `i` on the link's displacement from the unloaded shape,
/// `L_i [axial_i (cos θ_i − cos θ0_i) + vertical_i (sin θ_i − sin θ0_i)]`, J, with
/// `L_i = a_i / cos θ0_i` and the resultants of eq. (48) (N); local variables as
/// [`super::LinkRise`]'s (`[θ_i, θ0_i]`, or `[u_i, θ0_i]` when `deflection`). Summed over the links
/// it is `Σ_j P_j · (r_j(θ) − r_j(θ0))`, the loads' work on the node displacements: the compliance
/// `fᵀu` of that load case at its equilibrium `θ`.
#[derive(Clone, Copy, Debug)]
pub struct LinkWork {
    pub span: f64,
    pub vertical: f64,
    pub axial: f64,
    pub deflection: bool,
}

impl LinkWork {
    /// The work at `x` with the span and resultants in `C`.
    fn eval_with<D: Elementary + Mul<C, Output = D>, C: Copy>(&self, span: C, vertical: C, axial: C, x: &[D; 2]) -> D {
        let (s, c) = link_angle(x, self.deflection).sin_cos();
        let (s0, c0) = x[1].sin_cos();
        link_length(span, x[1]) * ((c - c0) * axial + (s - s0) * vertical)
    }
}

impl Element<2> for LinkWork {
    const HESSIAN_PAIRS: &'static [(usize, usize)] = &[(0, 0), (1, 0), (1, 1)];
    fn eval<D: Elementary>(&self, x: &[D; 2]) -> D {
        self.eval_with(self.span, self.vertical, self.axial, x)
    }
    fn eval_moving<D: Elementary>(&self, rates: &Self, lift: impl Fn(f64, f64) -> D, x: &[D; 2]) -> D {
        let (span, vertical, axial) =
            (lift(self.span, rates.span), lift(self.vertical, rates.vertical), lift(self.axial, rates.axial));
        self.eval_with(span, vertical, axial, x)
    }
}

#[cfg(test)]
mod tests {
    use super::power;

    #[test]
    fn power_by_squaring_is_powi_including_the_zeroth() {
        for p in 0..=9u32 {
            for x in [-1.7, -0.3, 0.0, 0.4, 2.5] {
                let want = f64::powi(x, p as i32);
                assert!((power(x, p) - want).abs() <= 1e-14 * want.abs().max(1.0), "{x}^{p}");
            }
        }
    }
}
