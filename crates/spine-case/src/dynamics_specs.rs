//! The sections of a dynamic case that set up a design: eq. (33) first (`static_design`), eq. (35)
//! (`damping_design`), eq. (37) (`periodic_design`).

use crate::design_case::{BoundsSpec, StartSpec};
use serde::{Deserialize, Serialize};
use spine_design::{Formulation, SolverSettings};
use spine_dynamic_design::{DampingSettings, PeriodicDesignSettings, SearchMethod};

/// Eq. (33) settings for a dynamic case whose design is `"optimise"` (chain and loads are the case's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StaticDesignSpec {
    pub delta_d: f64,
    #[serde(default = "crate::design_case::one")]
    pub stiffness_scale: f64,
    #[serde(default)]
    pub bounds: BoundsSpec,
    pub start: StartSpec,
    #[serde(default = "crate::design_case::full")]
    pub formulation: Formulation,
    #[serde(default)]
    pub solver: SolverSettings,
}

/// Eq. (35): one design per target rise time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DampingDesignSpec {
    /// Target rise times `T_d`, s (each > 0; each design simulates at least `3 T_d`, more if `simulation.t_end` is longer).
    pub targets: Vec<f64>,
    /// Damper bounds, N·m·s/rad (default 1 and 10³, the paper's).
    #[serde(default = "c_min")]
    pub damping_min: f64,
    #[serde(default = "c_max")]
    pub damping_max: f64,
    #[serde(default = "tol")]
    pub tolerance: f64,
    #[serde(default = "iters")]
    pub max_iterations: usize,
    /// Raise `damping_min` until each design's step response is over-damped (the paper's "trial
    /// and error", Sec. 4.2); default false.
    #[serde(default)]
    pub overdamped: bool,
}

// The defaults are eq. (35)'s own (`DampingSettings::default()`), written once there.
fn c_min() -> f64 {
    DampingSettings::default().damping_min
}
fn c_max() -> f64 {
    DampingSettings::default().damping_max
}
fn tol() -> f64 {
    DampingSettings::default().tolerance
}
fn iters() -> usize {
    DampingSettings::default().max_iterations
}

/// Eq. (37).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PeriodicDesignSpec {
    /// Desired `min_t (X_{N+1}(t) − L_x)`, m (≠ 0).
    pub delta_d: f64,
    /// `"ga"` (default), `"pattern"` or `"gradient"`; `spine periodic --method` overrides it.
    #[serde(default = "ga")]
    pub method: SearchMethod,
    #[serde(default)]
    pub settings: PeriodicDesignSettings,
}

fn ga() -> SearchMethod {
    SearchMethod::Ga
}
