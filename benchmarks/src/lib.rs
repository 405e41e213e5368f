//! Benchmark fixtures: the scaled family of `PEERS.md` (`s = N/10`, `K = 10³ s²` N·m/rad,
//! `P_X = −400 s` N, `P_Y = −5` N per node, `L_x = 1` m) on a symmetric arch of amplitude 0.4 rad.

use spine_model::fixtures::{arch, uniform_loads};
use spine_solve::StaticProblem;

/// The benchmark problem for `n` links.
pub fn scaled_arch(n: usize) -> StaticProblem {
    let s = n as f64 / 10.0;
    let (mut chain, design) = arch(n, 1.0, 0.4, 1e3 * s * s);
    chain.masses = vec![0.5 / n as f64; n];
    let mut passive = uniform_loads(n, -5.0, 0.0);
    passive.p_x = vec![0.0; n + 1];
    StaticProblem { chain, design, passive, actuation: uniform_loads(n, 0.0, -400.0 * s) }
}
