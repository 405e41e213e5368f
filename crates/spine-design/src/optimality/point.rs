//! The NLP of eq. (33) evaluated at one point for one problem: what the KKT conditions and their
//! parameter derivatives need (values, first derivatives, bounds).

use crate::assembly::Assembled;
use crate::layout::Layout;
use crate::numbers::{FullSpaceBounds, Numbers};
use crate::problem::DesignProblem;

/// `f`, `g`, `∇f`, the Jacobian (in the assembled pattern) and all bounds at `x`.
pub(crate) struct Evaluation {
    pub objective: f64,
    pub constraints: Vec<f64>,
    pub gradient: Vec<f64>,
    pub jacobian: Vec<f64>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub row_lower: Vec<f64>,
    pub row_upper: Vec<f64>,
}

impl Evaluation {
    /// The evaluation with the problem's elements already assembled.
    pub fn of(assembled: &Assembled, problem: &DesignProblem, layout: Layout, x: &[f64]) -> Self {
        let (n, m) = (layout.num_variables(), layout.num_constraints());
        let mut constraints = vec![0.0; m];
        let objective = assembled.values(x, &mut constraints);
        let mut gradient = vec![0.0; n];
        let mut jacobian = vec![0.0; assembled.patterns.jacobian.len()];
        assembled.first_derivatives(x, &mut gradient, &mut jacobian);
        let FullSpaceBounds { lower, upper, row_lower, row_upper } = Numbers::of(problem).full_space_bounds(&layout);
        Self { objective, constraints, gradient, jacobian, lower, upper, row_lower, row_upper }
    }
}
