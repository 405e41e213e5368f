//! Stages 3 to 5 of a design run ([`crate::solve`]) in their order, as one loop: from a solver's
//! run to the optimum that is reported: checked, certified, and never a point that is not a
//! minimum when a minimum can be reached from it.
//!
//! 1. The run is checked ([`SolverRun::check`]) and certified at its own solution with Ipopt's
//!    multipliers ([`certify_run`], [`crate::certificate::certify`]); `strict_minimum` ends here
//!    (the common case: no extra solve).
//! 2. Otherwise (a weak or no certificate, a reduced-space run without multipliers) it is
//!    re-solved tightly from itself ([`super::polish::polish`], cold from its design, at most 200
//!    iterations above 600 free variables: `tight::tight_resolve`) and certified there. The same
//!    optimum (`J` within 1e-6 relative, or lower by at most 1e-4 with `θ0` within 1e-4 rad:
//!    [`same_optimum`]) keeps the run's numbers with the polished point's certificate. A
//!    re-solve that descends further shows the run's point was not a minimum: the polished run is
//!    taken (carried to the case's tolerance where it stopped at Ipopt's acceptable level:
//!    `tight::at_case_tolerance`) and certified in turn.
//! 3. A point with negative curvature is left along it ([`super::escape`]): the design is stepped
//!    by [`super::escape::ESCAPE_STEPS`] along `±d` and eq. (33) solved again from each; the
//!    lowest clean end below the point is taken and certified in turn.
//! 4. A weak minimum (zero curvature along `d`, within tolerance) is probed the same way along
//!    its flat direction: second order cannot tell a flat valley from a saddle whose descent is of
//!    higher order or hidden in round-off (fig8's first point: curvature −2e-7 against a scale of
//!    2e4, and a descent to a vertex 1.8e-3 lower that the tight re-solve finds or misses by
//!    rounding). An end lower by more than [`FLAT_MARGIN`] is taken; otherwise the weak minimum
//!    is reported.
//!
//! At most [`MAX_ESCAPES`] points are left; every one is listed in the result
//! ([`DesignResult::escapes`]). A result still `not_a_minimum` after that carries the warning
//! [`DesignWarning::NotAMinimum`] and is not clean.

use super::escape::{leave, restart};
use super::ipopt::DesignError;
use super::tight::{at_case_tolerance, tight_resolve, FLAT_MARGIN};
use crate::certificate::{certify, Certificate, CertifiedPoint, MinimumStatus, NegativeCurvature};
use crate::problem::DesignProblem;
use crate::result::{DesignResult, Escape, EscapeHow};
use crate::settings::SolverSettings;
use crate::solver_report::PathCost;
use crate::solver_run::SolverRun;
use crate::warnings::DesignWarning;

/// At most this many points are left on the way to a certified minimum.
pub const MAX_ESCAPES: usize = 3;

/// Whether `polished` is the optimum `first` re-solved: `J` within 1e-6 relative (the first
/// solve's tolerance moves it by about 1e-7 on design5), or lower by at most 1e-4 relative with
/// the same shape (`θ0` within 1e-4 rad, as the multi-start groups optima): the first solve
/// stopped in a flat valley of `K` and the re-solve went on down it (Fig. 5 at −1 N: 6e-6).
pub fn same_optimum(first: &DesignResult, polished: &DesignResult) -> bool {
    let moved = (polished.objective - first.objective).abs() / first.objective.abs().max(1e-12);
    let shape_moved =
        polished.design.theta0.iter().zip(&first.design.theta0).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    moved <= 1e-6 || (polished.objective < first.objective && moved <= 1e-4 && shape_moved <= 1e-4)
}

/// The certificate of a run at its own solution (`None` without multipliers or states).
pub fn certify_run(
    problem: &DesignProblem,
    run: &SolverRun,
    point: CertifiedPoint,
) -> Option<(Certificate, Option<NegativeCurvature>)> {
    let multipliers = run.multipliers.as_ref()?;
    let (layout, x) = run.point(problem)?;
    (multipliers.constraints.len() == layout.num_constraints() && multipliers.z_lower.len() == x.len())
        .then(|| certify(problem, layout, &x, multipliers, point))
}

