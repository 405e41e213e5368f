//! A branch-free forward-mode dual number of fixed width, and the few operations the joint
//! kernels use.
//!
//! num-dual's `DualSVec64<M>` keeps its derivative part as an `Option` of a vector, so that a
//! constant costs nothing; every operation matches on it. The element kernels of this crate seed
//! every lane they carry, so the `Option` is never `None` there and the match is pure overhead.
//! [`Jet`] is the value and `M` derivatives in a plain array: every operation is straight-line code
//! over `M` lanes that the compiler unrolls.
//!
//! The kernels are generic over [`Elementary`], which every [`Scalar`] (`f64`, num-dual's duals)
//! and every [`Jet`] implement, so the physics is still written once: the same
//! [`crate::residual::spring_moment`] and [`crate::residual::Joint::link`] give values to the
//! solvers, first derivatives through [`Jet`] and second derivatives through num-dual.

use crate::Scalar;
use std::ops::{Add, Mul, Neg, Sub};

/// What an element kernel needs of its number type: the arithmetic operations it uses, a product
/// with a constant, and `sin`, `cos`, `tan`, `1/x`.
pub trait Elementary:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self> + Mul<f64, Output = Self>
{
    /// `(sin x, cos x)`.
    fn sin_cos(self) -> (Self, Self);
    /// `sin x`.
    fn sin(self) -> Self;
    /// `cos x`.
    fn cos(self) -> Self;
    /// `tan x`.
    fn tan(self) -> Self;
    /// `1 / x`.
    fn recip(self) -> Self;
}

impl<T: Scalar> Elementary for T {
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        num_dual::DualNum::sin_cos(&self)
    }
    #[inline]
    fn sin(self) -> Self {
        num_dual::DualNum::sin(&self)
    }
    #[inline]
    fn cos(self) -> Self {
        num_dual::DualNum::cos(&self)
    }
    #[inline]
    fn tan(self) -> Self {
        num_dual::DualNum::tan(&self)
    }
    #[inline]
    fn recip(self) -> Self {
        num_dual::DualNum::recip(&self)
    }
}

/// A value `re` with its derivatives `eps` in `M` directions, none of them optional.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet<const M: usize> {
    pub re: f64,
    pub eps: [f64; M],
}

impl<const M: usize> Jet<M> {
    /// A constant: every derivative zero.
    #[inline]
    pub fn constant(re: f64) -> Self {
        Self { re, eps: [0.0; M] }
    }

    /// The independent variable of direction `k`: derivative 1 there, 0 elsewhere.
    #[inline]
    pub fn variable(re: f64, k: usize) -> Self {
        let mut eps = [0.0; M];
        eps[k] = 1.0;
        Self { re, eps }
    }

    /// `f(re)` with the chain rule's factor `f'(re)` on every lane.
    #[inline]
    fn chain(self, value: f64, derivative: f64) -> Self {
        Self { re: value, eps: self.eps.map(|e| e * derivative) }
    }
}

impl<const M: usize> Add for Jet<M> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self { re: self.re + o.re, eps: std::array::from_fn(|k| self.eps[k] + o.eps[k]) }
    }
}

impl<const M: usize> Sub for Jet<M> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self { re: self.re - o.re, eps: std::array::from_fn(|k| self.eps[k] - o.eps[k]) }
    }
}

#[allow(clippy::suspicious_arithmetic_impl)] // the product rule adds
impl<const M: usize> Mul for Jet<M> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Self { re: self.re * o.re, eps: std::array::from_fn(|k| self.eps[k] * o.re + self.re * o.eps[k]) }
    }
}

impl<const M: usize> Mul<f64> for Jet<M> {
    type Output = Self;
    #[inline]
    fn mul(self, c: f64) -> Self {
        Self { re: self.re * c, eps: self.eps.map(|e| e * c) }
    }
}

impl<const M: usize> Neg for Jet<M> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self { re: -self.re, eps: self.eps.map(|e| -e) }
    }
}

