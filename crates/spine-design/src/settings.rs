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

/// The type and allowed values of an Ipopt option a case file may set.
#[derive(Clone, Copy, Debug)]
enum Allowed {
    /// A finite number (an integer literal is accepted too).
    Number,
    Integer,
    /// One of these strings.
    OneOf(&'static [&'static str]),
}

/// The Ipopt options a case file may set in `solver.ipopt_options`: numerical settings only
/// (tolerances, limits, barrier and scaling choices, warm starts, printing to the terminal). Options
/// that open, write or read files (`output_file`, `option_file_name`, `file_print_level`, …) and
/// anything not listed are refused, so that a case file cannot reach the file system through Ipopt
/// and every accepted option exists in both supported Ipopt versions (3.11 and 3.14).
const CASE_IPOPT_OPTIONS: &[(&str, Allowed)] = &[
    ("tol", Allowed::Number),
    ("dual_inf_tol", Allowed::Number),
    ("constr_viol_tol", Allowed::Number),
    ("compl_inf_tol", Allowed::Number),
    ("acceptable_tol", Allowed::Number),
    ("acceptable_iter", Allowed::Integer),
    ("acceptable_dual_inf_tol", Allowed::Number),
    ("acceptable_constr_viol_tol", Allowed::Number),
    ("acceptable_compl_inf_tol", Allowed::Number),
    ("acceptable_obj_change_tol", Allowed::Number),
    ("max_iter", Allowed::Integer),
    ("max_cpu_time", Allowed::Number),
    ("mu_strategy", Allowed::OneOf(&["monotone", "adaptive"])),
    ("mu_oracle", Allowed::OneOf(&["quality-function", "probing", "loqo"])),
    ("mu_init", Allowed::Number),
    ("mu_min", Allowed::Number),
    ("mu_max", Allowed::Number),
    ("mu_linear_decrease_factor", Allowed::Number),
    ("mu_superlinear_decrease_power", Allowed::Number),
    ("barrier_tol_factor", Allowed::Number),
    ("bound_push", Allowed::Number),
    ("bound_frac", Allowed::Number),
    ("slack_bound_push", Allowed::Number),
    ("slack_bound_frac", Allowed::Number),
    ("bound_relax_factor", Allowed::Number),
    ("honor_original_bounds", Allowed::OneOf(&["yes", "no"])),
    ("bound_mult_init_method", Allowed::OneOf(&["constant", "mu-based"])),
    ("bound_mult_init_val", Allowed::Number),
    ("constr_mult_init_max", Allowed::Number),
    ("nlp_scaling_method", Allowed::OneOf(&["gradient-based", "none"])),
    ("nlp_scaling_max_gradient", Allowed::Number),
    ("obj_scaling_factor", Allowed::Number),
    ("hessian_approximation", Allowed::OneOf(&["exact", "limited-memory"])),
    ("limited_memory_max_history", Allowed::Integer),
    ("fixed_variable_treatment", Allowed::OneOf(&["make_parameter", "make_constraint", "relax_bounds"])),
    ("mehrotra_algorithm", Allowed::OneOf(&["yes", "no"])),
    ("max_soc", Allowed::Integer),
    ("watchdog_shortened_iter_trigger", Allowed::Integer),
    ("warm_start_init_point", Allowed::OneOf(&["yes", "no"])),
    ("warm_start_bound_push", Allowed::Number),
    ("warm_start_bound_frac", Allowed::Number),
    ("warm_start_slack_bound_push", Allowed::Number),
    ("warm_start_slack_bound_frac", Allowed::Number),
    ("warm_start_mult_bound_push", Allowed::Number),
    ("linear_solver", Allowed::OneOf(&["spine", "mumps"])),
    ("mumps_pivot_order", Allowed::Integer),
    ("mumps_mem_percent", Allowed::Integer),
    ("mumps_scaling", Allowed::Integer),
    ("mumps_permuting_scaling", Allowed::Integer),
    ("print_level", Allowed::Integer),
    ("print_timing_statistics", Allowed::OneOf(&["yes", "no"])),
];

/// Options that touch files, refused with that reason.
const FILE_OPTIONS: &[&str] = &["output_file", "option_file_name", "file_print_level", "print_options_documentation"];

impl SolverSettings {
    /// Checks `ipopt_options` against the options a case may set: the option's name (with the
    /// reason when it is refused) and its type and value. The error's field is the option's name.
    pub fn check_ipopt_options(&self) -> Result<(), FieldError> {
        for (name, value) in &self.ipopt_options {
            if FILE_OPTIONS.contains(&name.as_str()) {
                return Err(FieldError::new(name.clone(), "opens or reads a file: not allowed in a case file"));
            }
            let Some((_, allowed)) = CASE_IPOPT_OPTIONS.iter().find(|(n, _)| n == name) else {
                let names: Vec<&str> = CASE_IPOPT_OPTIONS.iter().map(|(n, _)| *n).collect();
                return Err(FieldError::new(
                    name.clone(),
                    format!("not an Ipopt option a case may set; allowed: {}", names.join(", ")),
                ));
            };
            let ok = match (allowed, value) {
                (Allowed::Number, ExtraOption::Num(x)) => x.is_finite(),
                (Allowed::Number | Allowed::Integer, ExtraOption::Int(i)) => i32::try_from(*i).is_ok(),
                (Allowed::OneOf(values), ExtraOption::Str(s)) => values.contains(&s.as_str()),
                _ => false,
            };
            if !ok {
                let expected = match allowed {
                    Allowed::Number => "a finite number".to_string(),
                    Allowed::Integer => "an integer within ±2147483647".to_string(),
                    Allowed::OneOf(values) => format!("one of {values:?}"),
                };
                return Err(FieldError::new(name.clone(), format!("must be {expected}, got {value}")));
            }
        }
        Ok(())
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
        require(["monotone", "adaptive"].contains(&self.barrier_strategy.as_str()), "barrier_strategy", || {
            format!("must be \"monotone\" or \"adaptive\", got {:?}", self.barrier_strategy)
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
