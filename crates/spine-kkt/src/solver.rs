//! A factorised symmetric system with iterative refinement: what Ipopt's linear solver has to do.

use crate::analysis::Analysis;
use crate::factor::{Factor, FactorStats, Inertia};
use crate::symmetric::Structure;
use crate::KktError;

/// At most this many steps of iterative refinement per solve.
pub const MAX_REFINEMENT: usize = 3;
/// Refinement stops once the componentwise backward error is at most this.
pub const BACKWARD_ERROR: f64 = 4.0 * f64::EPSILON;

/// The analysis of one structure and the factorisation of the latest values.
#[derive(Clone, Debug)]
pub struct SymmetricSolver {
    analysis: Analysis,
    values: Vec<f64>,
    factor: Option<Factor>,
}

/// What one solve did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveReport {
    /// Steps of iterative refinement taken.
    pub refinement_steps: usize,
    /// The final componentwise backward error `max_i |b − A x|_i / (|A| |x| + |b|)_i`.
    pub backward_error: f64,
}

impl SymmetricSolver {
    /// Orders the structure (the symbolic phase).
    pub fn new(structure: Structure) -> Self {
        Self { analysis: Analysis::new(structure), values: Vec::new(), factor: None }
    }

    /// The analysis of the structure.
    pub fn analysis(&self) -> &Analysis {
        &self.analysis
    }

    /// Factorises the matrix with these values (in the structure's stored order) and returns its
    /// inertia. A singular matrix is an error and leaves no factorisation.
    pub fn factorize(&mut self, values: &[f64]) -> Result<Inertia, KktError> {
        self.factor = None;
        let factor = Factor::new(&self.analysis, values)?;
        self.values.clear();
        self.values.extend_from_slice(values);
        let inertia = factor.inertia();
        self.factor = Some(factor);
        Ok(inertia)
    }

    /// Statistics of the current factorisation.
    pub fn stats(&self) -> Option<FactorStats> {
        self.factor.as_ref().map(Factor::stats)
    }

    /// Overwrites `b` with `A⁻¹ b`, refined until the backward error is at round-off.
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
        let (mut residual, mut magnitude) = (vec![0.0; n], vec![0.0; n]);
        let mut report = SolveReport::default();
        loop {
            structure.multiply(&self.values, b, &mut residual);
            structure.multiply_abs(&self.values, b, &mut magnitude);
            let mut error = 0.0f64;
            for i in 0..n {
                residual[i] = rhs[i] - residual[i];
                let scale = magnitude[i] + rhs[i].abs();
                if scale > 0.0 {
                    error = error.max(residual[i].abs() / scale);
                }
            }
            let stalled = report.refinement_steps > 0 && error > 0.5 * report.backward_error;
            report.backward_error = if stalled { report.backward_error.min(error) } else { error };
            if error <= BACKWARD_ERROR || stalled || report.refinement_steps == MAX_REFINEMENT {
                return Ok(report);
            }
            factor.solve_in_place(&mut residual, &mut work);
            for (x, d) in b.iter_mut().zip(&residual) {
                *x += d;
            }
            report.refinement_steps += 1;
        }
    }
}
