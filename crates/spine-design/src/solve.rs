//! Runs eq. (33) with Ipopt in either formulation and checks what comes back.

use crate::full_space::FullSpaceNlp;
use crate::full_space::Multipliers;
use crate::problem::start_states;
use crate::problem::DesignProblem;
use crate::reduced_space::ReducedSpaceNlp;
use crate::refine::{self, LevelStart, MAX_RESTARTS};
use crate::result::{LevelReport, RefinementReport, SolverReport};
use crate::settings::{Formulation, SolverSettings, SpringVariables};
pub use crate::solver_run::SolverRun;
use spine_ipopt::{IterationInfo, OptionValue, SetupError, Solution};
use spine_model::{Design, State};
use std::time::Instant;

/// Why a design run could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DesignError {
    /// Ipopt rejected the problem or its options before iterating.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The workspace's linear solver could not be installed as Ipopt's Pardiso library.
    #[error("the linear solver could not be loaded: {0}")]
    LinearSolver(#[source] spine_kkt::KktError),
}

/// Ipopt on `nlp` with `options`, the linear solver they name made ready first: where they name
/// Pardiso, the workspace's own `LDLᵀ` is installed as Ipopt's Pardiso library
/// ([`crate::settings::LinearSolver::ready`]). Every eq. (33) solve goes through here.
pub fn ipopt_solve(
    nlp: &mut dyn spine_ipopt::Problem,
    options: &spine_ipopt::Options,
) -> Result<Solution, DesignError> {
    if options.get("linear_solver") == Some(&OptionValue::Str(spine_ipopt::LinearSolver::Pardiso.name().into())) {
        crate::settings::LinearSolver::Spine.ready().map_err(DesignError::LinearSolver)?;
    }
    Ok(spine_ipopt::solve(nlp, options)?)
}

/// [`ipopt_solve`] on the full space, the springs `k` handed to Ipopt by their logarithm
/// ([`crate::log_variables`]) when `springs` resolves to [`SpringVariables::Log`] for the NLP's
/// problem; the solution in `k` either way.
pub fn ipopt_solve_full(
    nlp: &mut FullSpaceNlp<'_>,
    options: &spine_ipopt::Options,
    springs: SpringVariables,
) -> Result<Solution, DesignError> {
    if springs.resolve(nlp.problem) != SpringVariables::Log {
        return ipopt_solve(nlp, options);
    }
    let logged: Vec<usize> = (0..=nlp.layout.n).map(|j| nlp.layout.stiffness(j)).collect();
    let mut wrapped = crate::log_variables::LogVariables::new(nlp, &logged);
    let options = crate::log_variables::relaxed_in_logs(&wrapped, options);
    let solution = ipopt_solve(&mut wrapped, &options)?;
    Ok(wrapped.solution_back(solution))
}

/// Eq. (33) with Ipopt from `start`, as [`crate::solve_design`], without the final check and certificate.
pub fn run_solver(
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
    let layout = crate::full_space::Layout::of(problem, state_form);
    let springs = (formulation == Formulation::Full).then(|| settings.spring_variables.resolve(problem));
    let run = Finished { formulation, layout, springs, start_seconds, equilibrium_evaluations, clock };
    Ok(run.into_run(&solution, &options, design, states, notes, refinement))
}

/// What [`run_solver`] and [`resolve_from`] know when Ipopt returns.
struct Finished {
    formulation: Formulation,
    /// The full space's layout at the problem's own size (its state form; whether it holds `θ3`).
    layout: crate::full_space::Layout,
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
        let probe =
            (full && self.layout.probe).then(|| self.layout.state(&solution.x, crate::full_space::LoadState::Probe));
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
pub struct FullPoint<'a> {
    pub form: crate::full_space::StateForm,
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
pub fn resolve_from(
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
        layout: crate::full_space::Layout::of(problem, start.form),
        springs: Some(start.springs),
        start_seconds: 0.0,
        equilibrium_evaluations: 0,
        clock,
    };
    Ok(run.into_run(&solution, options, design, Some(states), notes, None))
}

/// Stops a level's Ipopt run after `after` iterations so that it can be restarted
/// ([`refine::WarmStart::restart_after`]); every iteration first goes to the caller's observer,
/// whose stop is final.
struct RestartBudget {
    after: usize,
    reached: bool,
}

impl RestartBudget {
    fn watch(&mut self, info: &IterationInfo, observer: &mut dyn FnMut(&IterationInfo) -> bool) -> bool {
        if !observer(info) {
            return false;
        }
        if info.iteration >= self.after && !info.restoration {
            self.reached = true;
            return false;
        }
        true
    }
}

/// One Ipopt run of a ladder level from a design and its states.
struct LevelRun<'a> {
    level: &'a DesignProblem,
    form: crate::full_space::StateForm,
    springs: SpringVariables,
    design: &'a Design,
    states: &'a (State, State),
}

impl LevelRun<'_> {
    /// Solves with `options`, every iteration watched by `budget` and the caller's `observer`,
    /// Ipopt started from the multipliers `multipliers` gives for the NLP (if any). Returns the
    /// solution with its design and states.
    fn solve(
        &self,
        options: &spine_ipopt::Options,
        budget: &mut RestartBudget,
        observer: &mut dyn FnMut(&IterationInfo) -> bool,
        multipliers: impl FnOnce(&FullSpaceNlp<'_>) -> Option<Multipliers>,
    ) -> Result<(Solution, Design, (State, State)), DesignError> {
        let mut watched = |info: &IterationInfo| budget.watch(info, &mut *observer);
        let mut nlp = FullSpaceNlp::new(self.level, self.form, self.design, &self.states.0, &self.states.1);
        nlp.multipliers = multipliers(&nlp);
        nlp.on_iteration = Some(&mut watched);
        let solution = ipopt_solve_full(&mut nlp, options, self.springs)?;
        let (design, states) = refine::solution_parts(&nlp, &solution.x);
        Ok((solution, design, states))
    }
}

