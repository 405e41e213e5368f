//! A branch-free hyper-dual number for the rates of an element's gradient along a parameter:
//! `ε₁` over the element's `M` slots, `ε₂` one direction in its constants (a load, a span, `C_K`
//! moving with a parameter of the problem).
//!
//! One forward pass of an element with its slots seeded in `ε₁` and its constants lifted as
//! `c + ε₂ dc/dp` ([`TangentJet::moving`]) gives, exactly, the element's value, its gradient, the
//! value's rate `∂e/∂p` and the gradient's rate `∂(∇e)/∂p`: what the implicit-function theorem
//! needs of the NLP's data at an optimum ([`crate::local::rates`]). num-dual's
//! `HyperDualSVec64<M, 1>` gives the same numbers (tested) with an `Option` matched in every
//! operation.

use std::ops::{Add, Mul, Neg, Sub};

/// A value `re` with its gradient `eps` in `M` slots, its rate `rate` along one parameter and the
/// gradient's rate `eps_rate`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentJet<const M: usize> {
    pub re: f64,
    pub eps: [f64; M],
    pub rate: f64,
    pub eps_rate: [f64; M],
}

impl<const M: usize> TangentJet<M> {
    /// The slot `k` at `re`: derivative 1 in lane `k`, no rate.
    #[inline]
    pub fn variable(re: f64, k: usize) -> Self {
        let mut eps = [0.0; M];
        eps[k] = 1.0;
        Self { re, eps, rate: 0.0, eps_rate: [0.0; M] }
    }

    /// A constant `re` that moves with the parameter at `rate` per unit.
    #[inline]
    pub fn moving(re: f64, rate: f64) -> Self {
        Self { re, eps: [0.0; M], rate, eps_rate: [0.0; M] }
    }

    /// `f(re)` by the chain rule with `f'(re)` and `f''(re)`.
    #[inline]
    fn chain(self, value: f64, first: f64, second: f64) -> Self {
        let bent = second * self.rate;
        Self {
            re: value,
            eps: self.eps.map(|e| e * first),
            rate: self.rate * first,
            eps_rate: std::array::from_fn(|k| first * self.eps_rate[k] + bent * self.eps[k]),
        }
    }
}

impl<const M: usize> Add for TangentJet<M> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            re: self.re + o.re,
            eps: std::array::from_fn(|k| self.eps[k] + o.eps[k]),
            rate: self.rate + o.rate,
            eps_rate: std::array::from_fn(|k| self.eps_rate[k] + o.eps_rate[k]),
        }
    }
}

impl<const M: usize> Sub for TangentJet<M> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self + -o
    }
}

#[allow(clippy::suspicious_arithmetic_impl)] // the product rule adds
impl<const M: usize> Mul for TangentJet<M> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self, o);
        Self {
            re: a.re * b.re,
            eps: std::array::from_fn(|k| a.eps[k] * b.re + a.re * b.eps[k]),
            rate: a.rate * b.re + a.re * b.rate,
            eps_rate: std::array::from_fn(|k| {
                a.eps_rate[k] * b.re + a.eps[k] * b.rate + a.rate * b.eps[k] + a.re * b.eps_rate[k]
            }),
        }
    }
}

impl<const M: usize> Mul<f64> for TangentJet<M> {
    type Output = Self;
    #[inline]
    fn mul(self, c: f64) -> Self {
        Self {
            re: self.re * c,
            eps: self.eps.map(|e| e * c),
            rate: self.rate * c,
            eps_rate: self.eps_rate.map(|e| e * c),
        }
    }
}

impl<const M: usize> Neg for TangentJet<M> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

crate::jet::elementary_by_second_order_chain!(TangentJet);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::Elementary;
    use num_dual::HyperDualSVec64;

    /// Every operation, with a constant `c` that moves with the parameter.
    fn kernel<D: Elementary>(x: D, y: D, c: D) -> D {
        let (s, k) = (x * y * c).sin_cos();
        (s - k * 3.0) * (x * c).cos().recip() + (-y) * y * c + s * k + x.sin() * (y * c).tan()
    }

    #[test]
    fn a_tangent_jet_agrees_with_num_duals_hyper_dual() {
        for (x, y, c, dc) in [(0.3, -1.2, 0.7, 1.0), (1.1, 0.7, -0.4, 2.5), (-0.4, 0.5, 1.3, -0.3)] {
            let jet = kernel(TangentJet::<2>::variable(x, 0), TangentJet::variable(y, 1), TangentJet::moving(c, dc));
            let seed = |v: f64, k: usize| HyperDualSVec64::<2, 1>::from_re(v).derivative1(k);
            let moving = HyperDualSVec64::<2, 1>::from_re(c) + HyperDualSVec64::from_re(0.0).derivative2(0) * dc;
            let dual = kernel(seed(x, 0), seed(y, 1), moving);
            let e1 = dual.eps1.unwrap_generic(nalgebra::Const::<2>, nalgebra::U1);
            let e2 = dual.eps2.unwrap_generic(nalgebra::U1, nalgebra::Const::<1>);
            let e12 = dual.eps1eps2.unwrap_generic(nalgebra::Const::<2>, nalgebra::Const::<1>);
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs().max(1.0);
            assert!(close(jet.re, dual.re));
            assert!(close(jet.rate, e2[0]), "{} vs {}", jet.rate, e2[0]);
            for k in 0..2 {
                assert!(close(jet.eps[k], e1[k]), "{k}");
                assert!(close(jet.eps_rate[k], e12[(k, 0)]), "{k}: {} vs {}", jet.eps_rate[k], e12[(k, 0)]);
            }
        }
    }
}
