//! How the full space's quantities are Ipopt's variables (case fields `solver.state_variables`
//! and `solver.spring_variables`): the same NLP after a change of variables, with the same KKT
//! points, and a different path for Ipopt.

use crate::layout::StateForm;
use crate::problem::DesignProblem;
use serde::{Deserialize, Serialize};

/// How the full space's states are Ipopt's variables (case field `solver.state_variables`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum StateVariables {
    /// Deflections where absolute angles cannot resolve the tolerance, else absolute angles:
    /// see [`StateVariables::resolve`].
    #[default]
    Auto,
    /// The absolute link angles `θ1`, `θ2`, as the paper writes eq. (33).
    Absolute,
    /// The deflections `θ1 − θ0`, `θ2 − θ0`.
    Deflection,
}

/// How the full space's springs are Ipopt's variables (case field `solver.spring_variables`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum SpringVariables {
    /// Logarithms from [`LOG_SPRINGS_FROM_LINKS`] links on, `k` itself below: see
    /// [`SpringVariables::resolve`].
    #[default]
    Auto,
    /// `ln k`, `k = K / C_K` (eq. (34)): a Newton step changes a spring by a bounded factor
    /// ([`crate::log_variables`]; docs/design.md, "Springs by their logarithm").
    Log,
    /// `k = K / C_K` itself, as the paper writes eq. (34).
    Linear,
}

/// `"auto"` hands Ipopt the springs' logarithms from this many links on (the size from which
/// `solver.refine: "auto"` sequences meshes, [`crate::refine::AUTO_FROM_LINKS`]).
pub const LOG_SPRINGS_FROM_LINKS: usize = crate::refine::AUTO_FROM_LINKS;

impl SpringVariables {
    /// The form of a run on `problem`: `Auto` takes logarithms from [`LOG_SPRINGS_FROM_LINKS`]
    /// links on, where they were measured to take fewer iterations (docs/design.md), and keeps
    /// the paper's `k` below, so that the paper's cases (up to 20 links) and the C_K study of
    /// eq. (34), which is about how Ipopt sees `k`, keep their paths. A ladder's levels all use
    /// the form of the chain asked for.
    pub fn resolve(self, problem: &DesignProblem) -> SpringVariables {
        match self {
            Self::Auto if problem.n_links() >= LOG_SPRINGS_FROM_LINKS => Self::Log,
            Self::Auto => Self::Linear,
            other => other,
        }
    }
}

/// Round-off of absolute angles, in units of `K_max θ0_max ε` (N·m), above which
/// [`StateVariables::Auto`] takes deflections once it exceeds the tolerance: measured 2.6 at the
/// scaled family's N = 1000 (a floor of 3e-8 N·m with `K_max` = 1e8 N·m/rad); 8 leaves a margin.
pub const ABSOLUTE_ANGLE_FLOOR_FACTOR: f64 = 8.0;

impl StateVariables {
    /// The form of this run. `Auto` takes deflections when the round-off of a spring moment formed
    /// from absolute angles, `8 K_max θ0_max ε` (N·m; `ε` the machine epsilon), exceeds
    /// `tolerance`, the smaller of the run's `tolerance` and `constraint_tolerance`
    /// ([`crate::settings::SolverSettings::smaller_tolerance`]): the paper's cases (`K ≤ 1e4` N·m/rad) stay on
    /// absolute angles; the scaled family of docs/PEERS.md (`K_max = 100 N²` N·m/rad, `tol` 1e-8)
    /// moves to deflections from N ≈ 330.
    pub fn resolve(self, problem: &DesignProblem, tolerance: f64) -> StateForm {
        match self {
            Self::Absolute => StateForm::Absolute,
            Self::Deflection => StateForm::Deflection,
            Self::Auto => {
                let k_max = problem.bounds.stiffness_max.iter().fold(0.0f64, |m, &k| m.max(k));
                let floor = ABSOLUTE_ANGLE_FLOOR_FACTOR * k_max * problem.bounds.theta0_max * f64::EPSILON;
                if floor > tolerance {
                    StateForm::Deflection
                } else {
                    StateForm::Absolute
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{paper_problem, scaled_family};

    #[test]
    fn auto_takes_deflections_only_where_absolute_angles_cannot_resolve_the_tolerance() {
        // The scaled family's settings in docs/PEERS.md: tol 1e-8, constraints 1e-9 s² (here 1e-5).
        let settings =
            crate::settings::SolverSettings { tolerance: 1e-8, constraint_tolerance: 1e-5, ..Default::default() };
        let mut tolerance = settings.smaller_tolerance();
        let auto = StateVariables::Auto;
        // The paper's bounds (K ≤ 1e4 N·m/rad): round-off 8 K θ0_max ε ≈ 9e-12 N·m.
        assert_eq!(auto.resolve(&paper_problem(10, -5.0, -400.0, -0.02, 1.0), tolerance), StateForm::Absolute);
        // The scaled family, K_max = 100 N²: the threshold 1.1e7 N·m/rad lies between N = 300 and 400.
        assert_eq!(auto.resolve(&scaled_family(300), tolerance), StateForm::Absolute);
        assert_eq!(auto.resolve(&scaled_family(400), tolerance), StateForm::Deflection);
        assert_eq!(auto.resolve(&scaled_family(1000), tolerance), StateForm::Deflection);
        // A tighter constraint tolerance counts too.
        tolerance = crate::settings::SolverSettings { constraint_tolerance: 1e-12, ..settings }.smaller_tolerance();
        assert_eq!(auto.resolve(&scaled_family(100), tolerance), StateForm::Deflection);
        // Forced forms are taken as given.
        assert_eq!(StateVariables::Absolute.resolve(&scaled_family(1000), tolerance), StateForm::Absolute);
        let paper = paper_problem(5, -5.0, -400.0, -0.02, 1.0);
        assert_eq!(StateVariables::Deflection.resolve(&paper, tolerance), StateForm::Deflection);
    }
}
