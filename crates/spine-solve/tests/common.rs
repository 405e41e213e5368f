//! Dense oracles for the solver tests (small N only).
#![allow(dead_code)]

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use spine_model::sparse::BorderedTridiagonal;

/// Orthonormal basis of `{x : bᵀx = 0}` from a Householder reflector, `n × (n−1)`.
pub fn tangent_basis(b: &[f64]) -> DMatrix<f64> {
    let n = b.len();
    let mut v = DVector::from_column_slice(b);
    let norm = v.norm();
    v[0] += norm.copysign(b[0]);
    let p = DMatrix::identity(n, n) - &v * v.transpose() * (2.0 / v.dot(&v));
    p.columns(1, n - 1).into_owned()
}

/// Dense tridiagonal block `H` of a bordered matrix.
pub fn block(jac: &BorderedTridiagonal) -> DMatrix<f64> {
    let n = jac.block_size();
    DMatrix::from_fn(n, n, |i, j| {
        if i == j {
            jac.diag[i]
        } else if i == j + 1 {
            jac.lower[j]
        } else if j == i + 1 {
            jac.upper[i]
        } else {
            0.0
        }
    })
}

/// Eigenvalues of `ZᵀHZ`, ascending.
pub fn projected_eigenvalues(h: &DMatrix<f64>, b: &[f64]) -> Vec<f64> {
    let z = tangent_basis(b);
    let m = z.transpose() * h * &z;
    let mut e: Vec<f64> = SymmetricEigen::new(m).eigenvalues.iter().copied().collect();
    e.sort_by(|a, b| a.partial_cmp(b).unwrap());
    e
}
