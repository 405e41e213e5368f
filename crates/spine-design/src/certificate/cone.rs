//! The smallest curvature on the critical cone (step 2 of [`super`]'s module docs), formed densely.
//!
//! The cone's faces share one subspace: with every weakly active bound released, the directions
//! are the null space `Z₀` of the strictly active rows on the free variables; holding some weak
//! bounds restricts them to `{Z₀ y : C y = 0}`, `C` those bounds' forms on `Z₀`. So `Z₀` (one
//! Householder QR of `A_Fᵀ`) and `H₀ = Z₀ᵀ H Z₀` are formed once, and each of the `2^w` faces costs
//! an eigensolve of the null space's size (`free − rows`), not of the free variables'.
//!
//! Measured on the peers case at N = 50 (204 free variables, 155 rows, 5 weak bounds: 32 faces):
//! 0.29 s with a projector `P H P + c (I − P)` of the free variables' size per face, the
//! certificate then costing more than the solve. The projector's spectrum is kept in the tests as
//! the reference the null-space form is checked against.

use super::MAX_DENSE_FREE;
use crate::optimality::active_set::{ActiveSet, Bound, Side};
use crate::optimality::system::{dependent_rows, free_positions, Matrices};
use nalgebra::{DMatrix, DVector};

/// A weakly active bound's form counts as moved off the bound above this (unit directions).
const SIGN_TOLERANCE: f64 = 1e-9;

/// A held weak bound whose form on the null space is below this fraction of its own norm is
/// implied by the active rows (the projector form dropped such a row as dependent).
const IMPLIED_FORM: f64 = 1e-10;

/// A weakly active bound as a linear form on directions, positive on its feasible side.
struct WeakForm {
    bound: Bound,
    row: bool,
}

impl WeakForm {
    /// The form's coefficients on the full-space variables (a variable's unit vector, or its
    /// constraint row), signed so that the feasible side is positive.
    fn coefficients(&self, n: usize, matrices: &Matrices) -> Vec<f64> {
        let mut c = vec![0.0; n];
        if self.row {
            for (&(r, col), &j) in matrices.jacobian_pattern.iter().zip(&matrices.jacobian) {
                if r == self.bound.index {
                    c[col] += j;
                }
            }
        } else {
            c[self.bound.index] = 1.0;
        }
        if self.bound.side == Side::Upper {
            c.iter_mut().for_each(|v| *v = -*v);
        }
        c
    }
}

/// The weakly active bounds of `set`: the variables', then the rows'.
fn weak_forms(set: &ActiveSet) -> Vec<WeakForm> {
    let variables = set.weak_variables.iter().map(|b| WeakForm { bound: *b, row: false });
    variables.chain(set.weak_rows.iter().map(|b| WeakForm { bound: *b, row: true })).collect()
}

/// Rows of `rows` independent of the earlier ones on the free variables of `fixed`.
fn independent(n: usize, fixed: &[Bound], rows: Vec<Bound>, matrices: &Matrices) -> Vec<Bound> {
    let jacobian = (&matrices.jacobian_pattern[..], &matrices.jacobian[..]);
    match dependent_rows(n, fixed, &rows, jacobian) {
        Some(dependent) => rows.into_iter().filter(|b| !dependent.contains(&b.index)).collect(),
        None => rows,
    }
}

/// An orthonormal basis of the orthogonal complement of the columns of `basis` (which must be
/// linearly independent): the trailing columns of the full `Q` of its Householder QR.
fn complement(basis: DMatrix<f64>) -> DMatrix<f64> {
    let (m, r) = basis.shape();
    if r == 0 {
        return DMatrix::identity(m, m);
    }
    let qr = basis.qr();
    let mut q_transposed = DMatrix::identity(m, m);
    qr.q_tr_mul(&mut q_transposed);
    q_transposed.rows(r, m - r).transpose()
}

/// The null space of the strictly active rows with every weak bound released: its basis `Z₀` in
/// the free variables, `H₀ = Z₀ᵀ H Z₀`, and the Hessian's scale on the free variables.
struct NullSpace {
    free_vars: Vec<usize>,
    basis: DMatrix<f64>,
    reduced: DMatrix<f64>,
    hessian_scale: f64,
}

