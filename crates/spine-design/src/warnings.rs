//! What can make a design result not clean, each with its numbers.

use serde::Serialize;
use spine_solve::EquilibriumStatus;

/// Which equilibrium of eq. (33) (`θ3` only with the compliance criterion).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadCase {
    /// `θ1`, under the passive load.
    Passive,
    /// `θ2`, under the passive load plus the actuation.
    Loaded,
    /// `θ3`, under the compliance criterion's load case ([`crate::Objective::Compliance`]).
    Probe,
}

/// Why a design result is not clean.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignWarning {
    /// Ipopt ended without converging (its status).
    NotConverged { status: spine_ipopt::Status },
    /// An equilibrium of the final design is not stable (its smallest reduced-Hessian
    /// eigenvalue, N·m/rad, when it has one).
    Unstable { equilibrium: LoadCase, min_eigenvalue: Option<f64> },
    /// The final design has no equilibria on its load path.
    NoEquilibria,
    /// The optimiser's equilibria are not the ones reached by loading the design (largest angle
    /// differences, rad, and the statuses of the two paths).
    OffLoadPath {
        passive_difference: f64,
        loaded_difference: f64,
        passive_status: EquilibriumStatus,
        loaded_status: Option<EquilibriumStatus>,
    },
    /// The reported design and states break a constraint of eq. (33) by more than allowed: the
    /// part (a field of `Violations`), its recomputed violation and the allowance (its unit).
    /// Ipopt's status alone does not show this: it judges its own last iterate, which a bound
    /// clipping after the solve (`honor_original_bounds`) or an "acceptable" stop can leave.
    ConstraintViolated { part: &'static str, violation: f64, allowed: f64 },
    /// The second-order certificate found negative curvature on the critical face and no lower
    /// minimum was reached from it ([`crate::certificate`]): its smallest curvature, where computed.
    NotAMinimum { curvature: Option<f64> },
}

impl std::fmt::Display for DesignWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotConverged { status } => write!(f, "Ipopt did not converge: {status}"),
            Self::Unstable { equilibrium, min_eigenvalue } => {
                let name = match equilibrium {
                    LoadCase::Passive => "θ1 (passive)",
                    LoadCase::Loaded => "θ2 (passive + actuation)",
                    LoadCase::Probe => "θ3 (the compliance's load case)",
                };
                let eigenvalue = min_eigenvalue.map_or("none".into(), |e| format!("{e:.3e} N·m/rad"));
                write!(f, "the equilibrium {name} is unstable (smallest reduced-Hessian eigenvalue {eigenvalue})")
            }
            Self::NoEquilibria => write!(f, "the final design has no equilibria on its load path"),
            Self::OffLoadPath { passive_difference, loaded_difference, passive_status, loaded_status } => {
                let loaded = loaded_status.map_or("loaded path not reached".into(), |s| s.to_string());
                write!(
                    f,
                    "the optimiser's equilibria are not the ones reached by loading the design (differences {passive_difference:.3e} and {loaded_difference:.3e} rad; paths: {passive_status}, {loaded})"
                )
            }
            Self::ConstraintViolated { part, violation, allowed } => write!(
                f,
                "the reported design violates eq. (33): {part} {violation:.3e} (allowed {allowed:.1e}); its numbers are not those of an optimum"
            ),
            Self::NotAMinimum { curvature } => write!(
                f,
                "the point is not a minimum: negative curvature{} on the null space of the active constraints (a saddle of eq. (33))",
                curvature.map_or(String::new(), |c| format!(" {c:.3e}"))
            ),
        }
    }
}

impl Serialize for DesignWarning {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}
