//! Stage 1 of a design run ([`crate::solve`]): the refinement ladder. Eq. (33) in the full space
//! solved on coarser chains first, each level warm-starting the next ([`crate::refine`]), the
//! finest warm level restarted when it runs past its iteration budget.

use super::ipopt::{ipopt_solve_full, DesignError};
use crate::full_space::{FullSpaceNlp, Multipliers};
use crate::layout::StateForm;
use crate::problem::DesignProblem;
use crate::refine::{self, LevelStart, MAX_RESTARTS};
use crate::settings::SolverSettings;
use crate::solver_report::{LevelReport, RefinementReport};
use crate::variables::SpringVariables;
use spine_ipopt::{IterationInfo, Solution};
use spine_model::{Design, State};
use std::time::Instant;

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
    form: StateForm,
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
pub(super) fn solve_refined(
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
