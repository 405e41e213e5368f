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

/// The scaled step case of `docs/PEERS.md` ("Dynamics"), simulated by `just bench-dynamics` and
/// its scipy peer: over 1 m, arch `θ0` of amplitude 0.3 rad, `K = 1000 N/5` N·m/rad at every joint
/// but the slider's (0), `C = 20 N/5` N·m·s/rad at every joint, `0.5/N` kg per link (no gravity),
/// `−50/N` N at every node and `−400` N at the end, as a step at `t = 0`. Springs and dampers grow
/// with `N` so that the chain keeps its overall stiffness and damping as it is refined.
pub fn peer_step_problem(n_links: usize) -> DynamicProblem {
    let scale = n_links as f64 / 5.0;
    let (mut chain, design) = arch(n_links, 1.0, 0.3, 1000.0 * scale);
    chain.masses = vec![0.5 / n_links as f64; n_links];
    chain.gravity = 0.0;
    DynamicProblem {
        structure: Structure {
            chain,
            passive: uniform_loads(n_links, -50.0 / n_links as f64, 0.0),
            actuation: uniform_loads(n_links, 0.0, -400.0),
        },
        design,
        damping: vec![20.0 * scale; n_links + 1],
    }
}

/// The chain of the periodic-load tests: the arch of [`spine_model::fixtures::arch`] over 1 m
/// (amplitude 0.3 rad, K = 2000 N·m/rad at every joint, the end spring too), 0.5 kg per link,
/// −20 N per node, −1500 N at the end, 20 N·m·s/rad at every joint.
pub fn periodic_problem(n_links: usize) -> DynamicProblem {
    let (mut chain, mut design) = arch(n_links, 1.0, 0.3, 2000.0);
    design.stiffness[n_links] = 2000.0;
    chain.masses = vec![0.5; n_links];
    DynamicProblem {
        structure: Structure {
            chain,
            passive: uniform_loads(n_links, -20.0, 0.0),
            actuation: uniform_loads(n_links, 0.0, -1500.0),
        },
        design,
        damping: vec![20.0; n_links + 1],
    }
}
