//! The physical situation every problem shares: a chain with its loads.

use crate::{Chain, LinkLoads, NodalLoads};
use serde::{Deserialize, Serialize};

/// A chain with its loads: the passive load (transverse nodal forces, N; self-weight comes from the
/// chain's masses and gravity) and the actuation added on top of it (the axial force at the end
/// node, N). The static problem, the design problem of eq. (33) and the dynamic problem each embed
/// one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Structure {
    /// Spans `a_i`, link masses and gravity.
    pub chain: Chain,
    /// The passive nodal load, N.
    pub passive: NodalLoads,
    /// The actuation added to the passive load, N.
    pub actuation: NodalLoads,
}

impl Structure {
    pub fn n_links(&self) -> usize {
        self.chain.n_links()
    }

    /// Link load resultants of the passive load, self-weight included (the load of `θ1`).
    pub fn passive_loads(&self) -> LinkLoads {
        LinkLoads::from_nodal(&self.chain, &self.passive, true)
    }

    /// Link load resultants of the passive load plus the actuation, self-weight included (the load
    /// of `θ2`).
    pub fn total_loads(&self) -> LinkLoads {
        LinkLoads::from_nodal(&self.chain, &self.passive.plus(&self.actuation), true)
    }
}
