//! The cost baseline of the sensitivity step, for benchmarks: the optimum's reduced KKT matrix
//! built and factorised, and solved for the step's own right-hand sides (one per parameter), and
//! nothing else the step does (no evaluation, no active set, no LICQ measure, no rates).

use super::derivative::right_hand_side;
use super::rates::rates;
use super::{Optimum, Parameter, SensitivityError};
use crate::optimality::active_set::{ActiveSet, Bound};
use crate::optimality::system::{ActiveSystem, Matrices, ReducedKkt};

/// The reduced KKT system of an optimum's active set, ready to be factorised again and again, with
/// the right-hand sides its parameters' derivatives solve for.
pub struct KktBaseline {
    n: usize,
    m: usize,
    variables: Vec<Bound>,
    /// The rows of the step's system (`None` where it is singular).
    rows: Option<Vec<Bound>>,
    matrices: Matrices,
    right_hand_sides: Vec<Vec<f64>>,
}

impl KktBaseline {
    /// The optimum's matrices and active set (its dependent rows left out, as the step leaves
    /// them out), and each parameter's right-hand side.
    pub fn new(optimum: &Optimum<'_>, parameters: &[Parameter]) -> Result<Self, SensitivityError> {
        let (layout, x) = (optimum.layout, optimum.x);
        let assembled = crate::full_space::assemble(optimum.problem, layout.states);
        let (at, matrices) = Matrices::of(&assembled, optimum.problem, layout, x, &optimum.multipliers.constraints);
        let set = ActiveSet::identify(x, &at, &matrices.jacobian_pattern, optimum.multipliers);
        let system = ActiveSystem::new(&matrices, layout, set.variables.clone(), set.rows.clone());
        let mut right_hand_sides = Vec::new();
        if let Some(kkt) = &system.kkt {
            for p in parameters {
                let rates = rates(optimum, &assembled.groups, &p.name, &p.tangent)?;
                right_hand_sides.push(right_hand_side(kkt, &system.variables, &matrices, &rates).1);
            }
        }
        let rows = system.kkt.map(|kkt| kkt.rows);
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        Ok(Self { n, m, variables: system.variables, rows, matrices, right_hand_sides })
    }

    /// Builds and factorises the reduced KKT matrix and solves it for each parameter's
    /// right-hand side; the sum of the solutions, or `None` when the matrix is singular.
    pub fn factorise_and_solve(&self) -> Option<f64> {
        let hessian = (&self.matrices.hessian_pattern[..], &self.matrices.hessian[..]);
        let jacobian = (&self.matrices.jacobian_pattern[..], &self.matrices.jacobian[..]);
        let kkt = ReducedKkt::new(self.n, self.m, &self.variables, self.rows.as_ref()?, hessian, jacobian).ok()?;
        let mut sum = 0.0;
        for b in &self.right_hand_sides {
            let mut rhs = b.clone();
            kkt.solve(&mut rhs).ok()?;
            sum += rhs.iter().sum::<f64>();
        }
        Some(sum)
    }
}
