//! The NLP of eq. (33) evaluated at one point for one problem: what the KKT conditions and their
//! parameter derivatives need (values, first derivatives, bounds).

use crate::assembly::Assembled;
use crate::full_space::Layout;
use crate::numbers::Numbers;
use crate::DesignProblem;

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
        let numbers = Numbers::of(problem);
        let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
        numbers.variable_bounds(&mut lower, &mut upper, |j| layout.height(j));
        let (mut row_lower, mut row_upper) = (vec![0.0; m], vec![0.0; m]);
        numbers.constraint_bounds(
            &mut row_lower,
            &mut row_upper,
            layout.end_row(),
            |i| layout.relative_row(i),
            layout.budget_row_if_any(),
        );
        Self { objective, constraints, gradient, jacobian, lower, upper, row_lower, row_upper }
    }
}
