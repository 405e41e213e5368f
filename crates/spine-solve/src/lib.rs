//! # spine-solve: solvers for the flexible spine
//!
//! * [`linalg`]: the `O(N)` solve of the bordered tridiagonal equilibrium Jacobian, with a sparse LU
//!   fallback (faer) when elimination without pivoting is unsafe.
//! * [`stability`]: the stability certificate, the smallest eigenvalue of the Hessian of
//!   `U + V − λΦ` projected on the tangent space of `Φ = 0`, found in `O(N)` per probe by Sturm
//!   counts on the bordered matrix.
//! * [`equilibrium`]: Newton on `(θ, λ)` with load continuation, reporting the status of the path
//!   (stable, lost stability at a bifurcation, limit point, Newton failure).
//! * [`twolink`]: the exact two-link design of Sec. 3 solved with the general `N`-link code.
//!
//! Solvers return result structs and print nothing.
#![forbid(unsafe_code)]

pub mod equilibrium;
pub mod linalg;
pub mod problem;
pub mod stability;
pub mod twolink;

pub use equilibrium::{
    solve_path, solve_static, ContinuationOptions, EquilibriumSolution, EquilibriumStatus, LoadPath, OptionError,
    SolveStats, StaticSolution,
};
pub use problem::StaticProblem;
pub use stability::Stability;
