//! From a solver's run to the optimum that is reported: certified, and never a point that is not a
//! minimum when a minimum can be reached from it.
//!
//! 1. The run is certified at its own solution with Ipopt's multipliers ([`super::certify`]);
//!    `strict_minimum` ends here (the common case: no extra solve).
//! 2. Otherwise (a weak or no certificate, a reduced-space run without multipliers) it is re-solved
//!    tightly from itself ([`polish`](crate::sensitivity::polish), cold from its design, at most 200 iterations above 600 free variables: [`tight_resolve`]) and certified there. The same optimum (`J` within 1e-6
//!    relative, or lower by at most 1e-4 with `θ0` within 1e-4 rad: [`same_optimum`]) keeps the
//!    run's numbers with the polished point's certificate. A re-solve that descends further
//!    shows the run's point was not a minimum: the polished run is taken (carried to the case's
//!    tolerance where it stopped at Ipopt's acceptable level: [`at_case_tolerance`]) and
//!    certified in turn.
//! 3. A point with negative curvature is left along it: the design is stepped by
//!    [`ESCAPE_STEPS`] along `±d` and eq. (33) solved again from each; the lowest clean end below
//!    the point is taken and certified in turn.
//! 4. A weak minimum (zero curvature along `d`, within tolerance) is probed the same way along
//!    its flat direction: second order cannot tell a flat valley from a saddle whose descent is of
//!    higher order or hidden in round-off (fig8's first point: curvature −2e-7 against a scale of
//!    2e4, and a descent to a vertex 1.8e-3 lower that the tight re-solve finds or misses by
//!    rounding). An end lower by more than [`FLAT_MARGIN`] is taken; otherwise the weak minimum
//!    is reported.
//!
//! At most [`MAX_ESCAPES`] points are left; every one is listed in the result
//! ([`crate::DesignResult::escapes`]). A result still `not_a_minimum` after that carries the
//! warning [`crate::result::DesignWarning::NotAMinimum`] and is not clean.

use super::tight::{at_case_tolerance, tight_resolve, FLAT_MARGIN};
use super::{certify, Certificate, CertifiedPoint, MinimumStatus, NegativeCurvature};
use crate::result::DesignWarning;
use crate::solve::{resolve_from, run_solver, DesignError, FullPoint, SolverRun};
use crate::solver_report::PathCost;
use crate::{DesignProblem, DesignResult, Formulation, SolverSettings};
use serde::{Deserialize, Serialize};
use spine_ipopt::IterationInfo;
use spine_model::Design;

/// At most this many points are left on the way to a certified minimum.
pub const MAX_ESCAPES: usize = 3;

/// The steps along a direction of negative curvature, as fractions of the design box: the design
/// variable the direction moves most (relative to its bound interval) moves by this fraction of
/// its interval. The smaller is tried first; the larger where the smaller falls back.
pub const ESCAPE_STEPS: [f64; 2] = [0.02, 0.1];

/// How a point that was not a minimum was left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EscapeHow {
    /// The tight re-solve from it descended to a lower `J` elsewhere.
    TightResolve,
    /// A step along its direction of negative curvature, then eq. (33) again.
    NegativeCurvature,
    /// A weak minimum: a step along its direction of zero curvature, then eq. (33) again, ended
    /// lower.
    FlatDirection,
    /// Eq. (33) again from its design with the run's own settings (where the inertia shows
    /// negative curvature but no direction was formed: above [`super::MAX_DENSE_FREE`] free
    /// variables or [`crate::sensitivity::MAX_WEAK`] weakly active bounds).
    Restart,
}

impl EscapeHow {
    /// The name written in results (`tight_resolve`, `negative_curvature`).
    pub fn name(self) -> &'static str {
        match self {
            Self::TightResolve => "tight_resolve",
            Self::NegativeCurvature => "negative_curvature",
            Self::FlatDirection => "flat_direction",
            Self::Restart => "restart",
        }
    }
}

/// A point left on the way to the reported optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Escape {
    /// `J` at the point left, J.
    pub objective: f64,
    /// Its certificate where one was computed (a run without multipliers has none).
    pub status: Option<MinimumStatus>,
    pub how: EscapeHow,
    /// The negative curvature it was left along (for [`EscapeHow::NegativeCurvature`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curvature: Option<f64>,
    /// `J` where the next solve ended, J.
    pub reached: f64,
    /// Ipopt iterations of the solve that reached `reached` from the point left (after a tight
    /// re-solve, with its carrying to the case's tolerance); the attempts that ended higher are not
    /// counted.
    #[serde(default)]
    pub iterations: usize,
}

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

/// Eq. (33) from `run`'s design stepped along `±d` (design variables only, [`ESCAPE_STEPS`]; the
/// states are found again): the lowest clean end below `below` by more than `margin` relative
/// (`None` when no step reaches one).
fn leave(
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
fn restart(
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

/// Solves eq. (33) from `start` (projected into the bounds first) in the given formulation; in the
/// full space through the mesh-sequencing ladder of `settings.refine` when it applies.
/// `observer` sees every Ipopt iteration (of every level) and may stop the run by returning `false`.
/// The same as [`run_solver`] then [`crate::certificate::settle`]: the result is checked, carries
/// its second-order certificate, and is never a point that is not a minimum where a lower one can
/// be reached from it.
pub fn solve_design(
    problem: &DesignProblem,
    start: &Design,
    formulation: Formulation,
    settings: &SolverSettings,
    observer: &mut dyn FnMut(&IterationInfo) -> bool,
) -> Result<DesignResult, DesignError> {
    settle(problem, run_solver(problem, start, formulation, settings, observer)?, settings)
}

/// The reported optimum of `run`: checked ([`SolverRun::check`]), certified, and left for a lower
/// minimum where it is not one (module docs).
pub fn settle(problem: &DesignProblem, run: SolverRun, settings: &SolverSettings) -> Result<DesignResult, DesignError> {
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
