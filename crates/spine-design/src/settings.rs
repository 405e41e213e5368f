//! The settings of a design run (case file field `solver`): formulation, Ipopt's options, the
//! continuation of the equilibrium solves, mesh sequencing.

use crate::reduced_space::ReducedHessian;
use crate::refine::{Refine, WarmStart};
use serde::{Deserialize, Serialize};
use spine_check::{require, FieldError};
use spine_ipopt::{OptionValue, Options};
use spine_solve::ContinuationOptions;
use std::collections::BTreeMap;

/// Which form of eq. (33) Ipopt solves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
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
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
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

pub use crate::variables::{SpringVariables, StateVariables, ABSOLUTE_ANGLE_FLOOR_FACTOR, LOG_SPRINGS_FROM_LINKS};
pub use spine_ipopt::BarrierStrategy;

/// The factorisation of Ipopt's KKT matrices (case field `solver.linear_solver`; docs/design.md,
/// "Linear solver").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum LinearSolver {
    /// The workspace's own sparse `LDLᵀ` with exact inertia (`spine-kkt`), which Ipopt reaches
    /// through its Pardiso interface once installed ([`LinearSolver::ready`]). Thread-safe.
    #[default]
    Spine,
    /// The MUMPS that the Ipopt library ships (one solve at a time per process).
    Mumps,
}

impl LinearSolver {
    /// Ipopt's option value for this solver.
    pub fn ipopt(self) -> spine_ipopt::LinearSolver {
        match self {
            Self::Spine => spine_ipopt::LinearSolver::Pardiso,
            Self::Mumps => spine_ipopt::LinearSolver::Mumps,
        }
    }

    /// Makes the solver loadable by Ipopt: installs the workspace's `LDLᵀ` as Ipopt's Pardiso
    /// library (once per process; [`spine_kkt::install`]). MUMPS needs nothing.
    pub fn ready(self) -> Result<(), spine_kkt::KktError> {
        match self {
            Self::Spine => spine_kkt::install(),
            Self::Mumps => Ok(()),
        }
    }
}

/// One extra Ipopt option from a case file: a number, an integer or a string.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(untagged)]
pub enum ExtraOption {
    Int(i64),
    Num(f64),
    Str(String),
}

impl std::fmt::Display for ExtraOption {
    /// As the case file writes it: `3`, `1e-8`, `"yes"`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Int(i) => write!(f, "{i}"),
            Self::Num(x) => write!(f, "{x:e}"),
            Self::Str(s) => write!(f, "{s:?}"),
        }
    }
}

/// Solver settings of a design run (case file field `solver`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Ipopt `mu_strategy`: `"monotone"` or `"adaptive"`.
    pub barrier_strategy: BarrierStrategy,
    /// The factorisation of Ipopt's KKT matrices: `"spine"` (the workspace's own) or `"mumps"`.
    pub linear_solver: LinearSolver,
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
    /// Full space only: the states as absolute angles or as deflections from the unloaded shape
    /// (`"auto"`, `"absolute"`, `"deflection"`).
    pub state_variables: StateVariables,
    /// Full space only: the springs as Ipopt sees them, `"log"` (`ln k`), `"linear"` (`k`
    /// itself) or `"auto"` (default: logarithms from 100 links on). The problem and its optima
    /// are the same; Ipopt's path differs.
    pub spring_variables: SpringVariables,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-9,
            constraint_tolerance: 1e-9,
            max_iterations: 3000,
            scaling: ScalingMethod::GradientBased,
            barrier_strategy: BarrierStrategy::Monotone,
            linear_solver: LinearSolver::Spine,
            reduced_hessian: ReducedHessian::AdjointDifferences,
            continuation: ContinuationOptions { residual_tolerance: 1e-11, ..ContinuationOptions::default() },
            ipopt_options: BTreeMap::new(),
            refine: Refine::default(),
            warm_start: WarmStart::default(),
            state_variables: StateVariables::Auto,
            spring_variables: SpringVariables::Auto,
        }
    }
}