impl NullSpace {
    /// `None` above [`MAX_DENSE_FREE`] free variables.
    fn of(n: usize, fixed: &[Bound], rows: &[Bound], matrices: &Matrices) -> Option<Self> {
        let (position, free) = free_positions(n, fixed);
        if free > MAX_DENSE_FREE {
            return None;
        }
        let mut h = DMatrix::<f64>::zeros(free, free);
        for (&(a, b), &v) in matrices.hessian_pattern.iter().zip(&matrices.hessian) {
            if let (Some(p), Some(q)) = (position[a], position[b]) {
                h[(p, q)] += v;
                if p != q {
                    h[(q, p)] += v;
                }
            }
        }
        let hessian_scale = super::hessian_scale(n, fixed, matrices);
        let basis = if rows.len() >= free {
            DMatrix::zeros(free, 0)
        } else {
            let row_position: std::collections::HashMap<usize, usize> =
                rows.iter().enumerate().map(|(k, b)| (b.index, k)).collect();
            let mut at = DMatrix::<f64>::zeros(free, rows.len());
            for (&(r, c), &v) in matrices.jacobian_pattern.iter().zip(&matrices.jacobian) {
                if let (Some(&k), Some(p)) = (row_position.get(&r), position[c]) {
                    at[(p, k)] += v;
                }
            }
            complement(at)
        };
        let free_vars = (0..n).filter(|&i| position[i].is_some()).collect();
        let reduced = basis.transpose() * &h * &basis;
        Some(Self { free_vars, basis, reduced: (&reduced + reduced.transpose()) * 0.5, hessian_scale })
    }

    /// `Z₀ y` in the full-space variables.
    fn lift(&self, n: usize, y: &DVector<f64>) -> Vec<f64> {
        let z = &self.basis * y;
        let mut v = vec![0.0; n];
        for (p, &i) in self.free_vars.iter().enumerate() {
            v[i] = z[p];
        }
        v
    }
}

/// The smallest curvature on the critical cone `{d : A d = 0, ℓ_b(d) ≥ 0 for each weakly active
/// bound b}`, the Hessian's scale, and the minimising direction: the minimum of `dᵀHd` on the cone's
/// unit sphere is an eigenpair of `ZᵀHZ` on the face where the bounds with `ℓ_b(d) > 0` are
/// released and the others held, so every face (2^w of them) is searched for eigenvectors that
/// point into the cone. `None` above [`MAX_DENSE_FREE`] free variables.
pub(super) fn cone_minimum(n: usize, set: &ActiveSet, matrices: &Matrices) -> Option<(f64, f64, Option<Vec<f64>>)> {
    let weak = weak_forms(set);
    let mut rows = set.rows.clone();
    rows.sort_by_key(|b| b.index);
    let rows = independent(n, &set.variables, rows, matrices);
    let space = NullSpace::of(n, &set.variables, &rows, matrices)?;
    let dimension = space.basis.ncols();
    // Each weak form on the null space's basis (signed) and its norm in the full space.
    let mut forms = DMatrix::<f64>::zeros(weak.len(), dimension);
    let mut norms = vec![0.0f64; weak.len()];
    for (k, w) in weak.iter().enumerate() {
        let c = w.coefficients(n, matrices);
        norms[k] = c.iter().map(|v| v * v).sum::<f64>().sqrt();
        for col in 0..dimension {
            forms[(k, col)] = space.free_vars.iter().enumerate().map(|(p, &i)| c[i] * space.basis[(p, col)]).sum();
        }
    }
    let (mut minimum, mut direction): (f64, Option<Vec<f64>>) = (f64::INFINITY, None);
    for released in 0..(1usize << weak.len()) {
        let held: Vec<usize> = (0..weak.len()).filter(|k| released & (1 << k) == 0).collect();
        let face = face_basis(&forms, &norms, &held);
        if face.ncols() == 0 {
            continue;
        }
        let m = face.transpose() * &space.reduced * &face;
        let eigen = ((&m + m.transpose()) * 0.5).symmetric_eigen();
        let mut order: Vec<usize> = (0..face.ncols()).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        for k in order {
            let value = eigen.eigenvalues[k];
            if value >= minimum {
                break;
            }
            let y = &face * eigen.eigenvectors.column(k);
            let values: Vec<f64> = (0..weak.len())
                .filter(|k| released & (1 << k) != 0)
                .map(|k| forms.row(k).dot(&y.transpose()))
                .collect();
            let sign = if values.iter().all(|f| *f > SIGN_TOLERANCE) {
                1.0
            } else if values.iter().all(|f| *f < -SIGN_TOLERANCE) {
                -1.0
            } else {
                continue;
            };
            minimum = value;
            direction = Some(space.lift(n, &(y * sign)));
        }
    }
    Some((minimum, space.hessian_scale, direction))
}

