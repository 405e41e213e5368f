//! The static design problem of the paper, eq. (33): find the unloaded shape `θ0` and the joint
//! stiffnesses `K` that store the least strain energy under the passive load while the end moves
//! by `δ_d` under the added axial force.
//!
//! * [`problem`]: the problem data ([`DesignProblem`], [`DesignBounds`]), apart from any solver;
//!   [`objective`]: what it minimises, the paper's `J` or a built-in criterion ([`Objective`]).
//! * [`full_space`]: the simultaneous form for Ipopt with exact sparse Jacobian and Hessian from
//!   forward AD of the model's elements ([`assembly`]).
//! * [`reduced_space`] and [`adjoint`]: the paper's nested form, equilibria by continuation and
//!   gradients by the hand-derived adjoint.
//! * [`settings`]: the settings of a run, and the preset that solves like the paper's optimiser.
//! * [`solve`]: **the solve, its stages in their order** (refinement ladder, Ipopt, check,
//!   certificate, tight re-solve, escape along a flat or descending direction), and its one entry
//!   [`solve::Solver`]; [`solver_run`]: what Ipopt returned, before the check; [`result`]: the
//!   checked result.
//! * [`optimality`]: the active set, the KKT matrices and their inertia at a first-order point,
//!   which the [`certificate`] (is it a minimum?) and the [`sensitivity`] (how does it move?) both
//!   read.
//! * [`multistart`]: seeded feasible starts and clustering of the local optima.
//! * [`knife_edge`]: starts moved by a tiny seeded amount, which show whether the optimum a start
//!   reaches is decided by rounding.
//! * [`refine`]: mesh sequencing, coarse-to-fine warm starts for long chains.
//! * [`certificate`]: the second-order certificate of an optimum.
//! * [`sensitivity`]: derivatives of an optimum with respect to the problem's parameters.
//!
//! Further modules:
//!
//! * [`census`]: How complete a multi-start's census of local optima is: a Bayesian estimate in the
//!   manner of Boender and Rinnooy Kan.
//! * `ipopt_allowed`: The Ipopt options a case file may set in `solver.ipopt_options`, and their
//!   check: numerical settings only, one way to set each.
//! * `layout`: Where each quantity of eq. (33) sits in the full-space variable and constraint
//!   vectors (the table of `crate::full_space`).
//! * `solver_report`: Ipopt's account of a design run: status, iterations, infeasibilities, counts,
//!   times, and the levels of a mesh-sequenced run.
//! * [`start_point`]: The full space's start point in named parts, for a peer model (a CasADi
//!   script) to start from the point the solve hands Ipopt.
//! * [`sweep`]: Sweeps that follow one optimum of eq. (33) along a parameter `p` (a load, `δ_d`,
//!   `C_K`, a bound, …): predictor–corrector continuation of the optimum branch `x*(p)`.
//! * `violations`: How far a design result is from satisfying eq. (33): each part of the problem
//!   recomputed from the reported design and states, and what Ipopt's tolerances allow.
//! * `criterion`: The objective's elements in the full space, one group per criterion
//!   (`crate::Objective`): the paper's strain energies of the `N + 1` springs at `θ1`, the springs'
//!   stiffnesses, the powers of the joint moments at `θ1` and `θ2`, or the compliance load's work
//!   on each link at `θ3`.
//! * `fixtures`: Ready-made design problems for tests, examples and benchmarks (the case files are
//!   the user-facing way to state a problem).
//! * `log_variables`: Positive variables handed to Ipopt by their logarithm: `u = ln x`, so that a
//!   Newton step changes such a variable by a bounded factor instead of a bounded amount.
//! * `numbers`: The numbers of eq. (33)'s NLP that come from the problem rather than from its
//!   variables: the spans, the load resultants of both load states, `C_K`, the end target `L_x +
//!   δ_d` and the bounds, in any number type.
//! * `variables`: How the full space's quantities are Ipopt's variables (case fields
//!   `solver.state_variables` and `solver.spring_variables`): the same NLP after a change of
//!   variables, with the same KKT points, and a different path for Ipopt.
//! * `warnings`: What can make a design result not clean, each with its numbers.
//!
//! ```
//! use spine_design::fixtures::{paper_five_link_start, paper_problem};
//! use spine_design::settings::{Formulation, SolverPreset, SolverSettings};
//! use spine_design::solve::Solver;
//! // The paper's 5-link case (Sec. 5.1): −10 N per node, −400 N at the end, δ_d = −0.02 m, C_K = 1.
//! let problem = paper_problem(5, -10.0, -400.0, -0.02, 1.0);
//! let solver = Solver::new(SolverPreset::Exact, Formulation::Full, &SolverSettings::default());
//! let result = solver.solve(&problem, &paper_five_link_start(), &mut |_| true).unwrap();
//! assert!(result.is_clean(), "{} {:?}", result.solver.status, result.warnings);
//! assert!((result.end_displacement.unwrap() - (-0.02)).abs() < 1e-8); // m
//! assert!(result.passive.as_ref().unwrap().stability.stable);
//! ```
#![forbid(unsafe_code)]

pub mod adjoint;
pub mod assembly;
pub mod census;
pub mod certificate;
mod criterion;
#[cfg(any(test, feature = "testing"))]
pub mod fixtures;
pub mod full_space;
mod ipopt_allowed;
pub mod knife_edge;
mod layout;
pub mod log_variables;
pub mod multistart;
mod numbers;
pub mod objective;
pub mod optimality;
pub mod problem;
pub mod reduced_space;
pub mod refine;
pub mod result;
pub mod sensitivity;
pub mod settings;
pub mod solve;
mod solver_report;
pub mod solver_run;
pub mod start_point;
pub mod sweep;
pub mod variables;
mod violations;
mod warnings;

pub use numbers::ProblemTangent;
pub use objective::Objective;
pub use problem::{DesignBounds, DesignProblem};
pub use result::DesignResult;
pub use settings::{BarrierStrategy, Formulation, ScalingMethod, SolverPreset, SolverSettings};
pub use solve::ipopt::DesignError;
pub use solver_run::SolverRun;
pub use warnings::{DesignWarning, LoadCase};