/// How a design case solves eq. (33): this program's own settings, or made to behave like the
/// paper's optimiser.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SolverPreset {
    /// The case's `formulation` and `solver` as written (default).
    #[default]
    Exact,
    /// Like MATLAB's `fmincon` with its defaults, the paper's optimiser: the reduced space with
    /// [`SolverSettings::fmincon_like`] (L-BFGS, tolerances 1e-6, 1000 iterations, no mesh
    /// sequencing), from the case's start. It replaces the case's `formulation` and those fields of
    /// `solver`.
    FminconLike,
}

impl SolverPreset {
    /// The formulation and settings this preset solves with, from the case's.
    pub fn apply(self, formulation: Formulation, settings: &SolverSettings) -> (Formulation, SolverSettings) {
        match self {
            Self::Exact => (formulation, settings.clone()),
            Self::FminconLike => (Formulation::Reduced, settings.fmincon_like()),
        }
    }

    /// The name written in case files and results.
    pub fn name(self) -> &'static str {
        match self {
            Self::Exact => "exact",
            Self::FminconLike => "fmincon-like",
        }
    }
}

/// `acceptable_obj_change_tol` of every design solve (see [`SolverSettings::ipopt`]).
pub const ACCEPTABLE_OBJ_CHANGE: f64 = 1e-10;

impl SolverSettings {
    /// These settings made to stop like MATLAB's `fmincon` with its default options, the paper's
    /// optimiser (Sec. 5: "solved in Matlab using fmincon"), for the reduced space: an L-BFGS
    /// Hessian (fmincon's interior-point default is BFGS), first-order optimality and constraint
    /// tolerance 1e-6 (`OptimalityTolerance`, `ConstraintTolerance`), at most 1000 iterations
    /// (`MaxIterations`), no mesh sequencing. Ipopt's measures are not fmincon's, so this is the
    /// closest this program comes, not the same solver.
    pub fn fmincon_like(&self) -> Self {
        Self {
            tolerance: 1e-6,
            constraint_tolerance: 1e-6,
            max_iterations: 1000,
            reduced_hessian: ReducedHessian::LimitedMemory,
            refine: Refine::Mode(crate::refine::RefineMode::Off),
            ..self.clone()
        }
    }

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
            .string("mu_strategy", self.barrier_strategy.name())
            // Report the design Ipopt converged to, not one moved back onto the original bounds
            // afterwards (3.11's default): the equilibria of a moved design are not satisfied.
            .string("honor_original_bounds", "no")
            // Stop at the acceptable level only once the objective has stopped moving (change
            // below 1e-10 relative to max(1, |J|) between iterations): with Ipopt's default (no
            // such test) a run that creeps along a nearly flat valley of `K` with a constant dual
            // infeasibility between `tol` and `acceptable_tol` stopped after 15 such iterations
            // short of the optimum (scaled family, N = 10: J 0.7 % high; it converges to 6e-15
            // 18 iterations later).
            .number("acceptable_obj_change_tol", ACCEPTABLE_OBJ_CHANGE)
            // A fixed fill-reducing ordering: the automatic choice of MUMPS 5.5 picks SCOTCH on
            // large systems and runs of the same input then differ.
            .integer("mumps_pivot_order", MUMPS_PIVOT_ORDER)
            // The workspace's own sparse LDLᵀ (`crates/spine-kkt`): every paper case reaches the
            // same optima and claims as with MUMPS, and an iteration costs 25–50 % less
            // (docs/design.md, "Linear solver"). `solver.linear_solver: "mumps"` selects the MUMPS
            // that the Ipopt library ships.
            .string("linear_solver", self.linear_solver.ipopt().name());
        if self.linear_solver == LinearSolver::Spine {
            // Ipopt refines every solve at least once by default (`min_refinement_steps` 1), on
            // top of the refinement our solver has already done to a componentwise backward error
            // of 1e-12 (`spine_kkt::solver`); it still refines where its own residual test asks.
            // Saves one solve per search direction: N = 500's finest level takes the same 59
            // iterations with 91 solves instead of 168 (docs/design.md, "Linear solver").
            options = options.integer("min_refinement_steps", 0);
        }
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

impl SolverSettings {
    /// Checks every setting where it is defined; the error's field is the path inside a case
    /// file's `solver` section (`tolerance`, `continuation.min_step`, `ipopt_options.mu_init`,
    /// `refine.factor`, `warm_start.bound_push`).
    pub fn validate(&self) -> Result<(), FieldError> {
        for (field, v) in [("tolerance", self.tolerance), ("constraint_tolerance", self.constraint_tolerance)] {
            require(v.is_finite() && v > 0.0, field, || format!("must be a finite number > 0 , got {v}"))?;
        }
        require(self.max_iterations >= 1 && self.max_iterations <= i32::MAX as usize, "max_iterations", || {
            "must be between 1 and 2147483647".into()
        })?;
        self.continuation.validate().map_err(|e| e.under("continuation"))?;
        self.check_ipopt_options().map_err(|e| e.under("ipopt_options"))?;
        if let crate::refine::Refine::Ladder(ladder) = &self.refine {
            ladder.validate().map_err(|e| e.under("refine"))?;
        }
        self.warm_start.validate().map_err(|e| e.under("warm_start"))
    }
}

/// MUMPS's `ICNTL(7)` ordering used by every design solve: 5 (METIS), the fastest of the
/// orderings measured on eq. (33) (docs/design.md) and deterministic.
pub const MUMPS_PIVOT_ORDER: i64 = 5;

impl SolverSettings {
    /// The smaller of [`Self::tolerance`] and [`Self::constraint_tolerance`], which
    /// [`StateVariables::resolve`] compares with the round-off of absolute angles.
    pub fn smaller_tolerance(&self) -> f64 {
        self.tolerance.min(self.constraint_tolerance)
    }

