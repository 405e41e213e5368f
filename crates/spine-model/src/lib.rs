//! # spine-model: the physics of a planar flexible spine
//!
//! An `N`-link planar chain of rigid links. Node 1 (index 0 here) is the fixed base at the origin;
//! node `N+1` (index `N`) slides on the X axis. Torsional springs `K_1..K_{N+1}` join ground and
//! link 1, consecutive links, and link `N` and the slider. Conventions follow `docs/model.md`:
//!
//! * `θ_i` is the absolute angle of link `i` from +X, counter-clockwise positive (rad).
//! * Each link has a fixed horizontal span `a_i` (m); its length follows the unloaded design,
//!   `L_i = a_i / cos θ0_i` (paper, Sec. 5 "length constraint").
//! * Loads are nodal forces in newtons, positive along +X / +Y; gravity `g` (m/s²) acts along −Y.
//! * Stiffness in N·m/rad, moments in N·m, energies in J.
//!
//! Indexing in code is zero-based: link `i` (0..N) runs from node `i` to node `i+1`; spring `i`
//! (0..=N) sits at node `i`, between link `i-1` (or the ground) and link `i` (or the slider).
//!
//! Every physical function is written once, generic over [`Scalar`] (any
//! `num_dual::DualNum<Primitive = f64> + Copy`, including plain `f64`), so exact first and second
//! derivatives come from forward-mode automatic differentiation. [`jacobian`] assembles the sparse
//! Jacobians element by element with small fixed-size dual numbers, at a cost linear in `N`.
//!
//! This crate holds no solver: see `spine-solve`.
//!
//! Further modules:
//!
//! * [`energy`]: Energies: strain energy of the springs (eq. (31)) and potential of the loads (eq.
//!   (3), with the sign of gravity corrected: see `docs/errata.md`).
//! * [`finite_difference`]: Central finite differences of the equilibrium residual (eq. (5)),
//!   element by element: the third way to get the state Jacobian, beside forward AD
//!   (`crate::jacobian`) and the paper's hand-derived entries (`crate::hand`).
//! * [`hand`]: Derivatives written by hand from the paper's Appendix I (eqs. (46)–(53)), corrected
//!   for the link length `L_i = a_i / cos θ0_i` of Sec. 5 (errata E7).
//! * [`jet`]: A branch-free forward-mode dual number of fixed width ([`jet::Jet`]), and the few
//!   operations the joint kernels use ([`jet::Elementary`], which every [`Scalar`] implements).
//! * [`kinematics`]: Geometry: link lengths, node positions (eq. (1)) and the end constraint `Φ`
//!   (eq. (2)).
//! * [`local`]: Local elements: scalar functions of a few variables, written once over `Scalar`,
//!   whose gradients and Hessians come from forward AD with fixed-size duals.
//! * [`rng`]: A seeded random generator of our own, so that seeded runs are the same everywhere:
//!   the workspace's one generator, `spine_rng::SplitMix64`.
//! * [`structure`]: The physical situation every problem shares: a chain with its loads.
//! * [`twolink`]: The two-link analysis of Sec. 3, in closed form.
//! * `chain`: The chain (fixed geometry and masses), the design `(θ0, K)` and a state `(θ, λ)`.
//! * `fixtures`: Reference structures shared by tests, benchmarks and examples.
//! * `loads`: Loads: nodal forces and their per-link resultants (eq. (48) of the paper).
//! * `residual`: The equilibrium residual (paper eqs. (5), (33)), written once for every number
//!   type.
//! * `sparse`: Sparse matrix containers for the Jacobians: the bordered tridiagonal matrix of the
//!   equilibrium equations and a plain coordinate (triplet) matrix.
//! * `tangent`: A branch-free hyper-dual number for the rates of an element's gradient along a
//!   parameter: `ε₁` over the element's `M` slots, `ε₂` one direction in its constants (a load, a
//!   span, `C_K` moving with a parameter of the problem).
//!
//! ```
//! use spine_model::fixtures::{arch, uniform_loads};
//! use spine_model::{jacobian, residual, LinkLoads, State};
//! // A 5-link arch over L_x = 1 m (θ0 = 0.4 cos(π(i + ½)/5) rad), springs of 1000 N·m/rad.
//! let (chain, design) = arch(5, 1.0, 0.4, 1000.0);
//! let loads = LinkLoads::from_nodal(&chain, &uniform_loads(5, -10.0, 0.0), true);
//! // At the unloaded shape the springs store nothing; the residual of eq. (5) is the load's moment.
//! let state = State::unloaded(&design);
//! let r = residual::equilibrium_residual(&chain.spans, &design, &loads, &state);
//! assert_eq!(r.len(), 6); // five joint rows and the end constraint Φ = 0
//! assert!(r[5].abs() < 1e-15); // the arch closes on the X axis
//! // The exact state Jacobian by forward AD, O(N), in a bordered tridiagonal layout.
//! let (r_ad, jac) = jacobian::residual_and_state_jacobian(&chain.spans, &design, &loads, &state);
//! assert_eq!(r_ad, r);
//! assert_eq!(jac.to_sparse().to_dense().len(), 6);
//! ```
#![forbid(unsafe_code)]

pub mod chain;
pub mod energy;
pub mod finite_difference;
#[cfg(any(test, feature = "testing"))]
pub mod fixtures;
pub mod hand;
pub mod jacobian;
pub mod jet;
pub mod kinematics;
pub mod loads;
pub mod local;
pub mod residual;
pub mod rng;
pub mod sparse;
pub mod structure;
pub mod tangent;
pub mod twolink;

pub use chain::{Chain, Design, State};
pub use loads::{LinkLoads, NodalLoads};
pub use structure::Structure;

/// The number types every physical function accepts: `f64` and num-dual's dual numbers.
pub trait Scalar: num_dual::DualNum<Primitive = f64> + Copy {}
impl<T: num_dual::DualNum<Primitive = f64> + Copy> Scalar for T {}

/// Standard gravity, m/s², used when a case does not give its own value.
pub const STANDARD_GRAVITY: f64 = 9.81;
