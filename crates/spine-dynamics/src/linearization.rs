//! How a system offers its linearisation to the implicit stages (a problem-side interface): the linear
//! systems of the implicit stages, `(σ I − J̃) x = r`, for a real shift (TR-BDF2, the real
//! eigenvalue of Radau IIA) or a complex one (Radau IIA's complex pair): [`Linearization`] at one
//! point, factored once per shift ([`ShiftedSolve`]). The default ([`DenseJacobian`]) is the LU of
//! the dense Jacobian; a system with structure supplies its own (the chain's `O(N)` one,
//! [`crate::newton`]).
//!
//! `J̃` may approximate the Jacobian: the stages are solved by simplified Newton iterations, whose
//! converged value does not depend on `J̃`, only their rate of convergence does.

use nalgebra::{Complex, ComplexField, DMatrix, DVector, Dyn};

/// Complex numbers of the Newton matrices of Radau IIA's complex eigenvalue pair.
pub type Complex64 = Complex<f64>;

/// `σ I − J̃` factored for one shift `σ`.
pub trait ShiftedSolve<T> {
    /// `rhs ← (σ I − J̃)⁻¹ rhs` (non-finite entries when the matrix is singular).
    fn solve(&self, rhs: &mut [T]);
    /// `rhs ← (σ I − J̃)⁻ᵀ rhs`: the transpose (not the conjugate transpose), for the adjoint
    /// of a step ([`crate::integrator::adjoint`]).
    fn solve_transpose(&self, rhs: &mut [T]);
}

/// `J̃` at one point `(t, y)`, ready to be factored for any shift.
pub trait Linearization {
    /// `σ I − J̃` for a real `σ`, or `None` when it is singular.
    fn factor_real(&self, shift: f64) -> Option<Box<dyn ShiftedSolve<f64>>>;
    /// `σ I − J̃` for a complex `σ`, or `None` when it is singular.
    fn factor_complex(&self, shift: Complex64) -> Option<Box<dyn ShiftedSolve<Complex64>>>;
}

/// The dense Jacobian `∂f/∂y`, factored by LU with partial pivoting (`O(n³)` per shift).
pub struct DenseJacobian(pub DMatrix<f64>);

/// The LU of `σ I − J̃`, and that of its transpose when a transposed solve first asks for it.
struct DenseLu<T: ComplexField> {
    matrix: DMatrix<T>,
    lu: nalgebra::LU<T, Dyn, Dyn>,
    transposed: std::cell::OnceCell<nalgebra::LU<T, Dyn, Dyn>>,
}

fn lu_solve<T: ComplexField + From<f64>>(lu: &nalgebra::LU<T, Dyn, Dyn>, rhs: &mut [T]) {
    let b = DVector::from_column_slice(rhs);
    match lu.solve(&b) {
        Some(x) => rhs.clone_from_slice(x.as_slice()),
        None => rhs.iter_mut().for_each(|v| *v = T::from(f64::NAN)),
    }
}

impl<T: ComplexField + From<f64>> ShiftedSolve<T> for DenseLu<T> {
    fn solve(&self, rhs: &mut [T]) {
        lu_solve(&self.lu, rhs);
    }

    fn solve_transpose(&self, rhs: &mut [T]) {
        lu_solve(self.transposed.get_or_init(|| self.matrix.transpose().lu()), rhs);
    }
}

fn shifted<T: ComplexField + From<f64>>(jacobian: DMatrix<T>, shift: T) -> Option<Box<dyn ShiftedSolve<T>>> {
    let n = jacobian.nrows();
    let matrix = DMatrix::<T>::identity(n, n) * shift - jacobian;
    let lu = matrix.clone().lu();
    lu.is_invertible()
        .then(|| Box::new(DenseLu { matrix, lu, transposed: Default::default() }) as Box<dyn ShiftedSolve<T>>)
}

impl Linearization for DenseJacobian {
    fn factor_real(&self, shift: f64) -> Option<Box<dyn ShiftedSolve<f64>>> {
        shifted(self.0.clone(), shift)
    }

    fn factor_complex(&self, shift: Complex64) -> Option<Box<dyn ShiftedSolve<Complex64>>> {
        shifted(self.0.map(Complex64::from), shift)
    }
}
