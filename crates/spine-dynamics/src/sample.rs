//! One sample of the chain's motion: the time, the load factor, the end displacement and the
//! link angles (what responses, over-damping checks, CSV tables and animations read).

use serde::Serialize;

/// One sample of the motion.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Load factor `s(t)` of the actuation.
    pub load_factor: f64,
    /// End displacement from the start, `X_{N+1}(t) − X_{N+1}(θ1)`, m.
    pub delta: f64,
    /// `X_{N+1}(t) − L_x`, m.
    pub end_displacement: f64,
    /// Link angles, rad.
    pub theta: Vec<f64>,
}
