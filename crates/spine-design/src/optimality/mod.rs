//! The optimality core of eq. (33): what the certificate ([`crate::certificate`]) and the
//! sensitivities ([`crate::sensitivity`]) both read at a first-order point, below both, so that
//! neither reaches into the other.
//!
//! * [`active_set`]: which bounds hold at the point, strictly or weakly, read from the
//!   primal-dual solution ([`active_set::ActiveSet`]).
//! * `point`: the NLP evaluated at the point (values, first derivatives, bounds).
//! * `system`: the Hessian of the Lagrangian and the Jacobian there (`Matrices`), and the KKT
//!   matrix reduced to the free variables and the active rows, factorised once with its inertia
//!   `(n₊, n₋, n₀)` (`ActiveSystem`), which certifies second-order sufficiency.
//! * `smallest_singular_value`: LICQ's measure, the smallest singular value of the active rows'
//!   Jacobian by bidiagonalisation.
//!
//! The polish (the point solved again tightly, so that its active set can be read) is a solve
//! and sits with the solve's stages ([`crate::solve::polish`]).

pub mod active_set;
pub(crate) mod point;
mod smallest_singular_value;
pub(crate) mod system;
