//! A factorised symmetric system with iterative refinement: what Ipopt's linear solver has to do.

use crate::analysis::Analysis;
use crate::factor::{Factor, FactorStats, Inertia};
use crate::symmetric::Structure;
use crate::KktError;

/// At most this many steps of plain iterative refinement per solve.
pub const MAX_REFINEMENT: usize = 3;
/// Refinement stops once the normwise backward error is at most this (and the componentwise
/// one at most [`COMPONENTWISE_ERROR`]).
pub const BACKWARD_ERROR: f64 = 4.0 * f64::EPSILON;
/// Refinement stops once the componentwise backward error `max_i |b − A x|_i / (|A| |x| + |b|)_i`
/// is at most this (and the normwise one at most [`BACKWARD_ERROR`]). A solution that is
/// backward stable only normwise can be wrong in its small components: on the recorded
/// N = 1000 KKT matrix, 1.2e-8 componentwise left it 1e-8 (relative) from MUMPS's, one more
/// step 1.5e-12.
pub const COMPONENTWISE_ERROR: f64 = 1e-12;

/// The analysis of one structure and the factorisation of the latest values.
#[derive(Clone, Debug)]
pub struct SymmetricSolver {
    analysis: Analysis,
    values: Vec<f64>,
    factor: Option<Factor>,
    options: SweepOptions,
}

/// How the frontal sweep may be cut and run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepOptions {
    /// Split an order of at least [`crate::SPLIT_FROM`] variables (when the cut is narrow) into two
    /// halves swept from the two ends of the chain and a root front where they meet. The split
    /// changes the pivots, and with them the rounding.
    pub split: bool,
    /// Sweep the two halves of a split at once, on two threads. The factor is the same to the bit
    /// on one thread or two.
    pub two_threads: bool,
}

impl Default for SweepOptions {
    /// Split unless the environment variable `SPINE_KKT_SPLIT` is `0`; two threads unless
    /// `SPINE_KKT_THREADS` is `1`, when the machine has two cores or more.
    fn default() -> Self {
        static DEFAULT: std::sync::OnceLock<SweepOptions> = std::sync::OnceLock::new();
        *DEFAULT.get_or_init(|| {
            let unless = |name: &str, off: &str| std::env::var(name).map(|v| v.trim() != off);
            SweepOptions {
                split: unless("SPINE_KKT_SPLIT", "0").unwrap_or(true),
                two_threads: unless("SPINE_KKT_THREADS", "1")
                    .unwrap_or_else(|_| std::thread::available_parallelism().is_ok_and(|cores| cores.get() >= 2)),
            }
        })
    }
}

/// What one solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveReport {
    /// Steps of plain iterative refinement taken.
    pub refinement_steps: usize,
    /// The final componentwise backward error `max_i |b − A x|_i / (|A| |x| + |b|)_i`.
    pub backward_error: f64,
    /// The normwise backward error `‖b − A x‖∞ / ‖|A| |x| + |b|‖∞`.
    pub normwise_error: f64,
    /// Whether plain refinement stalled and GMRES corrected the solution.
    pub krylov: bool,
}

impl SymmetricSolver {
    /// Orders the structure (the symbolic phase).
    pub fn new(structure: Structure) -> Self {
        Self::with_options(structure, SweepOptions::default())
    }

    /// [`SymmetricSolver::new`] with these options.
    pub fn with_options(structure: Structure, options: SweepOptions) -> Self {
        Self { analysis: Analysis::new(structure, options.split), values: Vec::new(), factor: None, options }
    }

    /// The analysis of the structure.
    pub fn analysis(&self) -> &Analysis {
        &self.analysis
    }

    /// Factorises the matrix with these values (in the structure's stored order) and returns its
    /// inertia. A singular matrix is an error and leaves no factorisation.
    pub fn factorize(&mut self, values: &[f64]) -> Result<Inertia, KktError> {
        let factor = Factor::reusing(&self.analysis, values, self.factor.take(), self.options.two_threads)?;
        self.values.clear();
        self.values.extend_from_slice(values);
        let inertia = factor.inertia();
        self.factor = Some(factor);
        Ok(inertia)
    }

    /// Makes the next factorisation search for its pivots instead of replaying those of the last
    /// one (which it tests again and abandons where they fail).
    pub fn forget_pivot_sequence(&mut self) {
        if let Some(factor) = self.factor.as_mut() {
            factor.forget_pivot_sequence();
        }
    }

    /// Statistics of the current factorisation.
    pub fn stats(&self) -> Option<FactorStats> {
        self.factor.as_ref().map(Factor::stats)
    }

