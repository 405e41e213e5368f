//! The barrier strategy, Ipopt's `mu_strategy`, as a typed setting.

use serde::{Deserialize, Serialize};

/// Ipopt's `mu_strategy`: how the barrier parameter decreases (case fields `solver.barrier_strategy`
/// of eq. (33) and `periodic_design.settings.gradient.barrier_strategy` of eq. (37)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum BarrierStrategy {
    /// Fiacco–McCormick: μ decreases once each barrier problem is solved well enough.
    #[default]
    Monotone,
    /// μ chosen at every iteration (Mehrotra's probing or a quality function).
    Adaptive,
}

impl BarrierStrategy {
    /// The option value Ipopt reads.
    pub fn name(self) -> &'static str {
        match self {
            Self::Monotone => "monotone",
            Self::Adaptive => "adaptive",
        }
    }
}
