//! The continuum the chain discretises: a link chain with torsional springs is a finite-difference
//! model of a bending rod, and this crate gives the rod.
//!
//! - [`Rod`]: a uniform rod with the chain's boundary conditions and loads, and
//!   [`Rod::chain`], the chain of `N` links that converges to it (`K = EI/a` inside, `2EI/a` at
//!   the ends; derivation in [`rod`]);
//! - [`Elastica`]: Euler's elastica with the same loads, by Chebyshev collocation (spectrally
//!   accurate, independent of the chain's code);
//! - [`chain_critical_load`]: where the straight chain's stability certificate crosses zero,
//!   against Euler's `4π²EI/L²`;
//! - [`node_error`]: a chain equilibrium's nodes against the elastica at the same arclength.
//!
//! ```
//! use spine_continuum::{chain_critical_load, Rod};
//! let rod = Rod { length: 1.0, bending_stiffness: 10.0, end_force: 0.0, transverse_load: 0.0,
//!                 mass_per_length: 0.0, gravity: 9.81 };
//! let euler = rod.euler_critical_load();
//! let (e100, e200) = ((chain_critical_load(&rod, 100) - euler) / euler, (chain_critical_load(&rod, 200) - euler) / euler);
//! assert!((e100 / e200 - 4.0).abs() < 0.05, "second order: {e100:e} {e200:e}");
//! ```
#![forbid(unsafe_code)]

pub mod buckling;
pub mod chebyshev;
pub mod compare;
pub mod convergence;
pub mod design;
pub mod design_figure;
pub mod design_study;
pub mod elastica;
pub mod rod;

pub use buckling::{chain_critical_load, straight_min_eigenvalue};
pub use compare::{critical_load, loaded, on_branch, CriticalLoad, NodeComparison};
pub use elastica::{Elastica, ElasticaError};
pub use rod::Rod;

/// The largest distance between the chain's nodes and the elastica's points at the same arclength
/// (`s_j = (j − 1) a`), m. `theta` are the chain's link angles (straight design, spans `L/N`).
pub fn node_error(elastica: &Elastica, theta: &[f64]) -> f64 {
    let n = theta.len();
    let a = elastica.rod.length / n as f64;
    let (mut x, mut y, mut worst) = (0.0f64, 0.0f64, 0.0f64);
    for (j, t) in theta.iter().enumerate() {
        x += a * t.cos();
        y += a * t.sin();
        let (xe, ye) = elastica.position_at((j + 1) as f64 * a);
        worst = worst.max((x - xe).hypot(y - ye));
    }
    worst
}
