//! What the Ipopt callbacks share with the solve that started them (behind Ipopt's `user_data`),
//! and the arrays that go into and come out of `IpoptSolve`. Safe code: the C side is in
//! [`crate::ffi`].

use crate::{EvaluationCounts, IterationInfo, Problem};
use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

/// Everything a callback needs, behind the `user_data` pointer.
pub(crate) struct Context<'a> {
    pub problem: &'a mut dyn Problem,
    pub jacobian: Vec<(usize, usize)>,
    pub hessian: Option<Vec<(usize, usize)>>,
    pub panic: Option<Box<dyn Any + Send>>,
    pub last: IterationInfo,
    pub evaluations: EvaluationCounts,
    pub callback_time: Duration,
    /// Set when [`spine_stop::check`] stopped the run at an iteration.
    pub stopped: Option<spine_stop::StopReason>,
}

impl Context<'_> {
    /// Runs `f` with panics caught and time recorded; a panic is stored and reported as failure.
    pub(crate) fn guarded(&mut self, f: impl FnOnce(&mut Self) -> bool) -> bool {
        if self.panic.is_some() {
            return false;
        }
        let start = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| f(self)));
        self.callback_time += start.elapsed();
        match outcome {
            Ok(ok) => ok,
            Err(payload) => {
                self.panic = Some(payload);
                false
            }
        }
    }
}

/// The start of a solve: bounds, point and (optionally) multipliers, all of the right lengths.
pub(crate) struct Start {
    pub x_lower: Vec<f64>,
    pub x_upper: Vec<f64>,
    pub g_lower: Vec<f64>,
    pub g_upper: Vec<f64>,
    pub x: Vec<f64>,
    pub mult_g: Vec<f64>,
    pub z_lower: Vec<f64>,
    pub z_upper: Vec<f64>,
}

impl Start {
    /// The problem's bounds (infinities clamped to Ipopt's ±1e20), start point and, when it gives
    /// them, start multipliers (zeros otherwise).
    pub(crate) fn from_problem(problem: &mut dyn Problem, n: usize, m: usize) -> Self {
        let mut start = Start {
            x_lower: vec![f64::NEG_INFINITY; n],
            x_upper: vec![f64::INFINITY; n],
            g_lower: vec![f64::NEG_INFINITY; m],
            g_upper: vec![f64::INFINITY; m],
            x: vec![0.0; n],
            mult_g: vec![0.0; m],
            z_lower: vec![0.0; n],
            z_upper: vec![0.0; n],
        };
        problem.variable_bounds(&mut start.x_lower, &mut start.x_upper);
        problem.constraint_bounds(&mut start.g_lower, &mut start.g_upper);
        // Ipopt reads ±1e19 as infinite; Rust's infinities map onto that.
        for value in [&mut start.x_lower, &mut start.x_upper, &mut start.g_lower, &mut start.g_upper]
            .into_iter()
            .flat_map(|v| v.iter_mut())
        {
            *value = value.clamp(-1e20, 1e20);
        }
        problem.initial_point(&mut start.x);
        if !problem.initial_multipliers(&mut start.z_lower, &mut start.z_upper, &mut start.mult_g) {
            start.mult_g.fill(0.0);
            start.z_lower.fill(0.0);
            start.z_upper.fill(0.0);
        }
        start
    }
}

/// What `IpoptSolve` wrote back.
pub(crate) struct Finish {
    pub status: i32,
    pub x: Vec<f64>,
    pub g: Vec<f64>,
    pub objective: f64,
    pub mult_g: Vec<f64>,
    pub z_lower: Vec<f64>,
    pub z_upper: Vec<f64>,
}