    /// Ipopt's `tol` at the coarse levels of mesh sequencing: [`WarmStart::coarse_tolerance`], never
    /// tighter than [`Self::tolerance`].
    pub fn coarse_tolerance(&self) -> f64 {
        self.warm_start.coarse_tolerance.max(self.tolerance)
    }

    /// Ipopt's options for level `m` of a ladder from `from` links towards the chain's own `n`
    /// links (`cold`: the coarsest level, started from the case's start point), with
    /// `barrier`: the level's `μ_m` of [`WarmStart::barrier`] ([`Self::level_barrier`]), or `None`.
    ///
    /// A warm level starts close to its bounds ([`WarmStart`]'s `bound_push`, `bound_frac`,
    /// `mu_init`). With a barrier, a coarse level is solved to the barrier problem of `μ_m`
    /// (`mu_target`) and a warm level starts at `μ_m` (`mu_init`, bound multipliers
    /// `μ_m / slack`). The case's own Ipopt options override all of these, and the coarse levels
    /// are solved to [`Self::coarse_tolerance`].
    pub fn level_ipopt(&self, m: usize, n: usize, cold: bool, barrier: Option<f64>) -> Options {
        let warm = &self.warm_start;
        let mut options = Options::new();
        if !cold {
            options = options
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
        }
        if let Some(mu) = barrier {
            if m < n {
                options = options.number("mu_target", mu);
            }
            if !cold {
                options = options.number("mu_init", mu).string("bound_mult_init_method", "mu-based");
            }
        }
        options.extend(&self.ipopt());
        if m < n {
            options = options.number("tol", self.coarse_tolerance());
        }
        options
    }

    /// `μ_m` of level `m` of a ladder from `from` links ([`WarmStart::barrier`]), never below a
    /// tenth of [`Self::tolerance`]; `None` without a schedule.
    pub fn level_barrier(&self, from: usize, m: usize) -> Option<f64> {
        self.warm_start.barrier.map(|b| b.mu_at(from, m, self.tolerance / 10.0))
    }
}

/// Ipopt's options for a solve that starts from a whole point and its multipliers
/// (`warm_start_init_point`): the barrier's `mu_init`, and `push` for every warm-start bound push
/// and fraction (of the variables, the slacks and the bound multipliers). A followed sweep's
/// corrector and the certificate's solve at the case's tolerance set them.
pub(crate) fn warm_point_options(mu_init: f64, push: f64) -> [(&'static str, f64); 6] {
    [
        ("mu_init", mu_init),
        ("warm_start_bound_push", push),
        ("warm_start_bound_frac", push),
        ("warm_start_slack_bound_push", push),
        ("warm_start_slack_bound_frac", push),
        ("warm_start_mult_bound_push", push),
    ]
}
