//! Runs eq. (33) with Ipopt in either formulation and checks what comes back.

use crate::full_space::{FullSpaceNlp, LoadState};
use crate::problem::DesignProblem;
use crate::reduced_space::{ReducedHessian, ReducedSpaceNlp};
use crate::result::{DesignResult, SolverReport};
use serde::{Deserialize, Serialize};
use spine_ipopt::{IterationInfo, OptionValue, Options, SetupError};
use spine_model::{Design, State};
use spine_solve::{solve_static, ContinuationOptions};
use std::collections::BTreeMap;

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
            .string("mu_strategy", &self.barrier_strategy);
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
pub fn start_states(problem: &DesignProblem, start: &Design, continuation: &ContinuationOptions, notes: &mut Vec<String>) -> (State, State) {
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

/// Solves eq. (33) from `start` (projected into the bounds first) in the given formulation.
/// `observer` sees every Ipopt iteration and may stop the run by returning `false`.
pub fn solve_design(
    problem: &DesignProblem,
    start: &Design,
    formulation: Formulation,
    settings: &SolverSettings,
    observer: &mut dyn FnMut(&IterationInfo) -> bool,
) -> Result<DesignResult, DesignError> {
    let (start, mut notes) = problem.project_start(start);
    let options = settings.ipopt();
    let (solution, design, states, equilibrium_evaluations) = match formulation {
        Formulation::Full => {
            let (passive, loaded) = start_states(problem, &start, &settings.continuation, &mut notes);
            let mut nlp = FullSpaceNlp::new(problem, &start, &passive, &loaded);
            nlp.on_iteration = Some(observer);
            let solution = spine_ipopt::solve(&mut nlp, &options).map_err(DesignError::Setup)?;
            let layout = nlp.layout;
            let design = layout.design(&solution.x, problem.stiffness_scale);
            let states = Some((layout.state(&solution.x, LoadState::Passive), layout.state(&solution.x, LoadState::Loaded)));
            (solution, design, states, 0)
        }
        Formulation::Reduced => {
            let mut nlp = ReducedSpaceNlp::new(problem, &start, settings.continuation.clone(), settings.reduced_hessian);
            nlp.on_iteration = Some(observer);
            let solution = spine_ipopt::solve(&mut nlp, &options).map_err(DesignError::Setup)?;
            let design = nlp.design(&solution.x);
            let states = nlp.evaluate(&solution.x).map(|e| (e.passive.clone(), e.loaded.clone()));
            (solution, design, states, nlp.equilibrium_evaluations)
        }
    };
    let report = SolverReport::from_ipopt(&solution, equilibrium_evaluations);
    Ok(DesignResult::check(problem, formulation, design, states, report, notes, &settings.continuation))
}
