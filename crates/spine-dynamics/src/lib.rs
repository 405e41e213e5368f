//! # spine-dynamics: the flexible spine in motion
//!
//! * [`eom`]: the constrained equations of motion (eq. (6), `docs/model.md` "Dynamics"), generic
//!   over
//!   num-dual numbers: mass matrix, centrifugal terms, springs, dampers, loads, end constraint.
//! * [`integrator`]: Radau IIA of order 5 (default) and TR-BDF2, L-stable and error-controlled,
//!   with projection onto `Φ = 0, Φ̇ = 0`, dense output, event location, forward sensitivities and
//!   the discrete adjoint of the Radau steps ([`integrator::adjoint`]).
//! * [`newton`]: the integrator's Newton matrices for the chain in `O(N)`, real and complex.
//! * [`system`]: the equations of motion as an ODE in `(θ, θ̇)`, Jacobians by forward AD.
//! * [`forcing`]: the time profile of the axial force (step, pulse train, sinusoid).
//! * [`articulated`]: the chain's articulated-body recursion, the `O(N)` right-hand side.
//! * [`rates`]: the accelerations and their derivatives by that recursion ([`system`]'s fast path).
//! * [`linearization`]: the equations of motion linearised about an equilibrium (modes, damping
//!   ratios).
//! * [`ode`]: the ODE interface the integrators solve.
//! * [`parameters`]: which parameters a simulation differentiates with respect to.
//! * [`vjp`]: the accelerations' vector–Jacobian products in `O(N)` (the adjoint's).
//! * [`response`]: the step response (`T_90`, `Δ∞`, the static ends it moves between, drift).
//! * [`periodic`]: the settled response to a periodic axial force.
//! * [`sample`]: one sample of the motion (time, load factor, end displacement, angles).
//! * [`overdamping`]: whether a step response is over-damped (no turn back, no overshoot).
//! * `fixtures` (feature `testing`): chains with their responses for tests, benchmarks and
//!   examples.
//!
//! The designs built on these motions (eq. (35) and eq. (37)) are in the crate
//! `spine-dynamic-design`.
//!
//! Index reduction: the constraint is differentiated twice (`Φ̈ = 0`, index 1) and every accepted step
//! is projected back onto `Φ = 0` and `Φ̇ = 0`, so the drift does not accumulate.
//!
//! Further modules:
//!
//! * `cholesky`: Dense Cholesky factorisation and solve, generic over `Scalar` (dual numbers carry
//!   through): the reference path of the mass-matrix solves in `crate::eom`.
//! * `end_x`: The end's X displacement `X_{N+1} − L_x` on a trajectory of one ODE: its value and
//!   the first time it reaches a level (an event on the steps).
//! * `eq36`: Eq. (36)'s first-order model of the step response, fitted to a run
//!   (`fit_first_order`), and its own reading of the rise.
//!
//! ```
//! use spine_dynamics::fixtures::arch_problem;
//! use spine_dynamics::{step_response, StepSettings};
//! // A 5-link arch (0.5 kg links, K = 1000 N·m/rad) with dampers of 50 N·m·s/rad, −400 N step at t = 0.
//! let problem = arch_problem(5, 50.0);
//! let settings = StepSettings { t_end: 2.0, ..StepSettings::default() };
//! let r = step_response(&problem, &settings, false).unwrap();
//! assert!(r.rise_time.unwrap() > 0.0); // T_90, s
//! assert!(r.drift.max_constraint < 1e-12); // the projection keeps Φ = 0 at every step
//! assert!((r.ends.loaded_displacement - r.ends.passive_displacement - r.delta_inf).abs() < 1e-12);
//! ```
#![forbid(unsafe_code)]

pub mod articulated;
mod cholesky;
mod end_x;
pub mod eom;
pub mod eq36;
#[cfg(any(test, feature = "testing"))]
pub mod fixtures;
pub mod forcing;
pub mod integrator;
pub mod linearization;
pub mod newton;
pub mod ode;
pub mod parameters;
pub mod rates;
pub mod sample;
pub mod system;
pub mod vjp;

pub use eom::Dynamics;
pub use forcing::Forcing;
pub use integrator::{integrate, Options, Outcome, Stats, Trajectory, DEFAULT_ATOL, DEFAULT_RTOL};
pub use system::{Parameters, SpineOde};
pub mod overdamping;
pub mod periodic;
pub mod response;

pub use periodic::{periodic_response, PeriodicResponse, PeriodicSettings};
pub use response::{step_response, DynamicProblem, DynamicsError, StepResponse, StepSettings};
