//! Dense Cholesky factorisation and solve, generic over [`Scalar`] (dual numbers carry through):
//! the reference path of the mass-matrix solves in [`crate::eom`].

use spine_model::Scalar;

/// Lower Cholesky factor of a symmetric positive definite matrix (row-major), or `None`.
pub(crate) fn cholesky<D: Scalar>(mut a: Vec<Vec<D>>) -> Option<Vec<Vec<D>>> {
    let n = a.len();
    for j in 0..n {
        let mut d = a[j][j];
        for k in 0..j {
            d -= a[j][k] * a[j][k];
        }
        // Not positive, or NaN.
        if d.re().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..n {
            let mut s = a[i][j];
            for k in 0..j {
                s -= a[i][k] * a[j][k];
            }
            a[i][j] = s / d;
        }
    }
    Some(a)
}

/// Solves `L Lᵀ x = b`.
pub(crate) fn chol_solve<D: Scalar>(l: &[Vec<D>], b: &[D]) -> Vec<D> {
    let n = b.len();
    let mut x = b.to_vec();
    for i in 0..n {
        for k in 0..i {
            let v = l[i][k] * x[k];
            x[i] -= v;
        }
        x[i] /= l[i][i];
    }
    for i in (0..n).rev() {
        for k in i + 1..n {
            let v = l[k][i] * x[k];
            x[i] -= v;
        }
        x[i] /= l[i][i];
    }
    x
}
