//! The rates of the NLP's data (Lagrangian gradient, constraints, objective, bounds) in one
//! parameter at the optimum, by central differences of the problem rebuilt at `p ± h` with the
//! exact AD first derivatives, and whether the dependence is affine.

use super::point::Evaluation;
use super::{Optimum, Parameter, SensitivityError};
use crate::DesignProblem;

/// The rates of the NLP's data in one parameter at the optimum.
pub(crate) struct Rates {
    pub lagrangian_gradient: Vec<f64>,
    pub constraints: Vec<f64>,
    pub objective: f64,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub row_lower: Vec<f64>,
    pub row_upper: Vec<f64>,
    pub stiffness_scale: f64,
    pub affine: bool,
}

/// The rates of the NLP's data in the parameter by central differences of the rebuilt problem at
/// `p ± h`, and whether they are affine (the second difference at round-off).
pub(crate) fn rates(
    optimum: &Optimum<'_>,
    at: &Evaluation,
    pattern: &[(usize, usize)],
    parameter: &Parameter<'_>,
) -> Result<(f64, Rates), SensitivityError> {
    let h = 1e-4 * parameter.value.abs().max(1.0);
    let build = |value: f64| -> Result<DesignProblem, SensitivityError> {
        let problem = (parameter.problem_at)(value)
            .map_err(|reason| SensitivityError::Parameter { name: parameter.name.clone(), reason })?;
        if problem.n_links() != optimum.problem.n_links() {
            return Err(SensitivityError::Size(parameter.name.clone()));
        }
        Ok(problem)
    };
    let (plus_problem, minus_problem) = (build(parameter.value + h)?, build(parameter.value - h)?);
    let (layout, x) = (optimum.layout, optimum.x);
    let (plus, minus) = (Evaluation::at(&plus_problem, layout, x), Evaluation::at(&minus_problem, layout, x));
    let lambda = &optimum.multipliers.constraints;
    let (gp, g0, gm) = (
        plus.lagrangian_gradient(pattern, lambda),
        at.lagrangian_gradient(pattern, lambda),
        minus.lagrangian_gradient(pattern, lambda),
    );
    let rate = |p: &[f64], m: &[f64]| -> Vec<f64> {
        p.iter().zip(m).map(|(a, b)| if a == b { 0.0 } else { (a - b) / (2.0 * h) }).collect()
    };
    // The size of the terms that cancel in `∇f + Jᵀλ` (zero at the optimum): its round-off.
    let terms = at.gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()))
        + lambda.iter().fold(0.0f64, |m, l| m.max(l.abs())) * at.jacobian.iter().fold(0.0f64, |m, j| m.max(j.abs()));
    let affine = [
        (&gp, &g0, &gm, terms),
        (&plus.constraints, &at.constraints, &minus.constraints, 0.0),
        (&plus.lower, &at.lower, &minus.lower, 0.0),
        (&plus.upper, &at.upper, &minus.upper, 0.0),
    ]
    .iter()
    .all(|(p, z, m, terms)| second_difference_at_round_off(p, z, m, *terms));
    let rates = Rates {
        lagrangian_gradient: rate(&gp, &gm),
        constraints: rate(&plus.constraints, &minus.constraints),
        objective: (plus.objective - minus.objective) / (2.0 * h),
        lower: rate(&plus.lower, &minus.lower),
        upper: rate(&plus.upper, &minus.upper),
        row_lower: rate(&plus.row_lower, &minus.row_lower),
        row_upper: rate(&plus.row_upper, &minus.row_upper),
        stiffness_scale: (plus_problem.stiffness_scale - minus_problem.stiffness_scale) / (2.0 * h),
        affine,
    };
    Ok((h, rates))
}

/// Whether `p − 2 z + m` is at the round-off of the values (or of `terms`, the size of what
/// cancels in them), or below 1e-7 of the first difference: a dependence with curvature leaves
/// `h` (1e-4 relative) of it.
fn second_difference_at_round_off(p: &[f64], z: &[f64], m: &[f64], terms: f64) -> bool {
    let first =
        p.iter().zip(m).fold(0.0f64, |s, (a, c)| if a.is_finite() && c.is_finite() { s.max((a - c).abs()) } else { s });
    p.iter().zip(z).zip(m).all(|((&a, &b), &c)| {
        if !(a.is_finite() && b.is_finite() && c.is_finite()) {
            return true;
        }
        let round_off = 1e3 * f64::EPSILON * (a.abs() + 2.0 * b.abs() + c.abs() + 4.0 * terms);
        (a - 2.0 * b + c).abs() <= round_off + 1e-7 * first
    })
}
