//! Runs eq. (33) with Ipopt in either formulation and checks what comes back.

use crate::full_space::FullSpaceNlp;
use crate::problem::DesignProblem;
use crate::reduced_space::{ReducedHessian, ReducedSpaceNlp};
use crate::refine::{self, LevelStart, Multipliers, Refine, WarmStart};
use crate::result::{DesignResult, LevelReport, RefinementReport, SolverReport};
use serde::{Deserialize, Serialize};
use spine_ipopt::{IterationInfo, OptionValue, Options, SetupError, Solution};
use spine_model::{Design, State};
use spine_solve::{solve_static, ContinuationOptions};
use std::collections::BTreeMap;
use std::time::Instant;

/// Which form of eq. (33) Ipopt solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Formulation {
    /// Design, both equilibria and the node heights are variables; exact sparse Hessian.
    Full,
    /// Design only; equilibria by continuation, gradients by the adjoint; L-BFGS Hessian.
    Reduced,
}

impl Formulation {
    pub fn name(self) -> &'static str {
        match self {
            Formulation::Full => "full",
            Formulation::Reduced => "reduced",
        }
    }
}

/// Ipopt's `nlp_scaling_method`: how Ipopt rescales the problem before solving.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScalingMethod {
    /// Ipopt's default: objective and constraint rows scaled so that their gradients at the start
    /// point have ∞-norm at most `nlp_scaling_max_gradient` (100). It rescales functions, not
    /// variables, so it does not undo `C_K` (which rescales a variable), but it changes how the
    /// stopping tolerance weighs the rows.
    GradientBased,
    /// No scaling: the problem as written, so the effect of `C_K` is seen in its pure form.
    None,
}

/// One extra Ipopt option from a case file: a number, an integer or a string.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ExtraOption {
    Int(i64),
    Num(f64),
    Str(String),
}

/// Solver settings of a design run (case file field `solver`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// Ipopt `tol` (relative KKT error).
    pub tolerance: f64,
    /// Ipopt `constr_viol_tol` (absolute, in the constraints' units: N·m, m, rad).
    pub constraint_tolerance: f64,
    /// Ipopt `max_iter`.
    pub max_iterations: usize,
    /// Ipopt `nlp_scaling_method`.
    pub scaling: ScalingMethod,
    /// Ipopt `mu_strategy`: "monotone" or "adaptive".
    pub barrier_strategy: String,
    /// Reduced space only: second derivatives from differences of the adjoint gradients
    /// ("adjoint-differences", the default) or Ipopt's L-BFGS ("limited-memory").
    pub reduced_hessian: ReducedHessian,
    /// Continuation settings of every equilibrium solve (start states, reduced-space evaluations,
    /// the final load-path check).
    pub continuation: ContinuationOptions,
    /// Further Ipopt options passed as given (for experts; Ipopt rejects unknown names).
    pub ipopt_options: BTreeMap<String, ExtraOption>,
    /// Full space only: mesh sequencing (`"auto"`, `"off"` or `{ "from": 50, "factor": 2 }`),
    /// see [`crate::refine`].
    pub refine: Refine,
    /// Ipopt options of the warm levels of `refine`.
    pub warm_start: WarmStart,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-9,
            constraint_tolerance: 1e-9,
            max_iterations: 3000,
            scaling: ScalingMethod::GradientBased,
            barrier_strategy: "monotone".into(),
            reduced_hessian: ReducedHessian::AdjointDifferences,
            continuation: ContinuationOptions { residual_tolerance: 1e-11, ..ContinuationOptions::default() },
            ipopt_options: BTreeMap::new(),
            refine: Refine::default(),
            warm_start: WarmStart::default(),
        }
    }
}

impl SolverSettings {
    /// The Ipopt options of these settings.
    pub fn ipopt(&self) -> Options {
        let scaling = match self.scaling {
            ScalingMethod::GradientBased => "gradient-based",
            ScalingMethod::None => "none",
        };
        let mut options = Options::new()
            .number("tol", self.tolerance)
            .number("constr_viol_tol", self.constraint_tolerance)
            .integer("max_iter", self.max_iterations as i64)
            .string("nlp_scaling_method", scaling)
            .string("mu_strategy", &self.barrier_strategy)
            // Report the design Ipopt converged to, not one moved back onto the original bounds
            // afterwards (3.11's default): the equilibria of a moved design are not satisfied.
            .string("honor_original_bounds", "no")
            // A fixed fill-reducing ordering: the automatic choice of MUMPS 5.5 picks SCOTCH on
            // large systems and runs of the same input then differ.
            .integer("mumps_pivot_order", MUMPS_PIVOT_ORDER);
        for (name, value) in &self.ipopt_options {
            let value = match value {
                ExtraOption::Int(i) => OptionValue::Int(*i),
                ExtraOption::Num(x) => OptionValue::Num(*x),
                ExtraOption::Str(s) => OptionValue::Str(s.clone()),
            };
            options.set(name, value);
        }
        options
    }
}

/// MUMPS's `ICNTL(7)` ordering used by every design solve: 5 (METIS), the fastest of the
/// orderings measured on eq. (33) (docs/design.md) and deterministic.
pub const MUMPS_PIVOT_ORDER: i64 = 5;

