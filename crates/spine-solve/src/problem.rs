//! The static problem of a design, apart from the solver.

use spine_model::{Design, LinkLoads, Structure};

/// The static problem of a design: the structure (chain, passive load, actuation) and the design
/// (`θ0`, `K`) whose equilibria `θ1` (passive) and `θ2` (passive + actuation) are sought.
#[derive(Clone, Debug)]
pub struct StaticProblem {
    pub structure: Structure,
    pub design: Design,
}

impl StaticProblem {
    /// Link load resultants of the passive load (self-weight included).
    pub fn passive_loads(&self) -> LinkLoads {
        self.structure.passive_loads()
    }

    /// Link load resultants of passive load plus actuation.
    pub fn total_loads(&self) -> LinkLoads {
        self.structure.total_loads()
    }
}
