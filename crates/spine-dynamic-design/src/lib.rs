//! # spine-dynamic-design: the designs that need the spine in motion
//!
//! The static design of eq. (33) lives in `spine-design`; the two designs whose constraints are
//! measured on a simulated motion ([`spine_dynamics`]) live here:
//!
//! * [`damping`]: eq. (35), the dampers `C` for a target rise time `T_90 = T_d` at least `½ Σ C²`
//!   (Ipopt; the constraint's gradient `dT_90/dC` from one adjoint sweep of the plain run at the
//!   rise event).
//! * [`periodic_design`]: eq. (37), the springs `K` under a periodic axial force at least strain
//!   energy `U(θ1)`, with the settled motion reaching `δ_d`, by the paper's gradient-free searches
//!   (genetic algorithm, pattern search) or by Ipopt with exact gradients ([`periodic_gradient`]).
//! * [`periodic_gradient`]: eq. (37) by Ipopt with exact gradients: the envelope theorem at the
//!   minimising time, the gradients by the discrete adjoint of the whole periodic motion (or
//!   forward sensitivities), asked for at accepted points only.
//! * [`eq37_point`]: eq. (37)'s functions at one design, with their gradients.
//! * [`periodic_settings`]: the settings of eq. (37) and the choice of method ([`SearchMethod`]).
//! * [`error`]: why a design could not give a result ([`DynamicDesignError`]).
//! * `bracket`: the Illinois root bracketing both designs use for their uniform start.
//!
//! ```
//! use spine_dynamic_design::{design_damping, DampingSettings};
//! use spine_dynamics::fixtures::arch_problem;
//! // Eq. (35) on a 3-link arch (dampers start at 20 N·m·s/rad): reach 90 % of the step in 0.1 s.
//! let problem = arch_problem(3, 20.0);
//! let r = design_damping(&problem, 0.1, &DampingSettings::default()).unwrap();
//! assert!(r.converged, "{}", r.status);
//! assert!(r.rise_time_error.unwrap() < 5e-3); // |T_90 − T_d| / T_d
//! ```
#![forbid(unsafe_code)]

mod bracket;
pub mod damping;
pub mod eq37_point;
pub mod error;
pub mod periodic_design;
pub mod periodic_gradient;
pub mod periodic_settings;

pub use damping::{design_damping, DampingDesign, DampingSettings, DampingStatus, RISE_TIME_ACCEPTANCE};
pub use error::DynamicDesignError;
pub use periodic_design::{design_periodic, PeriodicDesign, PeriodicDesignSettings, SearchMethod};
