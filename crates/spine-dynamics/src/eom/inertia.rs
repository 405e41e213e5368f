//! The mass matrix's coefficients: the coupling `μ_j = ½ m_j + Σ_{k>j} m_k` and the diagonal.

use super::Dynamics;

/// The coupling coefficients `μ_j = ½ m_j + Σ_{k>j} m_k` (kg) of the mass matrix, in one pass
/// from the end (the adjoint's products need these alone).
pub(crate) fn coupling_coefficients(masses: &[f64]) -> Vec<f64> {
    let mut coupling = vec![0.0; masses.len()];
    let mut beyond = 0.0;
    for (mu, m) in coupling.iter_mut().zip(masses).rev() {
        *mu = 0.5 * m + beyond;
        beyond += m;
    }
    coupling
}

impl Dynamics {
    /// `c_ij = L_i L_j (½ m_j + Σ_{k>j} m_k)` for `i ≤ j` below the diagonal's own term: the
    /// coefficient of `cos(θ_i − θ_j)` in `M_ij`. Returns `(c, diag)` with
    /// `diag_i = L_i² (m_i / 3 + Σ_{k>i} m_k)`.
    pub(crate) fn inertia_coefficients(&self) -> (Vec<f64>, Vec<f64>) {
        let mut diag = vec![0.0; self.n_links()];
        let mut beyond = 0.0;
        for ((d, l), m) in diag.iter_mut().zip(&self.lengths).zip(&self.masses).rev() {
            *d = l.powi(2) * (m / 3.0 + beyond);
            beyond += m;
        }
        (coupling_coefficients(&self.masses), diag)
    }
}