impl SolverSettings {
    /// The options of a warm level of mesh sequencing: these settings plus [`WarmStart`], unless
    /// the case sets those options itself.
    pub fn warm_ipopt(&self, warm: &WarmStart) -> Options {
        let mut options = Options::new()
            .number("mu_init", warm.mu_init)
            .number("bound_push", warm.bound_push)
            .number("bound_frac", warm.bound_frac);
        if warm.multipliers {
            options = options
                .string("warm_start_init_point", "yes")
                .number("warm_start_bound_push", warm.bound_push)
                .number("warm_start_bound_frac", warm.bound_frac)
                .number("warm_start_slack_bound_push", warm.bound_push)
                .number("warm_start_slack_bound_frac", warm.bound_frac)
                .number("warm_start_mult_bound_push", warm.mult_bound_push);
        }
        options.extend(&self.ipopt());
        options
    }
}

/// Why a design run could not start.
#[derive(Debug, Clone, PartialEq)]
pub enum DesignError {
    Setup(SetupError),
}

impl std::fmt::Display for DesignError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DesignError::Setup(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for DesignError {}

/// Start states of the full space: the equilibria of the start design by continuation when they
/// exist, else the unloaded shape with `λ = 0` (and a note saying so).
pub fn start_states(
    problem: &DesignProblem,
    start: &Design,
    continuation: &ContinuationOptions,
    notes: &mut Vec<String>,
) -> (State, State) {
    let solution = solve_static(&problem.static_problem(start), continuation);
    let passive_ok = solution.passive.load_factor == 1.0;
    let passive = if passive_ok { solution.passive.state.clone() } else { State::unloaded(start) };
    let loaded = match solution.loaded.filter(|l| l.load_factor == 1.0) {
        Some(l) => l.state,
        None => {
            notes.push("the start design has no loaded equilibrium on its load path; θ2 starts at θ1".into());
            passive.clone()
        }
    };
    if !passive_ok {
        notes.push("the start design has no passive equilibrium on its load path; θ1 starts at θ0".into());
    }
    (passive, loaded)
}

/// Solves eq. (33) from `start` (projected into the bounds first) in the given formulation; in the
/// full space through the mesh-sequencing ladder of `settings.refine` when it applies.
/// `observer` sees every Ipopt iteration (of every level) and may stop the run by returning `false`.
pub fn solve_design(
    problem: &DesignProblem,
    start: &Design,
    formulation: Formulation,
    settings: &SolverSettings,
    observer: &mut dyn FnMut(&IterationInfo) -> bool,
) -> Result<DesignResult, DesignError> {
    let clock = Instant::now();
    let (start, mut notes) = problem.project_start(start);
    let options = settings.ipopt();
    let mut refinement = None;
    let mut start_seconds = 0.0;
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
                    let mut nlp = FullSpaceNlp::new(problem, &start, &passive, &loaded);
                    nlp.on_iteration = Some(observer);
                    let solution = spine_ipopt::solve(&mut nlp, &options).map_err(DesignError::Setup)?;
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
            let solution = spine_ipopt::solve(&mut nlp, &options).map_err(DesignError::Setup)?;
            let design = nlp.design(&solution.x);
            let states = nlp.evaluate(&solution.x).map(|e| (e.passive.clone(), e.loaded.clone()));
            (solution, design, states, nlp.equilibrium_evaluations)
        }
    };
    let mut report = SolverReport::from_ipopt(&solution, equilibrium_evaluations);
    report.start_seconds = start_seconds;
    report.ipopt_options = options
        .iter()
        .map(|(k, v)| (k.to_string(), if let OptionValue::Str(text) = v { text.clone() } else { v.to_string() }))
        .collect();
    let check_clock = Instant::now();
    let mut result = DesignResult::check(problem, formulation, design, states, report, notes, &settings.continuation);
    result.solver.check_seconds = check_clock.elapsed().as_secs_f64();
    result.solver.total_seconds = clock.elapsed().as_secs_f64();
    result.refinement = refinement;
    Ok(result)
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
    let cold_options = settings.ipopt();
    let warm = settings.warm_start;
    let warm_options = settings.warm_ipopt(&warm);
    let mut levels: Vec<LevelReport> = Vec::new();
    let mut previous: Option<(DesignProblem, Design, (State, State), Multipliers)> = None;
    let mut fell_back = false;
    let mut next = 0;
    loop {
        let m = if fell_back { n } else { sizes[next] };
        let clock = Instant::now();
        let previous_level = previous.as_ref().map(|(p, d, s, _)| (p, d, s));
        let setup = refine::prepare_level(problem, m, previous_level, start, &settings.continuation, notes);
        let (level, how, design, states) = (setup.problem(problem), setup.start, &setup.design, &setup.states);
        let start_seconds = clock.elapsed().as_secs_f64();
        let mut nlp = FullSpaceNlp::new(level, design, &states.0, &states.1);
        nlp.on_iteration = Some(&mut *observer);
        if let (Some((coarser, _, _, multipliers)), true) = (&previous, warm.multipliers) {
            let size = nlp.layout.num_variables();
            let (mut lower, mut upper) = (vec![f64::NEG_INFINITY; size], vec![f64::INFINITY; size]);
            spine_ipopt::Problem::variable_bounds(&nlp, &mut lower, &mut upper);
            nlp.multipliers =
                Some(refine::prolong_multipliers(coarser, level, multipliers, &nlp.start, &lower, &upper));
        }
        let options = if how == LevelStart::Cold { &cold_options } else { &warm_options };
        let solution = spine_ipopt::solve(&mut nlp, options).map_err(DesignError::Setup)?;
        let (design, states) = refine::solution_parts(&nlp, &solution.x);
        levels.push(LevelReport {
            links: m,
            start: how,
            status: solution.status.name(),
            optimal: solution.status.is_optimal(),
            iterations: solution.iterations,
            objective: solution.objective,
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
