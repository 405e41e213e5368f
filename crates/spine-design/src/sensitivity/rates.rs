//! The rates of the NLP's data (Lagrangian gradient, constraints, objective, bounds) along one
//! parameter at the optimum, exact: the problem's numbers carried as duals along the parameter's
//! [`ProblemTangent`] ([`Numbers::along`]: load resultants, spans, `C_K`, the end target and the
//! bounds, `K/C_K` included), and each element whose constants move differentiated by one pass of
//! a tangent jet ([`crate::assembly::rates`]). Nothing is differenced, and the elements need no
//! sparsity patterns.

use super::{Optimum, SensitivityError};
use crate::assembly::{AnyGroup, NlpRates};
use crate::full_space::groups;
use crate::numbers::ProblemTangent;
use crate::numbers::{FullSpaceBounds, Numbers};
use num_dual::Dual64;

/// The rates of the NLP's data in one parameter at the optimum.
pub(crate) struct Rates {
    pub lagrangian_gradient: Vec<f64>,
    pub constraints: Vec<f64>,
    pub objective: f64,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub row_lower: Vec<f64>,
    pub row_upper: Vec<f64>,
    /// `dC_K/dp`.
    pub stiffness_scale: f64,
}

/// The exact rates of the NLP's data along `tangent` at the optimum, whose elements are `elements`
/// (the groups of [`crate::full_space::groups`], registered or not).
pub(crate) fn rates(
    optimum: &Optimum<'_>,
    elements: &[Box<dyn AnyGroup + Send + Sync>],
    name: &str,
    tangent: &ProblemTangent,
) -> Result<Rates, SensitivityError> {
    let (problem, layout) = (optimum.problem, optimum.layout);
    if !tangent.fits(problem) {
        return Err(SensitivityError::Size(name.to_string()));
    }
    let numbers = Numbers::along(problem, tangent);
    let moving = numbers.rates();
    let (n, m) = (layout.num_variables(), layout.num_constraints());
    // A parameter that moves only bounds or `δ_d` (no element's constant) has no element rates.
    let nlp = if moving.moves_elements() {
        crate::assembly::rates(elements, &groups(&moving, layout.states), optimum.x, &optimum.multipliers.constraints)
    } else {
        NlpRates { objective: 0.0, constraints: vec![0.0; m], lagrangian_gradient: vec![0.0; n] }
    };
    let FullSpaceBounds { lower, upper, row_lower, row_upper } = numbers.full_space_bounds(&layout);
    let rate = |v: Vec<Dual64>| -> Vec<f64> { v.iter().map(|d| d.eps).collect() };
    Ok(Rates {
        lagrangian_gradient: nlp.lagrangian_gradient,
        constraints: nlp.constraints,
        objective: nlp.objective,
        lower: rate(lower),
        upper: rate(upper),
        row_lower: rate(row_lower),
        row_upper: rate(row_upper),
        stiffness_scale: numbers.stiffness_scale.eps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::full_space::{assemble, Multipliers};
    use crate::layout::{Layout, StateForm};
    use crate::optimality::point::Evaluation;
    use crate::optimality::system::jacobian_transpose_times;
    use spine_model::rng::SplitMix64;

    /// The exact rates along a direction in which every number of the problem moves at once
    /// (loads, spans, masses and gravity, whose product the self-weight is, `C_K` in the elements
    /// and in the bounds `K/C_K`, `δ_d`, every bound) against central differences of the NLP's
    /// data evaluated on the moved problems, at a random point with random multipliers, in both
    /// state forms.
    #[test]
    fn exact_rates_match_central_differences_of_the_moved_problems() {
        let mut load = spine_model::NodalLoads::zero(6);
        load.p_y.fill(-3.0);
        load.p_x[6] = 20.0;
        let objectives = [
            crate::objective::Objective::StrainEnergy,
            crate::objective::Objective::TotalStiffness,
            crate::objective::Objective::PeakMoment { exponent: 6, reference: 30.0 },
            crate::objective::Objective::Compliance { load },
        ];
        for objective in objectives {
            let mut problem = crate::fixtures::paper_problem(6, -10.0, -400.0, -0.02, 100.0);
            problem.structure.chain.masses = vec![0.2; 6];
            // The budget row with the criterion it is made for.
            problem.strain_energy_max = (objective == crate::objective::Objective::TotalStiffness).then_some(0.05);
            problem.objective = objective;
            let mut rng = SplitMix64::new(5);
            let mut tangent = ProblemTangent::zero(&problem);
            let r = tangent.rates_mut();
            let mut random =
                |v: &mut Vec<f64>, size: f64| v.iter_mut().for_each(|x| *x = size * rng.uniform(-1.0, 1.0));
            let s = &mut r.structure;
            random(&mut s.chain.spans, 0.01);
            random(&mut s.chain.masses, 0.1);
            random(&mut s.passive.p_y, 3.0);
            random(&mut s.passive.p_x, 3.0);
            random(&mut s.actuation.p_x, 30.0);
            random(&mut s.actuation.p_y, 3.0);
            random(&mut r.bounds.stiffness_min, 10.0);
            random(&mut r.bounds.stiffness_max, 100.0);
            (s.chain.gravity, r.delta_d, r.stiffness_scale) = (0.5, 0.003, 20.0);
            let b = &mut r.bounds;
            (b.theta0_max, b.relative_angle_max, b.height_min, b.height_max) = (0.1, -0.05, 0.002, 0.01);
            match &mut r.objective {
                crate::objective::Objective::PeakMoment { reference, .. } => *reference = 4.0,
                crate::objective::Objective::TotalStiffness => r.strain_energy_max = Some(0.01),
                crate::objective::Objective::Compliance { load } => {
                    random(&mut load.p_y, 2.0);
                    random(&mut load.p_x, 2.0);
                }
                _ => {}
            }
            for states in [StateForm::Absolute, StateForm::Deflection] {
                let layout = Layout::of(&problem, states);
                let (n, m) = (layout.num_variables(), layout.num_constraints());
                let mut rng = SplitMix64::new(9);
                let x: Vec<f64> = (0..n).map(|_| rng.uniform(-0.5, 0.5)).collect();
                let lambda: Vec<f64> = (0..m).map(|_| rng.uniform(-2.0, 2.0)).collect();
                let multipliers =
                    Multipliers { constraints: lambda.clone(), z_lower: vec![0.0; n], z_upper: vec![0.0; n] };
                let optimum = Optimum { problem: &problem, layout, x: &x, multipliers: &multipliers };
                let assembled = assemble(&problem, states);
                let exact = rates(&optimum, &assembled.groups, "all", &tangent).unwrap();
                let h = 1e-6;
                let at = |t: f64| {
                    let p = tangent.moved(&problem, t);
                    let assembled = assemble(&p, states);
                    let e = Evaluation::of(&assembled, &p, layout, &x);
                    // `∇f + Jᵀλ`.
                    let jt_lambda = jacobian_transpose_times(&assembled.patterns.jacobian, &e.jacobian, &lambda, n);
                    let gradient: Vec<f64> = e.gradient.iter().zip(&jt_lambda).map(|(g, j)| g + j).collect();
                    (e, gradient, p.stiffness_scale)
                };
                let ((hi, g_hi, c_hi), (lo, g_lo, c_lo)) = (at(h), at(-h));
                let check = |what: &str, exact: &[f64], hi: &[f64], lo: &[f64]| {
                    let size = exact.iter().fold(1.0f64, |s, v| s.max(v.abs()));
                    for (k, (e, (a, b))) in exact.iter().zip(hi.iter().zip(lo)).enumerate() {
                        let fd = if a.is_finite() { (a - b) / (2.0 * h) } else { 0.0 };
                        assert!((e - fd).abs() <= 1e-6 * size, "{states:?} {what}[{k}]: exact {e} vs {fd}");
                    }
                };
                check("∂(∇L)/∂p", &exact.lagrangian_gradient, &g_hi, &g_lo);
                check("∂g/∂p", &exact.constraints, &hi.constraints, &lo.constraints);
                check("∂f/∂p", &[exact.objective], &[hi.objective], &[lo.objective]);
                check("lower", &exact.lower, &hi.lower, &lo.lower);
                check("upper", &exact.upper, &hi.upper, &lo.upper);
                check("row lower", &exact.row_lower, &hi.row_lower, &lo.row_lower);
                check("row upper", &exact.row_upper, &hi.row_upper, &lo.row_upper);
                check("C_K", &[exact.stiffness_scale], &[c_hi], &[c_lo]);
                assert!(exact.lagrangian_gradient.iter().any(|&g| g != 0.0) && exact.objective != 0.0);
            }
        }
    }
}
