//! Options of Newton and of the load continuation, each checked where it is defined.

use serde::{Deserialize, Serialize};
use spine_check::FieldError;

/// Options of Newton and of the load continuation. Mirrored by a case file's `solver` section.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct ContinuationOptions {
    /// Newton stops when `max |r_i|` is at most this: joint rows in N·m, the constraint row in m.
    /// Where this is below the rounding floor of the residual (`32 ε` times the largest sum of
    /// absolute terms of a row, e.g. stiff springs of 10⁷ N·m/rad) that floor is used instead and
    /// reported as `tolerance_used`.
    pub residual_tolerance: f64,
    /// Newton iterations allowed per continuation step.
    pub max_newton_iterations: usize,
    /// First load step (fraction of the full load, `0 < step ≤ 1`).
    pub initial_step: f64,
    /// Smallest load step before the path is declared stuck.
    pub min_step: f64,
    /// Accepted continuation steps allowed.
    pub max_steps: usize,
    /// Largest change of any link angle in one step, rad: keeps the path from jumping branches.
    pub max_angle_step: f64,
    /// Width of the load-factor bracket when locating a loss of stability or a fold.
    pub critical_load_tolerance: f64,
}

impl ContinuationOptions {
    /// Checks every setting against the range where the solver is meaningful and finishes:
    /// `residual_tolerance` in [1e-300, 1] (below the rounding floor the floor is used),
    /// `critical_load_tolerance` in [1e-15, 0.1], `max_angle_step` in (0, π/2],
    /// `1e-15 ≤ min_step ≤ initial_step ≤ 1`, 1 … 1000 Newton iterations, 1 … 10⁷ steps.
    pub fn validate(&self) -> Result<(), FieldError> {
        let err = |field: &str, message: String| Err(FieldError::new(field, message));
        let within = |v: f64, lo: f64, hi: f64| v.is_finite() && v >= lo && v <= hi;
        if !within(self.residual_tolerance, 1e-300, 1.0) {
            return err("residual_tolerance", format!("must be in [1e-300, 1], got {}", self.residual_tolerance));
        }
        if !(self.max_angle_step > 0.0 && self.max_angle_step <= std::f64::consts::FRAC_PI_2) {
            return err("max_angle_step", format!("must be in (0, π/2] rad, got {}", self.max_angle_step));
        }
        if !within(self.critical_load_tolerance, 1e-15, 0.1) {
            let v = self.critical_load_tolerance;
            return err("critical_load_tolerance", format!("must be in [1e-15, 0.1], got {v}"));
        }
        if !(self.initial_step > 0.0 && self.initial_step <= 1.0) {
            return err("initial_step", format!("must be in (0, 1], got {}", self.initial_step));
        }
        if !(self.min_step >= 1e-15 && self.min_step <= self.initial_step) {
            return err("min_step", format!("must be in [1e-15, initial_step], got {}", self.min_step));
        }
        if !(1..=MAX_NEWTON_ITERATIONS).contains(&self.max_newton_iterations) {
            let v = self.max_newton_iterations;
            return err("max_newton_iterations", format!("must be between 1 and {MAX_NEWTON_ITERATIONS}, got {v}"));
        }
        if !(1..=MAX_CONTINUATION_STEPS).contains(&self.max_steps) {
            return err("max_steps", format!("must be between 1 and {MAX_CONTINUATION_STEPS}, got {}", self.max_steps));
        }
        Ok(())
    }
}

/// Most Newton iterations per continuation step a case may ask for.
pub const MAX_NEWTON_ITERATIONS: usize = 1000;
/// Most continuation steps a case may ask for.
pub const MAX_CONTINUATION_STEPS: usize = 10_000_000;

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            residual_tolerance: 1e-10,
            max_newton_iterations: 12,
            initial_step: 1.0,
            min_step: 1e-6,
            max_steps: 10_000,
            max_angle_step: 0.1,
            critical_load_tolerance: 1e-9,
        }
    }
}
