//! The settings of a design run (case file field `solver`): formulation, Ipopt's options, the
//! continuation of the equilibrium solves, mesh sequencing.

use crate::reduced_space::ReducedHessian;
use crate::refine::{Refine, WarmStart};
use serde::{Deserialize, Serialize};
use spine_ipopt::{OptionValue, Options};
use spine_solve::ContinuationOptions;
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
