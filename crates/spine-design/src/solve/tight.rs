//! Stage 4 of a design run ([`crate::solve`]): the tight re-solve of a run whose certificate is not
//! strict (step 2 of [`super::settle`]'s module docs), and the carrying of one that stopped at
//! Ipopt's acceptable level to the case's tolerance.

use super::ipopt::DesignError;
use super::polish::polish;
use super::run::{resolve_from, FullPoint};
use crate::certificate::{Certificate, MAX_DENSE_FREE};
use crate::problem::DesignProblem;
use crate::settings::{warm_point_options, ExtraOption, SolverSettings};
use crate::solver_report::PathCost;
use crate::solver_run::SolverRun;

/// A probe along a weak minimum's flat direction counts only an end lower than this, relative
/// (the tolerance of [`super::settle::same_optimum`]: a flat valley's re-solves differ by less).
pub const FLAT_MARGIN: f64 = 1e-6;

/// The most iterations of the tight re-solve (`tight_resolve`) of a problem above
/// [`MAX_DENSE_FREE`] free variables. One that has not converged by then is not clean, and the
/// run's own certificate (a weak minimum) is reported: with the springs as Ipopt's `k` such a
/// re-solve crept along a flat valley for 700 to more than 3 000 iterations at N = 5 000 … 10⁴
/// (80 ms each at N = 10⁴) to a `J` lower by 1e-5 to 2e-5 relative.
pub const TIGHT_RESOLVE_ITERATIONS: usize = 200;

/// The tight re-solve of `run` (step 2 of [`super::settle`]'s module docs): [`polish`], cold from
/// the design alone, at most [`TIGHT_RESOLVE_ITERATIONS`] iterations where the run's own
/// certificate has more than [`MAX_DENSE_FREE`] free variables. Cold, not from the run's point and
/// multipliers: a warm re-solve stays in the run's flat valley, and the cold one leaves it for
/// lower points (fig8's lower vertex; the continuum study's bang-bang optima, which a warm
/// re-solve, tried on 2026-11-29, left 1e-6 to 1e-5 higher with ramps of springs between their
/// bounds; docs/continuum.md).
pub(super) fn tight_resolve(
    problem: &DesignProblem,
    run: &SolverRun,
    own: Option<&Certificate>,
    settings: &SolverSettings,
) -> Result<SolverRun, DesignError> {
    let mut settings = settings.clone();
    if own.is_some_and(|c| c.free_variables > MAX_DENSE_FREE) {
        settings.max_iterations = TIGHT_RESOLVE_ITERATIONS.min(settings.max_iterations);
    }
    polish(problem, &run.design, &settings)
}

/// Eq. (33) solved again from `run`'s whole point and multipliers (`warm_start_init_point`,
/// `mu_init` 1e-11, every warm push 1e-12) with `settings`; `None` where the run has no states or
/// multipliers.
fn from_whole_point(
    problem: &DesignProblem,
    run: &SolverRun,
    mut settings: SolverSettings,
) -> Option<Result<SolverRun, DesignError>> {
    let (states, multipliers) = (run.states.as_ref()?, run.multipliers.as_ref()?);
    settings.ipopt_options.insert("warm_start_init_point".into(), ExtraOption::Str("yes".into()));
    for (name, value) in warm_point_options(1e-11, 1e-12) {
        settings.ipopt_options.insert(name.into(), ExtraOption::Num(value));
    }
    let form = run.solver.layout(problem).states;
    let point = FullPoint {
        form,
        design: &run.design,
        states,
        multipliers: Some(multipliers),
        springs: settings.spring_variables.resolve(problem),
    };
    Some(resolve_from(problem, point, &settings.ipopt()))
}