impl LevelRun<'_> {
    /// A solve that ran past its iteration budget (`restart_after`) solved again from where it
    /// stopped, with `options` (a small initial barrier parameter), until one converges within the
    /// budget; the last of [`MAX_RESTARTS`] restarts has no budget. Returns the last solve (its
    /// iterations counting every restart's) and the number of restarts.
    fn restarted(
        &self,
        (mut solution, mut design, mut states): (Solution, Design, (State, State)),
        restart_after: Option<usize>,
        options: &spine_ipopt::Options,
        observer: &mut dyn FnMut(&IterationInfo) -> bool,
    ) -> Result<(Solution, Design, (State, State), usize), DesignError> {
        let Some(restart_after) = restart_after else { return Ok((solution, design, states, 0)) };
        let mut restarts = 0;
        let mut budget = RestartBudget { after: 0, reached: true };
        while budget.reached {
            restarts += 1;
            budget = RestartBudget {
                after: if restarts < MAX_RESTARTS { restart_after } else { usize::MAX },
                reached: false,
            };
            let from = LevelRun { design: &design, states: &states, ..*self };
            let (mut again, d, s) = from.solve(options, &mut budget, &mut *observer, |_| None)?;
            again.continues(&solution);
            (solution, design, states) = (again, d, s);
        }
        Ok((solution, design, states, restarts))
    }
}

/// Eq. (33) in the full space through the ladder of chain sizes (see [`crate::refine`]). Returns
/// the solution of the last level (the problem itself) and every level's report. A coarse level
/// that does not converge ends the ladder: the problem itself is then solved cold, and the report
/// says so.
fn solve_refined(
    problem: &DesignProblem,
    start: &Design,
    settings: &SolverSettings,
    ladder: refine::Ladder,
    observer: &mut dyn FnMut(&IterationInfo) -> bool,
    notes: &mut Vec<String>,
) -> Result<(Solution, Design, (State, State), RefinementReport), DesignError> {
    let n = problem.n_links();
    let sizes = ladder.levels(n);
    let warm = settings.warm_start;
    let mut levels: Vec<LevelReport> = Vec::new();
    let mut previous: Option<(DesignProblem, Design, (State, State), Multipliers)> = None;
    let mut fell_back = false;
    let mut next = 0;
    loop {
        let m = if fell_back { n } else { sizes[next] };
        let clock = Instant::now();
        let previous_level = previous.as_ref().map(|(p, d, s, _)| (p, d, s));
        let restore = warm.restore_end_displacement;
        let setup = refine::prepare_level(problem, m, previous_level, start, restore, &settings.continuation, notes);
        let (level, how, design, states) = (setup.problem(problem), setup.start, &setup.design, &setup.states);
        let start_seconds = clock.elapsed().as_secs_f64();
        let form = settings.state_variables.resolve(level, settings.smaller_tolerance());
        let cold = how == LevelStart::Cold;
        // The finest warm level is restarted after `restart_after` iterations (docs/design.md).
        let restart_after = if m == n && !cold && warm.restart_after > 0 { warm.restart_after } else { usize::MAX };
        let mut budget = RestartBudget { after: restart_after, reached: false };
        // The coarse levels only prepare a start: solved to the coarse tolerance, and to their
        // barrier problem when the ladder has a barrier schedule.
        let barrier = if fell_back { None } else { settings.level_barrier(ladder.from, m) };
        let options = settings.level_ipopt(m, n, cold, barrier);
        let prolonged_multipliers = |nlp: &FullSpaceNlp<'_>| {
            let (coarser, _, _, multipliers) = previous.as_ref().filter(|_| warm.multipliers)?;
            let size = nlp.layout.num_variables();
            let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; size], vec![f64::INFINITY; size]);
            spine_ipopt::Problem::variable_bounds(nlp, &mut lower, &mut upper);
            Some(refine::prolong_multipliers(coarser, level, multipliers, &nlp.start, &lower, &upper))
        };
        let start = LevelRun { level, form, springs: settings.spring_variables.resolve(problem), design, states };
        let first = start.solve(&options, &mut budget, &mut *observer, prolonged_multipliers)?;
        let restart_options = settings.level_ipopt(m, n, cold, None).number("mu_init", settings.tolerance / 10.0);
        let (solution, design, states, restarts) =
            start.restarted(first, budget.reached.then_some(restart_after), &restart_options, &mut *observer)?;
        levels.push(LevelReport {
            links: m,
            start: how,
            barrier,
            status: solution.status,
            optimal: solution.status.is_optimal(),
            iterations: solution.iterations,
            restarts,
            objective: solution.objective,
            end_displacement_restored: setup.restored,
            start_seconds,
            wall_seconds: clock.elapsed().as_secs_f64(),
        });
        if m == n {
            let report = RefinementReport { ladder, warm_start: warm, fell_back_to_cold: fell_back, levels };
            return Ok((solution, design, states, report));
        }
        if solution.status.is_converged() {
            let multipliers = Multipliers {
                constraints: solution.lambda.clone(),
                z_lower: solution.z_lower.clone(),
                z_upper: solution.z_upper.clone(),
            };
            previous = Some((level.clone(), design, states, multipliers));
            next += 1;
        } else {
            notes.push(format!(
                "refinement level {m} links ended {}: the full chain is solved cold instead",
                solution.status.name()
            ));
            fell_back = true;
            previous = None;
        }
    }
}
