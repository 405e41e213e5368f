//! Sparse matrix containers for the Jacobians: the bordered tridiagonal matrix of the equilibrium
//! equations and a plain coordinate (triplet) matrix.

/// A tridiagonal `n × n` block bordered by one dense row and column:
///
/// ```text
/// [ A   c ]   A tridiagonal (lower, diag, upper)
/// [ bᵀ  d ]   c = column, b = row, d = corner
/// ```
///
/// The Jacobian of the equilibrium residual with respect to `(θ, λ)` has exactly this shape:
/// `A = K_m − ∂P/∂θ − λ ∂²Φ/∂θ²`, `c = −∇Φ`, `b = ∇Φ`, `d = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct BorderedTridiagonal {
    /// `lower[i] = A[i+1][i]`, length `n − 1`.
    pub lower: Vec<f64>,
    /// `diag[i] = A[i][i]`, length `n`.
    pub diag: Vec<f64>,
    /// `upper[i] = A[i][i+1]`, length `n − 1`.
    pub upper: Vec<f64>,
    /// The border column `c`, length `n`.
    pub column: Vec<f64>,
    /// The border row `b`, length `n`.
    pub row: Vec<f64>,
    /// The corner `d`.
    pub corner: f64,
}

impl BorderedTridiagonal {
    /// A zero matrix with an `n × n` tridiagonal block.
    pub fn zeros(n: usize) -> Self {
        let off = n.saturating_sub(1);
        Self {
            lower: vec![0.0; off],
            diag: vec![0.0; n],
            upper: vec![0.0; off],
            column: vec![0.0; n],
            row: vec![0.0; n],
            corner: 0.0,
        }
    }

    /// Size `n` of the tridiagonal block (the whole matrix is `n + 1` square).
    pub fn block_size(&self) -> usize {
        self.diag.len()
    }

    /// `y = J x` for `x` of length `n + 1`.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let n = self.block_size();
        let mut y = vec![0.0; n + 1];
        for i in 0..n {
            let mut s = self.diag[i] * x[i] + self.column[i] * x[n];
            if i > 0 {
                s += self.lower[i - 1] * x[i - 1];
            }
            if i + 1 < n {
                s += self.upper[i] * x[i + 1];
            }
            y[i] = s;
        }
        y[n] = self.row.iter().zip(x).map(|(b, v)| b * v).sum::<f64>() + self.corner * x[n];
        y
    }

    /// The same matrix as coordinate triplets (structural zeros kept), for general sparse solvers.
    pub fn to_sparse(&self) -> SparseMatrix {
        let n = self.block_size();
        let mut m = SparseMatrix::new(n + 1, n + 1);
        for i in 0..n {
            if i > 0 {
                m.push(i, i - 1, self.lower[i - 1]);
            }
            m.push(i, i, self.diag[i]);
            if i + 1 < n {
                m.push(i, i + 1, self.upper[i]);
            }
            m.push(i, n, self.column[i]);
            m.push(n, i, self.row[i]);
        }
        m.push(n, n, self.corner);
        m
    }
}

/// A sparse matrix as a list of `(row, column, value)` triplets; duplicates add up.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct SparseMatrix {
    pub nrows: usize,
    pub ncols: usize,
    pub entries: Vec<(usize, usize, f64)>,
}

impl SparseMatrix {
    pub fn new(nrows: usize, ncols: usize) -> Self {
        Self { nrows, ncols, entries: Vec::new() }
    }

    pub fn push(&mut self, row: usize, col: usize, value: f64) {
        debug_assert!(row < self.nrows && col < self.ncols);
        self.entries.push((row, col, value));
    }

    /// `y = M x`.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.nrows];
        for &(r, c, v) in &self.entries {
            y[r] += v * x[c];
        }
        y
    }

    /// `y = Mᵀ x`.
    pub fn transpose_mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.ncols];
        for &(r, c, v) in &self.entries {
            y[c] += v * x[r];
        }
        y
    }

    /// Dense copy, row-major `nrows × ncols` (tests and small problems only).
    pub fn to_dense(&self) -> Vec<Vec<f64>> {
        let mut d = vec![vec![0.0; self.ncols]; self.nrows];
        for &(r, c, v) in &self.entries {
            d[r][c] += v;
        }
        d
    }
}