impl<const M: usize> Elementary for Jet<M> {
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = self.re.sin_cos();
        (self.chain(s, c), self.chain(c, -s))
    }
    #[inline]
    fn sin(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }
    #[inline]
    fn cos(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }
    #[inline]
    fn tan(self) -> Self {
        let t = self.re.tan();
        self.chain(t, 1.0 + t * t)
    }
    #[inline]
    fn recip(self) -> Self {
        let r = self.re.recip();
        self.chain(r, -r * r)
    }
}

/// A value with its gradient and Hessian in `M` directions, none of them optional: the
/// second-order [`Jet`] (num-dual's `Dual2SVec64<M>` without its `Option`s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet2<const M: usize> {
    pub re: f64,
    pub grad: [f64; M],
    pub hess: [[f64; M]; M],
}

impl<const M: usize> Jet2<M> {
    /// A constant: every derivative zero.
    #[inline]
    pub fn constant(re: f64) -> Self {
        Self { re, grad: [0.0; M], hess: [[0.0; M]; M] }
    }

    /// The independent variable of direction `k`.
    #[inline]
    pub fn variable(re: f64, k: usize) -> Self {
        let mut x = Self::constant(re);
        x.grad[k] = 1.0;
        x
    }

    /// `f(re)` by the chain rule with `f'(re)` and `f''(re)`: `∇f = f' ∇x`,
    /// `∇²f = f' ∇²x + f'' ∇x ∇xᵀ`.
    #[inline]
    fn chain(self, value: f64, first: f64, second: f64) -> Self {
        let g = self.grad;
        Self {
            re: value,
            grad: g.map(|e| e * first),
            hess: std::array::from_fn(|a| std::array::from_fn(|b| first * self.hess[a][b] + second * g[a] * g[b])),
        }
    }
}

impl<const M: usize> Add for Jet2<M> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self {
            re: self.re + o.re,
            grad: std::array::from_fn(|k| self.grad[k] + o.grad[k]),
            hess: std::array::from_fn(|a| std::array::from_fn(|b| self.hess[a][b] + o.hess[a][b])),
        }
    }
}

impl<const M: usize> Sub for Jet2<M> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self {
            re: self.re - o.re,
            grad: std::array::from_fn(|k| self.grad[k] - o.grad[k]),
            hess: std::array::from_fn(|a| std::array::from_fn(|b| self.hess[a][b] - o.hess[a][b])),
        }
    }
}

#[allow(clippy::suspicious_arithmetic_impl)] // the product rule adds
impl<const M: usize> Mul for Jet2<M> {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (g, h) = (self.grad, o.grad);
        Self {
            re: self.re * o.re,
            grad: std::array::from_fn(|k| g[k] * o.re + self.re * h[k]),
            hess: std::array::from_fn(|a| {
                std::array::from_fn(|b| self.hess[a][b] * o.re + g[a] * h[b] + h[a] * g[b] + self.re * o.hess[a][b])
            }),
        }
    }
}

impl<const M: usize> Mul<f64> for Jet2<M> {
    type Output = Self;
    #[inline]
    fn mul(self, c: f64) -> Self {
        Self { re: self.re * c, grad: self.grad.map(|e| e * c), hess: self.hess.map(|row| row.map(|e| e * c)) }
    }
}

impl<const M: usize> Neg for Jet2<M> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self * -1.0
    }
}

