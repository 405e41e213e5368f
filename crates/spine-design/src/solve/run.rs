//! Stages 1 and 2 of a design run ([`crate::solve`]) put together: eq. (33) with Ipopt from a start
//! in either formulation, in the full space through the refinement ladder ([`super::ladder`])
//! where it applies, and the full space solved again from a whole point (the sweeps' corrector).
//! What comes back is the unchecked [`SolverRun`], the same in a worker process as here.

use super::ipopt::{ipopt_solve, ipopt_solve_full, DesignError};
use super::ladder::solve_refined;
use crate::full_space::{FullSpaceNlp, Multipliers};
use crate::layout::{Layout, LoadState, StateForm};
use crate::problem::{start_states, DesignProblem};
use crate::reduced_space::ReducedSpaceNlp;
use crate::refine;
use crate::settings::{Formulation, SolverSettings};
use crate::solver_report::{RefinementReport, SolverReport};
use crate::solver_run::SolverRun;
use crate::variables::SpringVariables;
use spine_ipopt::{IterationInfo, OptionValue, Solution};
use spine_model::{Design, State};
use std::time::Instant;

/// Eq. (33) with Ipopt from `start` (projected into the bounds first) in the given formulation; in
/// the full space through the refinement ladder of `settings.refine` where it applies. `observer`
/// sees every Ipopt iteration (of every level) and may stop the run by returning `false`. The run
/// is neither checked nor certified ([`super::Solver::run`]).
pub(crate) fn run_solver(
    problem: &DesignProblem,
    start: &Design,
    formulation: Formulation,
    settings: &SolverSettings,
    observer: &mut dyn FnMut(&IterationInfo) -> bool,
) -> Result<SolverRun, DesignError> {
    let clock = Instant::now();
    let (start, mut notes) = problem.project_start(start);
    let options = settings.ipopt();
    let mut refinement = None;
    let mut start_seconds = 0.0;
    // The full space's form at the problem's own size (a ladder resolves each level's).
    let state_form = settings.state_variables.resolve(problem, settings.smaller_tolerance());
    let (solution, design, states, equilibrium_evaluations) = match formulation {
        Formulation::Full => {
            let ladder = settings.refine.ladder(problem.n_links());
            let (solution, design, states) = match ladder {
                Some(ladder) => {
                    let (solution, design, states, report) =
                        solve_refined(problem, &start, settings, ladder, observer, &mut notes)?;
                    refinement = Some(report);
                    (solution, design, states)
                }
                None => {
                    let (passive, loaded) = start_states(problem, &start, &settings.continuation, &mut notes);
                    start_seconds = clock.elapsed().as_secs_f64();
                    let mut nlp = FullSpaceNlp::new(problem, state_form, &start, &passive, &loaded);
                    nlp.on_iteration = Some(observer);
                    let solution = ipopt_solve_full(&mut nlp, &options, settings.spring_variables.resolve(problem))?;
                    let (design, states) = refine::solution_parts(&nlp, &solution.x);
                    (solution, design, states)
                }
            };
            (solution, design, Some(states), 0)
        }
        Formulation::Reduced => {
            let mut nlp =
                ReducedSpaceNlp::new(problem, &start, settings.continuation.clone(), settings.reduced_hessian);
            nlp.on_iteration = Some(observer);
            let solution = ipopt_solve(&mut nlp, &options)?;
            let design = nlp.design(&solution.x);
            let states = nlp.evaluate(&solution.x).map(|e| (e.passive.clone(), e.loaded.clone()));
            (solution, design, states, nlp.equilibrium_evaluations)
        }
    };
    let layout = Layout::of(problem, state_form);
    let springs = (formulation == Formulation::Full).then(|| settings.spring_variables.resolve(problem));
    let run = Finished { formulation, layout, springs, start_seconds, equilibrium_evaluations, clock };
    Ok(run.into_run(&solution, &options, design, states, notes, refinement))
}

/// What [`run_solver`] and [`resolve_from`] know when Ipopt returns.
struct Finished {
    formulation: Formulation,
    /// The full space's layout at the problem's own size (its state form; whether it holds `θ3`).
    layout: Layout,
    /// Full space: how Ipopt saw the springs (resolved).
    springs: Option<SpringVariables>,
    start_seconds: f64,
    equilibrium_evaluations: usize,
    clock: Instant,
}

impl Finished {
    fn into_run(
        self,
        solution: &Solution,
        options: &spine_ipopt::Options,
        design: Design,
        states: Option<(State, State)>,
        start_notes: Vec<String>,
        refinement: Option<RefinementReport>,
    ) -> SolverRun {
        let full = self.formulation == Formulation::Full;
        let probe = (full && self.layout.probe).then(|| self.layout.state(&solution.x, LoadState::Probe));
        let multipliers = full.then(|| Multipliers {
            constraints: solution.lambda.clone(),
            z_lower: solution.z_lower.clone(),
            z_upper: solution.z_upper.clone(),
        });
        let mut report = SolverReport::from_ipopt(solution, self.equilibrium_evaluations);
        report.state_variables = full.then_some(self.layout.states);
        report.spring_variables = self.springs;
        report.start_seconds = self.start_seconds;
        report.ipopt_options = options
            .iter()
            .map(|(k, v)| (k.to_string(), if let OptionValue::Str(text) = v { text.clone() } else { v.to_string() }))
            .collect();
        report.total_seconds = self.clock.elapsed().as_secs_f64();
        SolverRun {
            formulation: self.formulation,
            design,
            states,
            probe,
            solver: report,
            start_notes,
            refinement,
            multipliers,
        }
    }
}

/// A point of the full space: a design, both states in absolute angles, and (optionally)
/// Ipopt's multipliers in the layout of `form`.
pub(crate) struct FullPoint<'a> {
    pub form: StateForm,
    pub design: &'a Design,
    pub states: &'a (State, State),
    pub multipliers: Option<&'a Multipliers>,
    /// How Ipopt sees the springs (`solver.spring_variables`).
    pub springs: SpringVariables,
}

/// Eq. (33) in the full space from a whole point (no start equilibria are computed, no mesh
/// sequencing), with `options`; with multipliers Ipopt starts from them
/// (`warm_start_init_point`, which `options` must ask for). The corrector of a followed sweep
/// ([`crate::sweep`]).
pub(crate) fn resolve_from(
    problem: &DesignProblem,
    start: FullPoint<'_>,
    options: &spine_ipopt::Options,
) -> Result<SolverRun, DesignError> {
    let clock = Instant::now();
    let (design, notes) = problem.project_start(start.design);
    let mut nlp = FullSpaceNlp::new(problem, start.form, &design, &start.states.0, &start.states.1);
    nlp.multipliers = start.multipliers.cloned();
    let solution = ipopt_solve_full(&mut nlp, options, start.springs)?;
    let (design, states) = refine::solution_parts(&nlp, &solution.x);
    let run = Finished {
        formulation: Formulation::Full,
        layout: Layout::of(problem, start.form),
        springs: Some(start.springs),
        start_seconds: 0.0,
        equilibrium_evaluations: 0,
        clock,
    };
    Ok(run.into_run(&solution, options, design, Some(states), notes, None))
}
