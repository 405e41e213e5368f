//! The settings of eq. (37)'s methods: which method ([`SearchMethod`]), the problem's bounds and
//! band, each method's own settings and the periodic response of every candidate.

use serde::{Deserialize, Serialize};
use spine_check::require;
pub use spine_dynamics::integrator::adjoint::Sensitivities;
use spine_dynamics::integrator::Options;
use spine_dynamics::periodic::PeriodicSettings;
use spine_search::{GaSettings, PatternSettings};

/// Which method solves eq. (37).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SearchMethod {
    Ga,
    Pattern,
    /// Ipopt with exact gradients ([`crate::periodic_gradient`]).
    Gradient,
}

impl std::fmt::Display for SearchMethod {
    /// As in a case file: `ga`, `pattern`, `gradient`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(match self {
            Self::Ga => "ga",
            Self::Pattern => "pattern",
            Self::Gradient => "gradient",
        })
    }
}

impl SearchMethod {
    /// Every method, in the order of the docs.
    pub const ALL: [SearchMethod; 3] = [SearchMethod::Ga, SearchMethod::Pattern, SearchMethod::Gradient];

    /// The method of a case-file name (`ga`, `pattern`, `gradient`).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.to_string() == name)
    }

    /// What a figure or report calls it.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Ga => "genetic algorithm",
            Self::Pattern => "pattern search",
            Self::Gradient => "gradient (Ipopt, exact sensitivities)",
        }
    }
}

/// Settings of eq. (37).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct PeriodicDesignSettings {
    /// Stiffness bounds, N·m/rad (the paper's 10² and 10⁴).
    pub stiffness_min: f64,
    pub stiffness_max: f64,
    /// Width of the equality band, as a fraction of `|δ_d|`.
    pub tolerance: f64,
    pub ga: GaSettings,
    pub pattern: PatternSettings,
    pub gradient: GradientSettings,
    /// The periodic response of every candidate.
    pub response: PeriodicSettings,
}

impl Default for PeriodicDesignSettings {
    fn default() -> Self {
        // The searches compare hundreds of responses through J and a 1 % displacement band, which
        // need far less than the single-simulation default (T_90 to 1e-6, about 8 times dearer).
        let integrator = Options { rtol: 1e-6, atol: 1e-8, ..Options::default() };
        let response = PeriodicSettings {
            max_periods: 6,
            settle_tolerance: 1e-3,
            samples_per_period: 200,
            integrator,
            ..Default::default()
        };
        Self {
            stiffness_min: 1e2,
            stiffness_max: 1e4,
            tolerance: 0.01,
            ga: GaSettings { population: 24, generations: 25, stall_generations: 10, ..Default::default() },
            pattern: PatternSettings {
                initial_mesh: 0.125,
                mesh_tolerance: 1e-3,
                max_evaluations: 600,
                ..Default::default()
            },
            gradient: GradientSettings::default(),
            response,
        }
    }
}

/// Where the gradient method starts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum GradientStart {
    /// Uniform springs that meet the equality (a root search on one common `log10 K`).
    #[default]
    Uniform,
    /// The case's springs (`design.stiffness`, clamped to the bounds).
    Case,
    /// The best point of the genetic algorithm (`settings.ga`), which runs first: the GA
    /// explores, Ipopt refines.
    Ga,
}

/// Settings of the gradient method.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct GradientSettings {
    /// Ipopt's `tol` on the scaled problem (objective over its start value, constraint over
    /// `|δ_d|`); > 0.
    pub tolerance: f64,
    /// Ipopt's iteration limit (≥ 1).
    pub max_iterations: usize,
    pub start: GradientStart,
    /// How the constraint's spring gradients are computed (default `adjoint`).
    pub sensitivities: Sensitivities,
    /// Ipopt's `mu_strategy` (default `adaptive`; docs/dynamics.md, "Eq. (37) by gradients", gives
    /// the measurements behind the default).
    pub barrier_strategy: spine_ipopt::BarrierStrategy,
}

impl Default for GradientSettings {
    fn default() -> Self {
        Self {
            tolerance: 1e-6,
            max_iterations: 100,
            start: GradientStart::Uniform,
            sensitivities: Sensitivities::Adjoint,
            barrier_strategy: spine_ipopt::BarrierStrategy::Adaptive,
        }
    }
}

impl GradientSettings {
    /// The fields in range, or the first that is not.
    pub fn validate(&self) -> Result<(), spine_check::FieldError> {
        let t = self.tolerance;
        require((1e-12..=0.1).contains(&t), "tolerance", || format!("must be in [1e-12, 0.1], got {t}"))?;
        let m = self.max_iterations;
        require((1..=10_000).contains(&m), "max_iterations", || format!("must be in 1..=10000, got {m}"))?;
        Ok(())
    }
}
