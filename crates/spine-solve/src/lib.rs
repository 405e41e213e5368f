//! # spine-solve: solvers for the flexible spine
//!
//! * [`linalg`]: the `O(N)` solve of the bordered tridiagonal equilibrium Jacobian, with a sparse
//!   LU
//!   fallback (faer) when elimination without pivoting is unsafe.
//! * [`stability`]: the stability certificate, the smallest eigenvalue of the Hessian of
//!   `U + V − λΦ` projected on the tangent space of `Φ = 0`, found in `O(N)` per probe by Sturm
//!   counts on the bordered matrix.
//! * [`equilibrium`]: Newton on `(θ, λ)` with load continuation, reporting the status of the path
//!   (stable, lost stability at a bifurcation, limit point, Newton failure).
//! * [`twolink`]: the exact two-link design of Sec. 3 solved with the general `N`-link code.
//!
//! Solvers return result structs and print nothing.
//!
//! Further modules:
//!
//! * `arclength`: Pseudo-arclength continuation where load control stalls.
//! * `corrector`: A load path and Newton's method on it: the corrector shared by load and arclength
//!   continuation.
//! * `options`: Options of Newton and of the load continuation, each checked where it is defined.
//! * [`problem`]: The static problem of a design, apart from the solver.
//! * `solution`: What an equilibrium solve reports: its status, the solution with its stability
//!   certificate, and the solver's counts.
//!
//! ```
//! use spine_model::fixtures::{arch, uniform_loads};
//! use spine_model::Structure;
//! use spine_solve::{solve_static, ContinuationOptions, StaticProblem};
//! // A 10-link arch, −5 N per node (passive), then −200 N pushing the sliding end (actuation).
//! let (chain, design) = arch(10, 1.0, 0.4, 1000.0);
//! let structure = Structure { chain, passive: uniform_loads(10, -5.0, 0.0), actuation: uniform_loads(10, 0.0, -200.0) };
//! let solution = solve_static(&StaticProblem { structure, design }, &ContinuationOptions::default());
//! let loaded = solution.loaded.expect("the passive path reached its load");
//! assert!(solution.passive.status.is_stable() && loaded.status.is_stable());
//! assert!(loaded.residual_norm < 1e-9); // N·m
//! assert!(loaded.stability.min_eigenvalue.unwrap() > 0.0); // the certificate
//! assert!(solution.end_displacement.unwrap() < 0.0); // the end moved toward the base
//! ```
#![forbid(unsafe_code)]

mod arclength;
mod corrector;
pub mod equilibrium;
pub mod linalg;
mod options;
pub mod problem;
mod solution;
pub mod stability;
pub mod twolink;

pub use corrector::LoadPath;
pub use equilibrium::{solve_path, solve_static, StaticSolution};
pub use options::{ContinuationOptions, MAX_CONTINUATION_STEPS, MAX_NEWTON_ITERATIONS};
pub use problem::StaticProblem;
pub use solution::{EquilibriumSolution, EquilibriumStatus, SolveStats};
pub use stability::Stability;
