//! The rates of the NLP's data (Lagrangian gradient, constraints, objective, bounds) in one
//! parameter at the optimum, by differences of the problem rebuilt at `p ± h` (one-sided at the
//! edge of what the case allows) with the exact AD first derivatives, and whether the dependence
//! is affine.

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
    pub difference: Difference,
}

/// Which three points the rates were differenced on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Difference {
    /// `p − h, p, p + h`: the case allows both sides.
    Central,
    /// `p, p + h, p + 2h`: `p − h` is outside what the case allows (a bound at its edge, e.g.
    /// `bounds.stiffness_min` = 0).
    Forward,
    /// `p − 2h, p − h, p`: `p + h` is outside what the case allows.
    Backward,
}

impl Difference {
    /// The points' offsets in steps of `h`, and the weights of the derivative at `p` (over `2h`)
    /// of the parabola through them.
    fn stencil(self) -> ([f64; 3], [f64; 3]) {
        match self {
            Self::Central => ([-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0]),
            Self::Forward => ([0.0, 1.0, 2.0], [-3.0, 4.0, -1.0]),
            Self::Backward => ([-2.0, -1.0, 0.0], [1.0, -4.0, 3.0]),
        }
    }
}

/// The rates of the NLP's data in the parameter by differences of the rebuilt problem on three
/// points `h` apart, central where the case allows `p ± h`, else one-sided (second order either
/// way), and whether they are affine (the second difference at round-off).
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
    let stencil = |difference: Difference| -> Result<Vec<Option<DesignProblem>>, SensitivityError> {
        let (offsets, _) = difference.stencil();
        offsets.iter().map(|&o| if o == 0.0 { Ok(None) } else { build(parameter.value + o * h).map(Some) }).collect()
    };
    let central = stencil(Difference::Central);
    let (difference, problems) = match central {
        Ok(p) => (Difference::Central, p),
        Err(e) => match (stencil(Difference::Forward), stencil(Difference::Backward)) {
            (Ok(p), _) => (Difference::Forward, p),
            (_, Ok(p)) => (Difference::Backward, p),
            _ => return Err(e),
        },
    };
    let (layout, x) = (optimum.layout, optimum.x);
    let (_, weights) = difference.stencil();
    let evaluations: Vec<Evaluation> =
        problems.iter().map(|p| Evaluation::at(p.as_ref().unwrap_or(optimum.problem), layout, x)).collect();
    let scales: Vec<f64> = problems.iter().map(|p| p.as_ref().unwrap_or(optimum.problem).stiffness_scale).collect();
    let lambda = &optimum.multipliers.constraints;
    let gradients: Vec<Vec<f64>> = evaluations.iter().map(|e| e.lagrangian_gradient(pattern, lambda)).collect();
    let scalar = |v: [f64; 3]| -> f64 {
        if v[0] == v[1] && v[1] == v[2] {
            0.0
        } else {
            // Zero weights left out: the central difference is `(p+ − p−) / 2h` to the last bit
            // (and an infinite bound at `p` cannot make it NaN).
            let sum = (0..3).filter(|&k| weights[k] != 0.0).fold(0.0, |s, k| s + weights[k] * v[k]);
            sum / (2.0 * h)
        }
    };
    let rate = |a: &[f64], b: &[f64], c: &[f64]| -> Vec<f64> {
        a.iter().zip(b).zip(c).map(|((&a, &b), &c)| scalar([a, b, c])).collect()
    };
    let e = &evaluations;
    // The size of the terms that cancel in `∇f + Jᵀλ` (zero at the optimum): its round-off.
    let terms = at.gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()))
        + lambda.iter().fold(0.0f64, |m, l| m.max(l.abs())) * at.jacobian.iter().fold(0.0f64, |m, j| m.max(j.abs()));
    let affine = [
        (&gradients[2], &gradients[1], &gradients[0], terms),
        (&e[2].constraints, &e[1].constraints, &e[0].constraints, 0.0),
        (&e[2].lower, &e[1].lower, &e[0].lower, 0.0),
        (&e[2].upper, &e[1].upper, &e[0].upper, 0.0),
    ]
    .iter()
    .all(|(p, z, m, terms)| second_difference_at_round_off(p, z, m, *terms));
    let rates = Rates {
        lagrangian_gradient: rate(&gradients[0], &gradients[1], &gradients[2]),
        constraints: rate(&e[0].constraints, &e[1].constraints, &e[2].constraints),
        objective: scalar([e[0].objective, e[1].objective, e[2].objective]),
        lower: rate(&e[0].lower, &e[1].lower, &e[2].lower),
        upper: rate(&e[0].upper, &e[1].upper, &e[2].upper),
        row_lower: rate(&e[0].row_lower, &e[1].row_lower, &e[2].row_lower),
        row_upper: rate(&e[0].row_upper, &e[1].row_upper, &e[2].row_upper),
        stiffness_scale: scalar([scales[0], scales[1], scales[2]]),
        affine,
        difference,
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

#[cfg(test)]
mod tests {
    use super::Difference;

    /// Each stencil gives the exact derivative at `p` of any quadratic: the weights (over 2h)
    /// annihilate constants and curvature and give 1 on the slope.
    #[test]
    fn stencils_are_exact_for_quadratics() {
        for d in [Difference::Central, Difference::Forward, Difference::Backward] {
            let (offsets, weights) = d.stencil();
            for (power, want) in [(0, 0.0), (1, 1.0), (2, 0.0)] {
                let got: f64 = offsets.iter().zip(weights).map(|(o, w)| w * o.powi(power)).sum::<f64>() / 2.0;
                assert_eq!(got, want, "{d:?}, power {power}");
            }
        }
    }
}