/// [`Elementary`] for a second-order jet type (a `re` field and a `chain(value, f′, f″)` method):
/// every function as its value with its first and second derivatives. [`Jet2`] and
/// [`crate::tangent::TangentJet`] share it.
macro_rules! elementary_by_second_order_chain {
    ($jet:ident) => {
        impl<const M: usize> $crate::jet::Elementary for $jet<M> {
            #[inline]
            fn sin_cos(self) -> (Self, Self) {
                let (s, c) = self.re.sin_cos();
                (self.chain(s, c, -s), self.chain(c, -s, -c))
            }
            #[inline]
            fn sin(self) -> Self {
                let (s, c) = self.re.sin_cos();
                self.chain(s, c, -s)
            }
            #[inline]
            fn cos(self) -> Self {
                let (s, c) = self.re.sin_cos();
                self.chain(c, -s, -c)
            }
            #[inline]
            fn tan(self) -> Self {
                let t = self.re.tan();
                let first = 1.0 + t * t;
                self.chain(t, first, 2.0 * t * first)
            }
            #[inline]
            fn recip(self) -> Self {
                let r = self.re.recip();
                self.chain(r, -r * r, 2.0 * r * r * r)
            }
        }
    };
}
pub(crate) use elementary_by_second_order_chain;

elementary_by_second_order_chain!(Jet2);

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::DualSVec64;

    /// A kernel of every operation, evaluated with a jet and with num-dual's dual: the same value
    /// and the same derivatives, to the last bits of round-off.
    fn kernel<D: Elementary>(x: D, y: D) -> D {
        let (s, c) = (x * y).sin_cos();
        (s - c * 3.0) * x.cos().recip() + (-y) * y + s * c + x.sin() * y.tan()
    }

    #[test]
    fn a_jet_agrees_with_num_dual() {
        for (x, y) in [(0.3, -1.2), (1.1, 0.7), (-0.4, 2.5)] {
            let jet = kernel(Jet::<2>::variable(x, 0), Jet::<2>::variable(y, 1));
            let dual = kernel(DualSVec64::<2>::from_re(x).derivative(0), DualSVec64::<2>::from_re(y).derivative(1));
            let g = dual.eps.unwrap_generic(nalgebra::Const::<2>, nalgebra::U1);
            assert!((jet.re - dual.re).abs() <= 1e-15 * dual.re.abs().max(1.0));
            for k in 0..2 {
                assert!((jet.eps[k] - g[k]).abs() <= 1e-14 * g[k].abs().max(1.0), "{k}: {} vs {}", jet.eps[k], g[k]);
            }
        }
    }

    #[test]
    fn a_second_order_jet_agrees_with_num_dual() {
        use num_dual::Dual2SVec64;
        for (x, y) in [(0.3, -1.2), (1.1, 0.7), (-0.4, 2.5)] {
            let jet = kernel(Jet2::<2>::variable(x, 0), Jet2::<2>::variable(y, 1));
            let dual = kernel(Dual2SVec64::<2>::from_re(x).derivative(0), Dual2SVec64::<2>::from_re(y).derivative(1));
            let g = dual.v1.unwrap_generic(nalgebra::U1, nalgebra::Const::<2>);
            let h = dual.v2.unwrap_generic(nalgebra::Const::<2>, nalgebra::Const::<2>);
            assert!((jet.re - dual.re).abs() <= 1e-15 * dual.re.abs().max(1.0));
            for a in 0..2 {
                assert!((jet.grad[a] - g[a]).abs() <= 1e-14 * g[a].abs().max(1.0), "{a}");
                for b in 0..2 {
                    let (mine, theirs) = (jet.hess[a][b], h[(a, b)]);
                    assert!((mine - theirs).abs() <= 1e-13 * theirs.abs().max(1.0), "{a}{b}: {mine} vs {theirs}");
                }
            }
        }
    }

    #[test]
    fn a_jet_agrees_with_central_differences() {
        let (x, y, h) = (0.8, -0.6, 1e-6);
        let jet = kernel(Jet::<2>::variable(x, 0), Jet::<2>::variable(y, 1));
        let fd = [(kernel(x + h, y) - kernel(x - h, y)) / (2.0 * h), (kernel(x, y + h) - kernel(x, y - h)) / (2.0 * h)];
        for k in 0..2 {
            assert!((jet.eps[k] - fd[k]).abs() < 1e-8, "{k}: {} vs {}", jet.eps[k], fd[k]);
        }
        assert_eq!(Jet::<3>::constant(2.0).eps, [0.0; 3]);
    }
}
