//! Linear solves with the bordered tridiagonal Jacobian `[A c; bᵀ d]`.
//!
//! The fast path is block elimination: one LU factorisation of the tridiagonal block `A` without
//! pivoting (Thomas), two triangular solves for `A⁻¹c` and `A⁻ᵀb`, and the scalar Schur complement
//! `d − bᵀA⁻¹c`. It costs `O(N)`. It is used only when every pivot of `A` is safely away from zero
//! and the multipliers stay bounded; otherwise (for example with the two-link structure
//! `K = [0, K, 0]`, whose `A` is singular at zero load) the whole matrix goes to faer's sparse LU
//! with partial pivoting, which is also the tests' oracle.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;
use spine_model::sparse::{BorderedTridiagonal, SparseMatrix};

/// The matrix could not be factorised: it is singular to working precision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SingularMatrix;

/// A factorised bordered tridiagonal matrix, ready for solves with it and its transpose.
pub enum BorderedLu {
    /// Block elimination, `O(N)`.
    Block(BlockFactors),
    /// General sparse LU with partial pivoting.
    General(GeneralLu),
}

/// Factors of the block elimination.
pub struct BlockFactors {
    /// Unit lower bidiagonal factor: `multipliers[i] = L[i+1][i]`.
    multipliers: Vec<f64>,
    /// Diagonal of the upper factor.
    pivots: Vec<f64>,
    /// Superdiagonal of `A` (the upper factor's superdiagonal).
    upper: Vec<f64>,
    column: Vec<f64>,
    row: Vec<f64>,
    /// `A⁻¹ c`.
    a_inv_column: Vec<f64>,
    /// `A⁻ᵀ b`.
    a_inv_t_row: Vec<f64>,
    /// `d − bᵀ A⁻¹ c`.
    schur: f64,
}

/// The sparse LU fallback.
pub struct GeneralLu {
    lu: faer::sparse::linalg::solvers::Lu<usize, f64>,
    n: usize,
}

impl BorderedLu {
    /// Factorises `jac`, choosing the block elimination when it is safe.
    pub fn factor(jac: &BorderedTridiagonal) -> Result<Self, SingularMatrix> {
        match BlockFactors::new(jac) {
            Some(f) => Ok(Self::Block(f)),
            None => GeneralLu::new(&jac.to_sparse()).map(Self::General),
        }
    }

    /// Always the general sparse LU (the oracle in tests).
    pub fn factor_general(jac: &BorderedTridiagonal) -> Result<Self, SingularMatrix> {
        GeneralLu::new(&jac.to_sparse()).map(Self::General)
    }

    /// Whether the fast block elimination was used.
    pub fn is_block(&self) -> bool {
        matches!(self, Self::Block(_))
    }

    /// Solves `J x = rhs`.
    pub fn solve(&self, rhs: &[f64]) -> Vec<f64> {
        match self {
            Self::Block(f) => f.solve(rhs, false),
            Self::General(g) => g.solve(rhs, false),
        }
    }

    /// Solves `Jᵀ x = rhs`.
    pub fn solve_transpose(&self, rhs: &[f64]) -> Vec<f64> {
        match self {
            Self::Block(f) => f.solve(rhs, true),
            Self::General(g) => g.solve(rhs, true),
        }
    }
}

/// Pivots smaller than this fraction of their row's magnitude send the matrix to the general LU.
const PIVOT_RATIO: f64 = 1e-8;
/// Multipliers larger than this (element growth) send the matrix to the general LU.
const MAX_MULTIPLIER: f64 = 1e6;

