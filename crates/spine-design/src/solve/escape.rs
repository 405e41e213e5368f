//! Stage 5 of a design run ([`crate::solve`]): leaving a point that is not a minimum (or a weak
//! one) for a lower minimum: the design stepped along the direction of negative (or zero)
//! curvature and eq. (33) solved again from each side, or solved again from the whole point where
//! no direction was formed. Every point left is listed in the result
//! ([`crate::result::Escape`]).

use super::ipopt::DesignError;
use super::run::{resolve_from, run_solver, FullPoint};
use crate::certificate::NegativeCurvature;
use crate::problem::DesignProblem;
use crate::result::DesignResult;
use crate::settings::{Formulation, SolverSettings};
use crate::solver_run::SolverRun;
use spine_model::Design;

/// The steps along a direction of negative curvature, as fractions of the design box: the design
/// variable the direction moves most (relative to its bound interval) moves by this fraction of
/// its interval. The smaller is tried first; the larger where the smaller falls back.
pub const ESCAPE_STEPS: [f64; 2] = [0.02, 0.1];

/// Eq. (33) from `run`'s design stepped along `±d` (design variables only, [`ESCAPE_STEPS`]; the
/// states are found again): the lowest clean end below `below` by more than `margin` relative
/// (`None` when no step reaches one).
pub(super) fn leave(
    problem: &DesignProblem,
    run: &SolverRun,
    negative: &NegativeCurvature,
    (below, margin): (f64, f64),
    settings: &SolverSettings,
) -> Result<Option<(SolverRun, DesignResult)>, DesignError> {
    let layout = run.solver.layout(problem);
    let b = &problem.bounds;
    let d = &negative.direction;
    let c = problem.stiffness_scale;
    // The direction's largest move relative to each design variable's interval.
    let theta_width = 2.0 * b.theta0_max;
    let reach = (0..layout.n)
        .map(|i| d[layout.theta0(i)].abs() / theta_width)
        .chain(
            (0..=layout.n)
                .map(|j| d[layout.stiffness(j)].abs() * c / (b.stiffness_max[j] - b.stiffness_min[j]).max(1e-300)),
        )
        .fold(0.0f64, f64::max);
    if reach <= 0.0 || !reach.is_finite() {
        return Ok(None);
    }
    for fraction in ESCAPE_STEPS {
        let alpha = fraction / reach;
        let mut best: Option<(SolverRun, DesignResult)> = None;
        for sign in [1.0, -1.0] {
            let step = sign * alpha;
            let start = Design {
                theta0: (0..layout.n).map(|i| run.design.theta0[i] + step * d[layout.theta0(i)]).collect(),
                stiffness: (0..=layout.n)
                    .map(|j| run.design.stiffness[j] + step * d[layout.stiffness(j)] * c)
                    .collect(),
            };
            let next = run_solver(problem, &start, Formulation::Full, settings, &mut |_| true)?;
            let result = next.clone().check(problem, settings);
            let lower = result.objective < below - margin * below.abs();
            if result.is_clean() && lower && best.as_ref().is_none_or(|(_, b)| result.objective < b.objective) {
                best = Some((next, result));
            }
        }
        if best.is_some() {
            return Ok(best);
        }
    }
    Ok(None)
}

/// Eq. (33) from `run`'s whole point (design and states, fresh multipliers) with `settings`: its
/// end, where clean and below `below`.
pub(super) fn restart(
    problem: &DesignProblem,
    run: &SolverRun,
    below: f64,
    settings: &SolverSettings,
) -> Result<Option<(SolverRun, DesignResult)>, DesignError> {
    let Some(states) = run.states.as_ref() else { return Ok(None) };
    let form = run.solver.layout(problem).states;
    let point = FullPoint {
        form,
        design: &run.design,
        states,
        multipliers: None,
        springs: settings.spring_variables.resolve(problem),
    };
    let next = resolve_from(problem, point, &settings.ipopt())?;
    let result = next.clone().check(problem, settings);
    Ok((result.is_clean() && result.objective < below * (1.0 - 1e-9)).then_some((next, result)))
}
