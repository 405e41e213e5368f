//! The cost baseline of the sensitivity step, for benchmarks: the optimum's reduced KKT matrix
//! built, factorised and solved for as many right-hand sides as there are parameters, and nothing
//! else the step does (no evaluation, no active set, no LICQ measures, no rates).

use super::active_set::{ActiveSet, Bound};
use super::system::{ActiveSystem, Matrices, ReducedKkt};
use super::Optimum;

/// The reduced KKT system of an optimum's active set, ready to be factorised again and again.
pub struct KktBaseline {
    n: usize,
    m: usize,
    variables: Vec<Bound>,
    /// The rows of the step's system (`None` where it is singular).
    rows: Option<Vec<Bound>>,
    matrices: Matrices,
}

impl KktBaseline {
    /// The optimum's matrices and active set (its dependent rows left out, as the step leaves
    /// them out).
    pub fn new(optimum: &Optimum<'_>) -> Self {
        let (layout, x) = (optimum.layout, optimum.x);
        let (at, matrices) = Matrices::at(optimum.problem, layout, x, &optimum.multipliers.constraints);
        let set = ActiveSet::identify(x, &at, &matrices.jacobian_pattern, optimum.multipliers);
        let system = ActiveSystem::new(&matrices, layout, set.variables.clone(), set.rows.clone());
        let rows = system.kkt.map(|kkt| kkt.rows);
        Self { n: layout.num_variables(), m: layout.num_constraints(), variables: system.variables, rows, matrices }
    }

    /// Builds and factorises the reduced KKT matrix and solves it for `solves` right-hand sides
    /// (all ones); the sum of the solutions, or `None` when the matrix is singular.
    pub fn factorise_and_solve(&self, solves: usize) -> Option<f64> {
        let hessian = (&self.matrices.hessian_pattern[..], &self.matrices.hessian[..]);
        let jacobian = (&self.matrices.jacobian_pattern[..], &self.matrices.jacobian[..]);
        let kkt = ReducedKkt::new(self.n, self.m, &self.variables, self.rows.as_ref()?, hessian, jacobian).ok()?;
        let mut sum = 0.0;
        for _ in 0..solves {
            let mut rhs = vec![1.0; kkt.free + kkt.rows.len()];
            kkt.solve(&mut rhs).ok()?;
            sum += rhs.iter().sum::<f64>();
        }
        Some(sum)
    }
}