/// A tight re-solve that descended but stopped short of its own tolerance (Ipopt's acceptable
/// level: the refined N = 1000 peers case, 3 278 free variables and 274 weakly active bounds) is
/// carried to the case's tolerance from its point and multipliers, warm (`mu_init` 1e-11 and the
/// warm pushes 1e-12, the polish's own), so that the reported run's status is the case's
/// convergence. It is kept only if it succeeds, is clean and ends within [`FLAT_MARGIN`] of the polished
/// `J` (the same optimum); otherwise the polished run stands. Measured at N = 1000: 2 iterations,
/// `J` 4.9e-8 above the polished one (with `mu_init` 1e-9: 6 iterations and 4.5e-6 above, the
/// barrier pushing the 274 weak bounds off). A carried run's iterations and Ipopt times count the polish's.
pub(super) fn at_case_tolerance(
    problem: &DesignProblem,
    polished: SolverRun,
    polished_objective: f64,
    settings: &SolverSettings,
) -> Result<SolverRun, DesignError> {
    if polished.solver.status.is_optimal() {
        return Ok(polished);
    }
    let Some(next) = from_whole_point(problem, &polished, settings.clone()) else { return Ok(polished) };
    let next = next?;
    let after = next.clone().check(problem, settings);
    let kept = next.solver.status.is_optimal()
        && after.is_clean()
        && after.objective <= polished_objective * (1.0 + FLAT_MARGIN);
    Ok(if kept {
        let mut next = next;
        PathCost::of(&polished.solver).add_to(&mut next.solver);
        next
    } else {
        polished
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certificate::{solved_scaled_family, CertifiedPoint};
    use crate::solve::settle::certify_run;

    /// Above [`MAX_DENSE_FREE`] free variables the tight re-solve is the cold polish capped at
    /// [`TIGHT_RESOLVE_ITERATIONS`] (the same run when it converges within the cap); below, the
    /// cold polish without a cap.
    #[test]
    fn a_large_weak_minimum_is_polished_cold_within_the_budget() {
        let (problem, run) = solved_scaled_family(300);
        let settings = SolverSettings::default();
        let (own, _) = certify_run(&problem, &run, CertifiedPoint::Run).expect("a certificate");
        assert!(own.free_variables > MAX_DENSE_FREE, "{} free variables", own.free_variables);
        let capped = tight_resolve(&problem, &run, Some(&own), &settings).expect("runs");
        let option = |r: &SolverRun, name: &str| r.solver.ipopt_options.get(name).cloned();
        // Cold from the design (no multipliers carried), capped.
        assert_eq!(option(&capped, "warm_start_init_point"), None);
        assert_eq!(option(&capped, "max_iter"), Some(TIGHT_RESOLVE_ITERATIONS.to_string()));
        assert!(capped.solver.iterations <= TIGHT_RESOLVE_ITERATIONS, "{}", capped.solver.iterations);
        // Within the budget it is the uncapped polish itself.
        let cold = polish(&problem, &run.design, &settings).expect("runs");
        assert!(cold.solver.iterations < TIGHT_RESOLVE_ITERATIONS, "{}", cold.solver.iterations);
        assert_eq!(capped.solver.iterations, cold.solver.iterations);
        assert_eq!(capped.design, cold.design);
        // Small problems are polished without a cap.
        let few = Certificate { free_variables: MAX_DENSE_FREE, ..own };
        let again = tight_resolve(&problem, &run, Some(&few), &settings).expect("runs");
        assert_eq!(option(&again, "max_iter"), Some(settings.max_iterations.to_string()));
        assert_eq!(again.design, cold.design);
    }

    #[test]
    fn a_polish_stopped_at_the_acceptable_level_is_carried_to_the_case_tolerance() {
        let (problem, run) = solved_scaled_family(10);
        let settings = SolverSettings::default();
        let polished = polish(&problem, &run.design, &settings).expect("polishes");
        assert!(polished.solver.status.is_optimal(), "{:?}", polished.solver.status);
        let j = polished.clone().check(&problem, &settings).objective;
        // A run that succeeded is returned as it is.
        let same = at_case_tolerance(&problem, polished.clone(), j, &settings).expect("runs");
        assert_eq!(same.solver.iterations, polished.solver.iterations);
        // One that Ipopt stopped at its acceptable level is solved again from its point, warm.
        let mut stopped = polished;
        stopped.solver.status = spine_ipopt::Status::SolvedToAcceptableLevel;
        let carried = at_case_tolerance(&problem, stopped, j, &settings).expect("runs");
        assert!(carried.solver.status.is_optimal(), "{:?}", carried.solver.status);
        let carried_j = carried.clone().check(&problem, &settings).objective;
        assert!((carried_j - j).abs() <= FLAT_MARGIN * j, "{carried_j} against {j}");
        assert!(carried.solver.iterations < 20, "{} iterations from the polished point", carried.solver.iterations);
    }
}
