//! Reference problems shared by tests, examples and benchmarks.

use crate::response::DynamicProblem;
use spine_model::fixtures::{arch, uniform_loads};
use spine_model::Structure;

/// The arch of [`spine_model::fixtures::arch`] over 1 m (amplitude 0.4 rad, K = 1000 N·m/rad, no
/// end spring) with 0.5 kg per link, −5 N per node, −400 N at the end, and `damping` N·m·s/rad at
/// every joint.
pub fn arch_problem(n_links: usize, damping: f64) -> DynamicProblem {
    let (mut chain, design) = arch(n_links, 1.0, 0.4, 1000.0);
    chain.masses = vec![0.5; n_links];
    DynamicProblem {
        structure: Structure {
            chain,
            passive: uniform_loads(n_links, -5.0, 0.0),
            actuation: uniform_loads(n_links, 0.0, -400.0),
        },
        design,
        damping: vec![damping; n_links + 1],
    }
}