    /// Overwrites `b` with `A⁻¹ b`: the factorisation's solution, refined while plain refinement
    /// gains (at most [`MAX_REFINEMENT`] steps, until the normwise backward error is at
    /// [`BACKWARD_ERROR`] and the componentwise one at [`COMPONENTWISE_ERROR`]), then corrected
    /// once by GMRES when the normwise error is still above [`KRYLOV_AFTER`].
    pub fn solve(&self, b: &mut [f64]) -> Result<SolveReport, KktError> {
        let factor = self.factor.as_ref().ok_or(KktError::NotFactorized)?;
        let n = self.analysis.order();
        if b.len() != n {
            return Err(KktError::Input(format!("right-hand side of length {} for order {n}", b.len())));
        }
        let structure = self.analysis.structure();
        let rhs = b.to_vec();
        let mut work = Vec::with_capacity(n);
        factor.solve_in_place(b, &mut work);
        let mut report = SolveReport::default();
        let mut residual = vec![0.0; n];
        let mut magnitude = vec![0.0; n];
        let mut measure = |x: &[f64], residual: &mut [f64], report: &mut SolveReport| {
            structure.multiply_with_magnitude(&self.values, x, residual, &mut magnitude);
            let (mut error, mut largest_residual, mut largest_scale) = (0.0f64, 0.0f64, 0.0f64);
            for i in 0..n {
                residual[i] = rhs[i] - residual[i];
                let scale = magnitude[i] + rhs[i].abs();
                if scale > 0.0 {
                    error = error.max(residual[i].abs() / scale);
                }
                largest_residual = largest_residual.max(residual[i].abs());
                largest_scale = largest_scale.max(scale);
            }
            report.backward_error = error;
            report.normwise_error = if largest_scale > 0.0 { largest_residual / largest_scale } else { 0.0 };
        };
        measure(b, &mut residual, &mut report);
        // Plain refinement while it gains at least a factor 2 per step, until both backward
        // errors are on target.
        let excess = |report: &SolveReport| {
            (report.normwise_error / BACKWARD_ERROR).max(report.backward_error / COMPONENTWISE_ERROR)
        };
        while excess(&report) > 1.0 && report.refinement_steps < MAX_REFINEMENT {
            let before = excess(&report);
            let mut correction = residual.clone();
            factor.solve_in_place(&mut correction, &mut work);
            let previous = b.to_vec();
            for (x, d) in b.iter_mut().zip(&correction) {
                *x += d;
            }
            report.refinement_steps += 1;
            measure(b, &mut residual, &mut report);
            if excess(&report) > 0.5 * before {
                if excess(&report) > before {
                    b.copy_from_slice(&previous);
                    measure(b, &mut residual, &mut report);
                }
                break;
            }
        }
        // Where that stalls short of what Ipopt needs, GMRES on the correction equation.
        if report.normwise_error > KRYLOV_AFTER {
            let correction = gmres(structure, &self.values, factor, &residual, GMRES_ITERATIONS, &mut work);
            let previous = b.to_vec();
            let before = report.normwise_error;
            for (x, d) in b.iter_mut().zip(&correction) {
                *x += d;
            }
            report.krylov = true;
            measure(b, &mut residual, &mut report);
            if report.normwise_error > before {
                b.copy_from_slice(&previous);
                measure(b, &mut residual, &mut report);
            }
        }
        Ok(report)
    }
}

/// A solve whose normwise backward error stays above this after plain refinement gets one GMRES
/// correction.
pub const KRYLOV_AFTER: f64 = 1e-10;

/// Krylov steps per refinement step.
pub const GMRES_ITERATIONS: usize = 12;

/// An approximate solution of `A d = r` by GMRES from `d = 0`, preconditioned on the right by the
/// factorisation (`A M⁻¹ y = r`, `d = M⁻¹ y`), at most `steps` Arnoldi steps (modified
/// Gram–Schmidt, Givens rotations). Where the factorisation is exact but for the Schur complement of
/// the few dense rows, `A M⁻¹` is the identity plus a perturbation of that small rank, and GMRES
/// ends in that many steps.
fn gmres(
    structure: &Structure,
    values: &[f64],
    factor: &Factor,
    r: &[f64],
    steps: usize,
    work: &mut Vec<f64>,
) -> Vec<f64> {
    let n = r.len();
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let beta = norm(r);
    let mut d = vec![0.0; n];
    if beta == 0.0 || !beta.is_finite() {
        return d;
    }
    let mut basis: Vec<Vec<f64>> = vec![r.iter().map(|x| x / beta).collect()];
    let mut h = vec![vec![0.0; steps]; steps + 1];
    let (mut cs, mut sn) = (vec![0.0; steps], vec![0.0; steps]);
    let mut g = vec![0.0; steps + 1];
    g[0] = beta;
    let mut z = vec![0.0; n];
    let mut used = 0;
    for j in 0..steps {
        z.copy_from_slice(&basis[j]);
        factor.solve_in_place(&mut z, work);
        let mut w = vec![0.0; n];
        structure.multiply(values, &z, &mut w);
        for (i, v) in basis.iter().enumerate() {
            let hij: f64 = w.iter().zip(v).map(|(a, b)| a * b).sum();
            h[i][j] = hij;
            for (wk, vk) in w.iter_mut().zip(v) {
                *wk -= hij * vk;
            }
        }
        let hnext = norm(&w);
        h[j + 1][j] = hnext;
        for i in 0..j {
            let t = cs[i] * h[i][j] + sn[i] * h[i + 1][j];
            h[i + 1][j] = -sn[i] * h[i][j] + cs[i] * h[i + 1][j];
            h[i][j] = t;
        }
        let rho = h[j][j].hypot(h[j + 1][j]);
        if rho == 0.0 {
            break;
        }
        cs[j] = h[j][j] / rho;
        sn[j] = h[j + 1][j] / rho;
        h[j][j] = rho;
        h[j + 1][j] = 0.0;
        g[j + 1] = -sn[j] * g[j];
        g[j] *= cs[j];
        used = j + 1;
        if g[j + 1].abs() <= f64::EPSILON * beta || hnext == 0.0 {
            break;
        }
        basis.push(w.iter().map(|x| x / hnext).collect());
    }
    // y from the triangular system, then d = M⁻¹ (V y).
    let mut y = vec![0.0; used];
    for i in (0..used).rev() {
        let sum: f64 = (i + 1..used).map(|k| h[i][k] * y[k]).sum();
        y[i] = (g[i] - sum) / h[i][i];
    }
    for (k, yk) in y.iter().enumerate() {
        for (di, vi) in d.iter_mut().zip(&basis[k]) {
            *di += yk * vi;
        }
    }
    factor.solve_in_place(&mut d, work);
    d
}