/// An orthonormal basis (in the null space's coordinates) of the face that holds the weak bounds
/// `held`: the null space of their forms, those implied by the active rows
/// ([`IMPLIED_FORM`]) left out.
fn face_basis(forms: &DMatrix<f64>, norms: &[f64], held: &[usize]) -> DMatrix<f64> {
    let dimension = forms.ncols();
    if held.is_empty() || dimension == 0 {
        return DMatrix::identity(dimension, dimension);
    }
    let c =
        DMatrix::from_fn(dimension, held.len(), |col, j| forms[(held[j], col)] / norms[held[j]].max(f64::MIN_POSITIVE));
    let svd = c.svd(true, false);
    // Invariant: `svd(true, _)` computes `U`.
    let u = svd.u.expect("requested");
    let kept: Vec<usize> = (0..svd.singular_values.len()).filter(|&j| svd.singular_values[j] > IMPLIED_FORM).collect();
    complement(u.select_columns(&kept))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference path: `ZᵀHZ`'s spectrum on one face from the projector `P H P + c (I − P)` of
    /// the free variables' size (`P = I − QQᵀ` onto the null space of the face's independent
    /// rows), its lowest `free − rows` eigenpairs, the directions in the full space.
    fn projector_spectrum(n: usize, fixed: &[Bound], rows: &[Bound], matrices: &Matrices) -> Vec<(f64, Vec<f64>)> {
        let free_vars: Vec<usize> = (0..n).filter(|i| !fixed.iter().any(|b| b.index == *i)).collect();
        let free = free_vars.len();
        let position = |i: usize| free_vars.iter().position(|&f| f == i);
        let mut h = DMatrix::<f64>::zeros(free, free);
        for (&(a, b), &v) in matrices.hessian_pattern.iter().zip(&matrices.hessian) {
            if let (Some(p), Some(q)) = (position(a), position(b)) {
                h[(p, q)] += v;
                if p != q {
                    h[(q, p)] += v;
                }
            }
        }
        if rows.len() >= free {
            return Vec::new();
        }
        let mut at = DMatrix::<f64>::zeros(free, rows.len());
        for (&(r, c), &v) in matrices.jacobian_pattern.iter().zip(&matrices.jacobian) {
            if let (Some(k), Some(p)) = (rows.iter().position(|b| b.index == r), position(c)) {
                at[(p, k)] += v;
            }
        }
        let identity = DMatrix::<f64>::identity(free, free);
        let projector = if rows.is_empty() {
            identity.clone()
        } else {
            let q = at.qr().q();
            &identity - &q * q.transpose()
        };
        let lift = h.iter().fold(0.0f64, |m, v| m.max(v.abs())) * free as f64 + 1.0;
        let m = &projector * &h * &projector + (&identity - &projector) * lift;
        let eigen = ((&m + m.transpose()) * 0.5).symmetric_eigen();
        let mut order: Vec<usize> = (0..free).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
        order.truncate(free - rows.len());
        order
            .into_iter()
            .map(|k| {
                let mut v = vec![0.0; n];
                for (p, &i) in free_vars.iter().enumerate() {
                    v[i] = eigen.eigenvectors[(p, k)];
                }
                (eigen.eigenvalues[k], v)
            })
            .collect()
    }

    /// The reference cone minimum: every face's projector spectrum, its bounds held as fixed
    /// variables or extra rows (dependent ones dropped).
    fn reference_minimum(n: usize, set: &ActiveSet, matrices: &Matrices) -> f64 {
        let weak = weak_forms(set);
        let mut minimum = f64::INFINITY;
        for released in 0..(1usize << weak.len()) {
            let (mut fixed, mut rows) = (set.variables.clone(), set.rows.clone());
            for (k, w) in weak.iter().enumerate() {
                if released & (1 << k) == 0 {
                    if w.row {
                        rows.push(w.bound)
                    } else {
                        fixed.push(w.bound)
                    }
                }
            }
            rows.sort_by_key(|b| b.index);
            let rows = independent(n, &fixed, rows, matrices);
            for (value, v) in projector_spectrum(n, &fixed, &rows, matrices) {
                let forms: Vec<f64> = weak
                    .iter()
                    .enumerate()
                    .filter(|(k, _)| released & (1 << k) != 0)
                    .map(|(_, w)| w.coefficients(n, matrices).iter().zip(&v).map(|(c, d)| c * d).sum())
                    .collect();
                let into = forms.iter().all(|f| *f > SIGN_TOLERANCE) || forms.iter().all(|f| *f < -SIGN_TOLERANCE);
                if into && value < minimum {
                    minimum = value;
                }
            }
        }
        minimum
    }

    fn bound(index: usize, side: Side) -> Bound {
        Bound { index, side, multiplier: 0.0, gap: 0.0 }
    }

    /// A dense symmetric `H` (upper triangle as the pattern) and a dense Jacobian.
    fn matrices(h: &DMatrix<f64>, jac: &DMatrix<f64>) -> Matrices {
        let (mut hessian_pattern, mut hessian) = (Vec::new(), Vec::new());
        for a in 0..h.nrows() {
            for b in a..h.ncols() {
                hessian_pattern.push((b, a));
                hessian.push(h[(a, b)]);
            }
        }
        let (mut jacobian_pattern, mut jacobian) = (Vec::new(), Vec::new());
        for r in 0..jac.nrows() {
            for c in 0..jac.ncols() {
                if jac[(r, c)] != 0.0 {
                    jacobian_pattern.push((r, c));
                    jacobian.push(jac[(r, c)]);
                }
            }
        }
        Matrices { hessian_pattern, hessian, jacobian_pattern, jacobian }
    }

    fn set(variables: Vec<Bound>, rows: Vec<Bound>, weak_variables: Vec<Bound>, weak_rows: Vec<Bound>) -> ActiveSet {
        ActiveSet {
            variables,
            rows,
            weak_variables,
            weak_rows,
            smallest_active_multiplier: f64::INFINITY,
            smallest_inactive_gap: f64::INFINITY,
        }
    }

    /// `H = diag(1, −1, 2)` with a weak lower bound on `x₁`: the cone is `d₁ ≥ 0`, its minimum
    /// −1 along `+e₁` (into the bound's feasible side); with the bound on the upper side the
    /// direction turns to `−e₁`; with `x₁` fixed strictly the minimum is 1.
    #[test]
    fn a_weak_bound_turns_the_direction_to_its_feasible_side() {
        let h = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, -1.0, 2.0]));
        let m = matrices(&h, &DMatrix::zeros(0, 3));
        for (side, sign) in [(Side::Lower, 1.0), (Side::Upper, -1.0)] {
            let (min, scale, d) =
                cone_minimum(3, &set(vec![], vec![], vec![bound(1, side)], vec![]), &m).expect("small");
            assert!((min + 1.0).abs() < 1e-14 && scale == 2.0, "{min} {scale}");
            let d = d.expect("a direction");
            assert!((d[1] - sign).abs() < 1e-14 && d[0].abs() < 1e-14 && d[2].abs() < 1e-14, "{d:?}");
        }
        let (min, _, _) =
            cone_minimum(3, &set(vec![bound(1, Side::Lower)], vec![], vec![], vec![]), &m).expect("small");
        assert!((min - 1.0).abs() < 1e-14, "{min}");
    }

    /// The null-space form against the projector reference on dense random problems with active
    /// rows, fixed variables, weak variable bounds and weak rows, one of them implied by the
    /// active rows: the same minimum, and the direction has that curvature, lies in the null
    /// space and points into the cone.
    #[test]
    fn the_null_space_form_agrees_with_the_projector_reference() {
        let mut rng = spine_rng::SplitMix64::new(7);
        let (mut negative, mut positive) = (0, 0);
        for trial in 0..20 {
            let n = 12;
            let mut h = DMatrix::from_fn(n, n, |_, _| rng.uniform(-1.0, 1.0));
            h = (&h + h.transpose()) * 0.5 + DMatrix::identity(n, n) * (0.5 + 0.1 * trial as f64);
            let mut jac = DMatrix::from_fn(5, n, |_, _| rng.uniform(-1.0, 1.0));
            // Row 4 (a weak row) is row 0 plus row 1 on the free variables: implied once held.
            let implied = jac.row(0) + jac.row(1);
            jac.set_row(4, &implied);
            let m = matrices(&h, &jac);
            let active = set(
                vec![bound(0, Side::Lower)],
                vec![bound(0, Side::Both), bound(1, Side::Both)],
                vec![bound(3, Side::Lower), bound(5, Side::Upper)],
                vec![bound(2, Side::Lower), bound(4, Side::Upper)],
            );
            let (min, _, d) = cone_minimum(n, &active, &m).expect("small");
            let reference = reference_minimum(n, &active, &m);
            assert!(
                (min - reference).abs() <= 1e-10 * (1.0 + reference.abs()),
                "trial {trial}: {min} against {reference}"
            );
            if min < 0.0 {
                negative += 1;
            } else {
                positive += 1;
            }
            if let Some(d) = d {
                let d = DVector::from_vec(d);
                assert!((d.norm() - 1.0).abs() < 1e-12 && d[0] == 0.0);
                assert!(((d.transpose() * &h * &d)[(0, 0)] - min).abs() < 1e-10, "trial {trial}");
                for r in 0..2 {
                    assert!(jac.row(r).dot(&d.transpose()).abs() < 1e-12, "trial {trial}: row {r}");
                }
                assert!(d[3] >= -1e-12 && d[5] <= 1e-12, "trial {trial}: {d}");
                assert!(jac.row(2).dot(&d.transpose()) >= -1e-12 && jac.row(4).dot(&d.transpose()) <= 1e-12);
            }
        }
        // Both kinds of point were drawn.
        assert!(negative >= 3 && positive >= 3, "{negative} negative, {positive} positive minima");
    }
}
