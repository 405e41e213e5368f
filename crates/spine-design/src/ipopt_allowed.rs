//! The Ipopt options a case file may set in `solver.ipopt_options`, and their check
//! ([`SolverSettings::check_ipopt_options`]): numerical settings only, one way to set each.

use crate::settings::{ExtraOption, SolverSettings};
use spine_check::FieldError;

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
    ("dual_inf_tol", Allowed::Number),
    ("compl_inf_tol", Allowed::Number),
    ("acceptable_tol", Allowed::Number),
    ("acceptable_iter", Allowed::Integer),
    ("acceptable_dual_inf_tol", Allowed::Number),
    ("acceptable_constr_viol_tol", Allowed::Number),
    ("acceptable_compl_inf_tol", Allowed::Number),
    ("acceptable_obj_change_tol", Allowed::Number),
    ("max_cpu_time", Allowed::Number),
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
    ("mumps_pivot_order", Allowed::Integer),
    ("mumps_mem_percent", Allowed::Integer),
    ("mumps_scaling", Allowed::Integer),
    ("mumps_permuting_scaling", Allowed::Integer),
    ("print_level", Allowed::Integer),
    ("print_timing_statistics", Allowed::OneOf(&["yes", "no"])),
];

/// Ipopt options that a typed field of `solver` sets: one way to set each, refused in
/// `ipopt_options` with the field to use.
const TYPED_OPTIONS: &[(&str, &str)] = &[
    ("tol", "solver.tolerance"),
    ("constr_viol_tol", "solver.constraint_tolerance"),
    ("max_iter", "solver.max_iterations"),
    ("mu_strategy", "solver.barrier_strategy"),
    ("linear_solver", "solver.linear_solver"),
    ("nlp_scaling_method", "solver.scaling"),
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
            if let Some((_, field)) = TYPED_OPTIONS.iter().find(|(n, _)| n == name) {
                return Err(FieldError::new(
                    name.clone(),
                    format!("set by {field}: give it there (one way to set each option)"),
                ));
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
                    Allowed::OneOf(values) => format!("one of {}", values.join(", ")),
                };
                return Err(FieldError::new(name.clone(), format!("must be {expected}, got {value}")));
            }
        }
        Ok(())
    }
}
