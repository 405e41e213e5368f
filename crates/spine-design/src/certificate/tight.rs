//! The tight re-solve of a run whose certificate is not strict (step 2 of [`super::settle`]'s
//! module docs), and the carrying of one that stopped at Ipopt's acceptable level to the case's
//! tolerance.

use super::{Certificate, MAX_DENSE_FREE};
use crate::sensitivity::{polish, tight_settings};
use crate::settings::{warm_point_options, ExtraOption};
use crate::solve::{resolve_from, DesignError, FullPoint, SolverRun};
use crate::{DesignProblem, SolverSettings};

/// A probe along a weak minimum's flat direction counts only an end lower than this, relative
/// (the tolerance of [`super::same_optimum`]: a flat valley's re-solves differ by less).
pub const FLAT_MARGIN: f64 = 1e-6;

/// The most iterations of a warm tight re-solve ([`tight_resolve`]). One that has not converged
/// by then is not clean, and the run's own certificate (a weak minimum) is reported: at
/// N = 5 000 … 10⁴ such a re-solve creeps along a flat valley for 700 to more than 3 000
/// iterations (80 ms each at N = 10⁴) to a `J` lower by 1e-5 to 2e-5 relative.
pub const TIGHT_RESOLVE_ITERATIONS: usize = 200;

/// The tight re-solve of `run` (step 2 of [`super::settle`]'s module docs) with [`polish`]'s settings. Where the
/// run's own certificate has more than [`MAX_DENSE_FREE`] free variables (so that no direction is
/// formed and a flat probe cannot follow), it starts from the run's whole point and multipliers
/// (`warm_start_init_point`, `mu_init` 1e-11, warm pushes 1e-12) and goes on from where the run
/// stopped (at most [`TIGHT_RESOLVE_ITERATIONS`]): the cold polish finds every multiplier again,
/// which at N = 1000 cost about 1 s of the 3 s of the whole solve. Otherwise from the design
/// alone ([`polish`]): smaller problems keep the cold polish's own path, which is what finds
/// fig8's lower vertex (docs/design.md, "Second-order certificate").
pub(super) fn tight_resolve(
    problem: &DesignProblem,
    run: &SolverRun,
    own: Option<&Certificate>,
    settings: &SolverSettings,
) -> Result<SolverRun, DesignError> {
    if own.is_some_and(|c| c.free_variables > MAX_DENSE_FREE) {
        let mut capped = tight_settings(settings);
        capped.max_iterations = TIGHT_RESOLVE_ITERATIONS.min(settings.max_iterations);
        // Converged or not: a cold polish of a problem this size would creep along the same
        // valley for longer (N = 10⁴: 1 400–1 700 iterations either way).
        if let Some(resolved) = from_whole_point(problem, run, capped) {
            return resolved;
        }
    }
    polish(problem, &run.design, settings)
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
/// barrier pushing the 274 weak bounds off).
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
    Ok(if kept { next } else { polished })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::certificate::{certify_run, CertifiedPoint};
    use crate::fixtures::{arch_start, scaled_family};
    use crate::solve::run_solver;
    use crate::Formulation;

    /// Above [`MAX_DENSE_FREE`] free variables the tight re-solve goes on from the run's point and
    /// multipliers, within its budget, to the cold polish's `J`; below, it is the cold polish.
    #[test]
    fn a_large_weak_minimum_is_re_solved_warm_within_the_budget() {
        let n = 300;
        let problem = scaled_family(n);
        let s = n as f64 / 10.0;
        let settings = SolverSettings::default();
        let run = run_solver(&problem, &arch_start(n, 0.3, 1e3 * s * s), Formulation::Full, &settings, &mut |_| true)
            .expect("solves");
        let (own, _) = certify_run(&problem, &run, CertifiedPoint::Run).expect("a certificate");
        assert!(own.free_variables > MAX_DENSE_FREE, "{} free variables", own.free_variables);
        let warm = tight_resolve(&problem, &run, Some(&own), &settings).expect("runs");
        let cold = polish(&problem, &run.design, &settings).expect("runs");
        assert!(warm.solver.iterations <= TIGHT_RESOLVE_ITERATIONS, "{}", warm.solver.iterations);
        // Warm from the run's point, capped (the cold polish's iteration count is no yardstick at
        // this size: Ipopt 3.14 took 18 warm against 13 cold, 3.11 fewer warm).
        let option = |r: &SolverRun, name: &str| r.solver.ipopt_options.get(name).cloned();
        assert_eq!(option(&warm, "warm_start_init_point").as_deref(), Some("yes"));
        assert_eq!(option(&warm, "max_iter"), Some(TIGHT_RESOLVE_ITERATIONS.to_string()));
        assert_eq!(option(&cold, "warm_start_init_point"), None);
        let j = |r: &SolverRun| r.clone().check(&problem, &settings).objective;
        assert!(j(&warm) <= j(&run) * (1.0 + FLAT_MARGIN), "{} against the run's {}", j(&warm), j(&run));
        assert!((j(&warm) - j(&cold)).abs() <= 1e-5 * j(&cold), "{} against the cold polish's {}", j(&warm), j(&cold));
        // Small problems keep the cold polish.
        let few = Certificate { free_variables: MAX_DENSE_FREE, ..own };
        let again = tight_resolve(&problem, &run, Some(&few), &settings).expect("runs");
        assert_eq!(again.solver.iterations, cold.solver.iterations);
        assert_eq!(option(&again, "warm_start_init_point"), None);
    }

    #[test]
    fn a_polish_stopped_at_the_acceptable_level_is_carried_to_the_case_tolerance() {
        let problem = scaled_family(10);
        let settings = SolverSettings::default();
        let run = run_solver(&problem, &arch_start(10, 0.3, 1e3), Formulation::Full, &settings, &mut |_| true)
            .expect("solves");
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
