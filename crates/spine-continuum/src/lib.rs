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
//! Further modules:
//!
//! * `buckling`: The critical axial load of the straight chain, where its stability certificate's
//!   smallest eigenvalue crosses zero, against Euler's.
//! * `chebyshev`: Chebyshev–Gauss–Lobatto collocation on an interval `[0, L]`: the nodes, the
//!   differentiation matrix, Clenshaw–Curtis weights, and a function's Chebyshev series with its
//!   integral, evaluated anywhere (Trefethen, *Spectral Methods in MATLAB*, ch.
//! * `compare`: The chain against the rod it discretises, at a number of links `N`: the critical
//!   load against Euler's, and equilibria against the elastica at the same arclength.
//! * `convergence`: The convergence study: the chain against the rod for a ladder of `N`, as a
//!   table and a figure.
//! * `design`: Eq. (33) posed for one physical rod, so that the chain of any `N` discretises the
//!   same design problem and its optima can be followed as `N → ∞`.
//! * `design_figure`: The figure of the design study: the optimal profiles of several `N` on one
//!   axis each, and `J*(N)` on a log axis with the Richardson limit.
//! * `design_study`: Eq. (33) for one rod (`RodDesign`) at a ladder of `N`, each level warm-started
//!   from the previous optimum: `J*(N)`, the optimal `θ0(x)` and `EI(x)`, the active-bound pattern
//!   of `EI` and its number of switches, and a Richardson estimate of `J*∞`.
//! * `elastica`: Euler's elastica with the rod's loads, solved by Chebyshev collocation: the
//!   continuum reference the chain converges to.
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
