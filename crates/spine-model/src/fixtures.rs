//! Reference structures shared by tests, benchmarks and examples.
//!
//! Deterministic: the random fixtures use a fixed-seed generator of their own (SplitMix64), so the
//! same seed gives the same structure on every machine.

use crate::rng::SplitMix64;
use crate::{Chain, Design, LinkLoads, NodalLoads, State};

/// A symmetric arch over `L_x` with `N` equal spans: `θ0_i = amplitude · cos(π (i + ½) / N)`, so
/// `Σ tan θ0_i = 0` (the unloaded end is on the X axis) and the middle is highest.
pub fn arch(n_links: usize, length_x: f64, amplitude: f64, stiffness: f64) -> (Chain, Design) {
    let chain = Chain::uniform(n_links, length_x);
    let theta0 =
        (0..n_links).map(|i| amplitude * (std::f64::consts::PI * (i as f64 + 0.5) / n_links as f64).cos()).collect();
    let mut k = vec![stiffness; n_links + 1];
    k[n_links] = 0.0;
    (chain, Design { theta0, stiffness: k })
}

/// Uniform transverse force `p_y` (N) at every node and an axial force `p_x` (N) at the end.
pub fn uniform_loads(n_links: usize, p_y: f64, p_x: f64) -> NodalLoads {
    let mut loads = NodalLoads { p_x: vec![0.0; n_links + 1], p_y: vec![p_y; n_links + 1] };
    loads.p_x[n_links] = p_x;
    loads
}

/// A random chain, design, load and state (not an equilibrium) for derivative tests: spans in
/// `[0.05, 0.2]` m, masses in `[0, 0.5]` kg, `θ0` in `[−0.5, 0.5]` rad, `K` in `[10², 10⁴]` N·m/rad,
/// nodal forces in `[−50, 50]` N, `θ = θ0 + [−0.3, 0.3]` rad, `λ` in `[−100, 100]` N.
pub fn random_problem(n_links: usize, seed: u64) -> (Chain, Design, LinkLoads, State) {
    let mut rng = SplitMix64::new(seed);
    let spans = (0..n_links).map(|_| rng.uniform(0.05, 0.2)).collect();
    let masses = (0..n_links).map(|_| rng.uniform(0.0, 0.5)).collect();
    let chain = Chain { spans, masses, gravity: crate::STANDARD_GRAVITY };
    let theta0: Vec<f64> = (0..n_links).map(|_| rng.uniform(-0.5, 0.5)).collect();
    let stiffness = (0..=n_links).map(|_| rng.uniform(1e2, 1e4)).collect();
    let nodal = NodalLoads {
        p_x: (0..=n_links).map(|_| rng.uniform(-50.0, 50.0)).collect(),
        p_y: (0..=n_links).map(|_| rng.uniform(-50.0, 50.0)).collect(),
    };
    let loads = LinkLoads::from_nodal(&chain, &nodal, true);
    let theta = theta0.iter().map(|t| t + rng.uniform(-0.3, 0.3)).collect();
    let state = State { theta, lambda: rng.uniform(-100.0, 100.0) };
    (chain, Design { theta0, stiffness }, loads, state)
}
