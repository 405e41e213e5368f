//! The polish: an optimum re-solved tightly, the tight re-solve of the certificate (stage 4 of a
//! design run, [`crate::solve`]) and the start of every sensitivity and sweep. At Ipopt's default
//! tolerance the complementarity products `z·gap` end near 1e-10, so a bound whose multiplier is small (a
//! stiffness at its upper bound where `J` hardly depends on it: `z` ≈ 7e-6) cannot be told from an
//! inactive one with a small gap; re-solved from the optimum with `tol` 1e-12 and the barrier
//! started at 1e-11, the products fall to about 1e-14 and the two separate.

use super::ipopt::DesignError;
use super::run::run_solver;
use crate::problem::DesignProblem;
use crate::refine::{Refine, RefineMode};
use crate::settings::{ExtraOption, Formulation, SolverSettings};
use crate::solver_run::SolverRun;
use spine_model::Design;

/// Ipopt's `tol` of the polishing solve.
pub const POLISH_TOLERANCE: f64 = 1e-12;

/// The case's settings with the polishing tolerance ([`POLISH_TOLERANCE`], on the constraints
/// too where the case's is looser) and no mesh sequencing: the polish's, the certificate's warm
/// tight re-solve's and every corrector's of a followed sweep (so that the active set can be read
/// and differentiated).
pub(crate) fn tight_settings(settings: &SolverSettings) -> SolverSettings {
    let mut tight = settings.clone();
    tight.tolerance = POLISH_TOLERANCE;
    tight.constraint_tolerance = settings.constraint_tolerance.min(POLISH_TOLERANCE);
    tight.refine = Refine::Mode(RefineMode::Off);
    tight
}

/// Eq. (33) in the full space from `optimum` with the tight settings above (the same problem and
/// state form; no mesh sequencing).
pub fn polish(problem: &DesignProblem, optimum: &Design, settings: &SolverSettings) -> Result<SolverRun, DesignError> {
    let mut tight = tight_settings(settings);
    for (name, value) in [("mu_init", 1e-11), ("bound_push", 1e-12), ("bound_frac", 1e-12)] {
        tight.ipopt_options.insert(name.into(), ExtraOption::Num(value));
    }
    run_solver(problem, optimum, Formulation::Full, &tight, &mut |_| true)
}
