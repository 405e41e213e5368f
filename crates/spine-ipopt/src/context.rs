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