/// The reported optimum of `run`: checked ([`SolverRun::check`]), certified, and left for a lower
/// minimum where it is not one (module docs).
pub(crate) fn settle(
    problem: &DesignProblem,
    run: SolverRun,
    settings: &SolverSettings,
) -> Result<DesignResult, DesignError> {
    let mut escapes: Vec<Escape> = Vec::new();
    // How the first solve started and its levels stay the result's: the escapes say what followed.
    let (first_notes, first_refinement) = (run.start_notes.clone(), run.refinement.clone());
    let mut current = run;
    let mut tight_before: Option<(SolverRun, DesignResult)> = None;
    // What the runs on the path before `current` cost (the result counts them all).
    let mut before = PathCost::default();
    loop {
        let result = current.clone().check(problem, settings);
        let finish = |mut result: DesignResult, certificate: Option<Certificate>, escapes: Vec<Escape>| {
            before.add_to(&mut result.solver);
            if !escapes.is_empty() {
                result.start_notes = first_notes.clone();
                result.refinement = first_refinement.clone();
            }
            if let Some(c) = certificate.as_ref().filter(|c| c.status == MinimumStatus::NotAMinimum) {
                result.warnings.push(DesignWarning::NotAMinimum { curvature: c.smallest_curvature });
            }
            result.certificate = certificate;
            result.escapes = escapes;
            result
        };
        if !result.solver.converged || result.passive.is_none() {
            return Ok(finish(result, None, escapes));
        }
        let own = certify_run(problem, &current, CertifiedPoint::Run);
        if own.as_ref().is_some_and(|(c, _)| c.status == MinimumStatus::StrictMinimum) || escapes.len() >= MAX_ESCAPES {
            return Ok(finish(result, own.map(|(c, _)| c), escapes));
        }
        // After a tight re-solve's escape `current` is that re-solve (carried to the case's
        // tolerance): its tight point is known and is not solved for again (unless the carrying
        // moved off it).
        // Whether `current` already counts the re-solve's iterations (it is that re-solve, carried).
        let (polished_run, polished, polish_counted) =
            match tight_before.take().filter(|(_, known)| same_optimum(&result, known)) {
                Some((run, checked)) => (run, checked, true),
                None => {
                    let run = tight_resolve(problem, &current, own.as_ref().map(|(c, _)| c), settings)?;
                    let checked = run.clone().check(problem, settings);
                    (run, checked, false)
                }
            };
        // What the runs up to the re-solve's point cost: the run's, and the re-solve's unless
        // `current` already counts it.
        let mut to_polished = PathCost::of(&current.solver);
        if !polish_counted {
            to_polished.add(&polished_run.solver);
        }
        let tight =
            polished.is_clean().then(|| certify_run(problem, &polished_run, CertifiedPoint::Polished)).flatten();
        // The point to leave (not a minimum): its certificate, its direction of negative curvature
        // (if formed), its run, its checked result, and what the runs that ended at it cost (the
        // run's, then the re-solve's).
        let (certificate, negative, from, from_result, to_from) = match tight {
            Some((c, negative)) if c.status == MinimumStatus::NotAMinimum => {
                (c, negative, polished_run, polished, to_polished)
            }
            Some((c, flat)) if same_optimum(&result, &polished) => {
                // A weak minimum: probed along its flat direction for a lower one.
                let lower = match flat.filter(|_| c.status == MinimumStatus::WeakMinimum) {
                    Some(d) => leave(problem, &polished_run, &d, (polished.objective, FLAT_MARGIN), settings)?,
                    None => None,
                };
                let Some((next, reached)) = lower else { return Ok(finish(result, Some(c), escapes)) };
                escapes.push(Escape {
                    objective: result.objective,
                    status: Some(c.status),
                    how: EscapeHow::FlatDirection,
                    curvature: c.smallest_curvature,
                    reached: reached.objective,
                    iterations: next.solver.iterations,
                });
                // The probe started from the re-solve's point: both runs are on the path.
                before.add_cost(to_polished);
                current = next;
                continue;
            }
            Some(_) if polished.objective < result.objective => {
                let carried = at_case_tolerance(problem, polished_run.clone(), polished.objective, settings)?;
                escapes.push(Escape {
                    objective: result.objective,
                    status: own.map(|(c, _)| c.status),
                    how: EscapeHow::TightResolve,
                    curvature: None,
                    reached: polished.objective,
                    iterations: carried.solver.iterations,
                });
                before.add(&current.solver);
                current = carried;
                tight_before = Some((polished_run, polished));
                continue;
            }
            // The tight re-solve failed or rose: the run's own certificate stands.
            _ => match own {
                Some((c, negative)) if c.status == MinimumStatus::NotAMinimum => {
                    (c, negative, current.clone(), result, PathCost::of(&current.solver))
                }
                own => return Ok(finish(result, own.map(|(c, _)| c), escapes)),
            },
        };
        let left = from_result.objective;
        let next = match &negative {
            Some(d) => leave(problem, &from, d, (left, 1e-9), settings)?.map(|n| (n, EscapeHow::NegativeCurvature)),
            None => restart(problem, &from, left, settings)?.map(|n| (n, EscapeHow::Restart)),
        };
        match next {
            Some(((next, reached), how_left)) => {
                escapes.push(Escape {
                    objective: left,
                    status: Some(certificate.status),
                    how: how_left,
                    curvature: negative.as_ref().map(|d| d.curvature),
                    reached: reached.objective,
                    iterations: next.solver.iterations,
                });
                before.add_cost(to_from);
                current = next;
            }
            _ => {
                // No lower minimum found along the direction: report the point with its certificate,
                // which is of the reported run's own solution.
                let c = Certificate { point: CertifiedPoint::Run, ..certificate };
                let mut from_result = from_result;
                to_from.put_in(&mut from_result.solver);
                return Ok(finish(from_result, Some(c), escapes));
            }
        }
    }
}