impl BlockFactors {
    fn new(jac: &BorderedTridiagonal) -> Option<Self> {
        let n = jac.block_size();
        let mut pivots: Vec<f64> = Vec::with_capacity(n);
        let mut multipliers = Vec::with_capacity(n.saturating_sub(1));
        for i in 0..n {
            let row_scale = jac.diag[i].abs()
                + if i > 0 { jac.lower[i - 1].abs() } else { 0.0 }
                + if i + 1 < n { jac.upper[i].abs() } else { 0.0 };
            let mut u = jac.diag[i];
            if i > 0 {
                let l = jac.lower[i - 1] / pivots[i - 1];
                if !l.is_finite() || l.abs() > MAX_MULTIPLIER {
                    return None;
                }
                u -= l * jac.upper[i - 1];
                multipliers.push(l);
            }
            if !u.is_finite() || u.abs() <= PIVOT_RATIO * row_scale {
                return None;
            }
            pivots.push(u);
        }
        let mut f = Self {
            multipliers,
            pivots,
            upper: jac.upper.clone(),
            column: jac.column.clone(),
            row: jac.row.clone(),
            a_inv_column: Vec::new(),
            a_inv_t_row: Vec::new(),
            schur: 0.0,
        };
        f.a_inv_column = f.solve_block(&jac.column);
        f.a_inv_t_row = f.solve_block_transpose(&jac.row);
        let b_dot: f64 = jac.row.iter().zip(&f.a_inv_column).map(|(b, z)| b * z).sum();
        f.schur = jac.corner - b_dot;
        let scale = jac.corner.abs() + b_dot.abs();
        if !f.schur.is_finite() || f.schur.abs() <= 1e-12 * scale.max(f64::MIN_POSITIVE) {
            return None;
        }
        Some(f)
    }

    /// `A⁻¹ v` with `A = L U`.
    fn solve_block(&self, v: &[f64]) -> Vec<f64> {
        let n = self.pivots.len();
        let mut y = v[..n].to_vec();
        for i in 1..n {
            y[i] -= self.multipliers[i - 1] * y[i - 1];
        }
        for i in (0..n).rev() {
            if i + 1 < n {
                y[i] -= self.upper[i] * y[i + 1];
            }
            y[i] /= self.pivots[i];
        }
        y
    }

    /// `A⁻ᵀ v` with `Aᵀ = Uᵀ Lᵀ`.
    fn solve_block_transpose(&self, v: &[f64]) -> Vec<f64> {
        let n = self.pivots.len();
        let mut y = v[..n].to_vec();
        for i in 0..n {
            if i > 0 {
                y[i] -= self.upper[i - 1] * y[i - 1];
            }
            y[i] /= self.pivots[i];
        }
        for i in (0..n.saturating_sub(1)).rev() {
            y[i] -= self.multipliers[i] * y[i + 1];
        }
        y
    }

    fn solve(&self, rhs: &[f64], transpose: bool) -> Vec<f64> {
        let n = self.pivots.len();
        let (y, border, z) = if transpose {
            (self.solve_block_transpose(rhs), &self.column, &self.a_inv_t_row)
        } else {
            (self.solve_block(rhs), &self.row, &self.a_inv_column)
        };
        let mu = (rhs[n] - border.iter().zip(&y).map(|(b, v)| b * v).sum::<f64>()) / self.schur;
        let mut x: Vec<f64> = y.iter().zip(z).map(|(yi, zi)| yi - zi * mu).collect();
        x.push(mu);
        x
    }
}

impl GeneralLu {
    fn new(m: &SparseMatrix) -> Result<Self, SingularMatrix> {
        let triplets: Vec<_> = m.entries.iter().map(|&(r, c, v)| Triplet::new(r, c, v)).collect();
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(m.nrows, m.ncols, &triplets)
            .map_err(|_| SingularMatrix)?;
        let lu = a.sp_lu().map_err(|_| SingularMatrix)?;
        let g = Self { lu, n: m.nrows };
        // faer does not report singularity: probe with a solve and reject non-finite answers.
        let probe = g.solve(&vec![1.0; m.nrows], false);
        if probe.iter().all(|v| v.is_finite()) {
            Ok(g)
        } else {
            Err(SingularMatrix)
        }
    }

    fn solve(&self, rhs: &[f64], transpose: bool) -> Vec<f64> {
        let b = Mat::<f64>::from_fn(self.n, 1, |i, _| rhs[i]);
        let x = if transpose { self.lu.solve_transpose(&b) } else { self.lu.solve(&b) };
        (0..self.n).map(|i| x[(i, 0)]).collect()
    }
}
