//! Geometry: link lengths, node positions (eq. (1)) and the end constraint `Φ` (eq. (2)).

use crate::jet::Elementary;
use crate::Scalar;
use std::ops::Mul;

/// Length of a link of horizontal span `span` (m) designed at angle `theta0`:
/// `L = a / cos θ0` (paper, Sec. 5 "length constraint"), m. The span may be a plain number or of
/// the angle's number type (a span that moves with a parameter, [`crate::tangent`]).
#[inline(always)]
pub fn link_length<D, C>(span: C, theta0: D) -> D
where
    D: Elementary + Mul<C, Output = D>,
{
    theta0.cos().recip() * span
}

/// Link lengths `L_i = a_i / cos θ0_i`, m.
pub fn link_lengths<D: Scalar>(spans: &[f64], theta0: &[D]) -> Vec<D> {
    spans.iter().zip(theta0).map(|(&a, &t0)| link_length(a, t0)).collect()
}

/// Node positions `(X_j, Y_j)`, m, eq. (1): `X_j = Σ_{k<j} L_k cos θ_k`, `Y_j = Σ_{k<j} L_k sin θ_k`.
/// Returns `N+1` points, the base `(0, 0)` first.
pub fn node_positions<D: Scalar>(lengths: &[D], theta: &[D]) -> Vec<(D, D)> {
    let mut nodes = Vec::with_capacity(lengths.len() + 1);
    let (mut x, mut y) = (D::zero(), D::zero());
    nodes.push((x, y));
    for (&l, &t) in lengths.iter().zip(theta) {
        let (s, c) = t.sin_cos();
        x += l * c;
        y += l * s;
        nodes.push((x, y));
    }
    nodes
}

/// Height of link `i`'s far end above its near end, `L_i sin θ_i`, m: one term of `Φ`.
pub fn link_rise<D, C>(span: C, theta0: D, theta: D) -> D
where
    D: Elementary + Mul<C, Output = D>,
{
    link_length(span, theta0) * theta.sin()
}

/// The end constraint, eq. (2): `Φ(θ) = Y_{N+1} = Σ L_i sin θ_i`, m. Zero when the end is on the X axis.
pub fn end_constraint<D: Scalar>(spans: &[f64], theta0: &[D], theta: &[D]) -> D {
    spans.iter().zip(theta0).zip(theta).map(|((&a, &t0), &t)| link_rise(a, t0, t)).sum()
}

/// X coordinate of the end, `X_{N+1} = Σ L_i cos θ_i`, m.
pub fn end_x<D: Scalar>(spans: &[f64], theta0: &[D], theta: &[D]) -> D {
    spans.iter().zip(theta0).zip(theta).map(|((&a, &t0), &t)| link_length(a, t0) * t.cos()).sum()
}
