//! The derivatives of an optimum: re-solved tightly from itself, then differentiated, or the
//! typed reason there are none ([`NoSensitivity`]).

use crate::error::RunError;
use serde::Serialize;
use spine_case::{CaseError, DesignCase, ValidDesign};
use spine_design::sensitivity::{sensitivities, Optimum, Parameter, SensitivityReport};
use spine_design::solve::polish::polish;
use spine_design::DesignResult;

/// Why an optimum has no sensitivities (in `result.json`: `{"reason": "another_optimum", …}`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum NoSensitivity {
    /// The optimum is not clean (its status, warnings and certificate say why).
    OptimumNotClean,
    /// The polishing re-solve (tolerance 1e-12) from the optimum did not end clean.
    PolishNotClean { status: spine_ipopt::Status, iterations: usize, warnings: Vec<spine_design::DesignWarning> },
    /// The polishing re-solve left the optimum: `J` moved by `relative_change` (to `objective`,
    /// J) and `θ0` by up to `angle_change` rad.
    AnotherOptimum { relative_change: f64, objective: f64, angle_change: f64 },
    /// The polished optimum has no multipliers or no equilibria.
    NoMultipliers,
}

impl std::fmt::Display for NoSensitivity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::OptimumNotClean => write!(f, "the optimum is not clean (see the design's status and warnings)"),
            Self::PolishNotClean { status, iterations, warnings } => {
                write!(f, "the polishing re-solve (tol 1e-12) from the optimum did not end clean: {status} after {iterations} iterations")?;
                warnings.iter().try_for_each(|w| write!(f, "; {w}"))
            }
            Self::AnotherOptimum { relative_change, objective, angle_change } => write!(
                f,
                "the polishing re-solve (tol 1e-12) moved J by {relative_change:.1e} relative (to {objective:.10e} J) and θ0 by {angle_change:.1e} rad: another optimum"
            ),
            Self::NoMultipliers => write!(f, "the polished optimum has no multipliers or equilibria"),
        }
    }
}

/// The sensitivities of a design case's optimum `first` (a clean result of `valid`'s problem):
/// re-solved tightly from it (see `spine_design::solve::polish::polish`), then, when that ends clean
/// on the same optimum, differentiated with respect to `names`. Returns the report (or why there
/// is none: the polishing solve's status, or how far it moved `J`) and the polishing solve's wall
/// time.
pub fn differentiate(
    c: &DesignCase,
    valid: &ValidDesign,
    names: &[String],
    first: &DesignResult,
) -> Result<(Result<SensitivityReport, NoSensitivity>, f64), RunError> {
    let values = names.iter().map(|name| c.parameter_value(name)).collect::<Result<Vec<f64>, CaseError>>()?;
    let problem = &valid.problem;
    let clock = std::time::Instant::now();
    let polished = polish(problem, &first.design, &valid.settings).map_err(RunError::Design)?;
    let multipliers = polished.multipliers.clone();
    let point = polished.point(problem);
    let design = polished.check(problem, &valid.settings);
    let polish_seconds = clock.elapsed().as_secs_f64();
    let moved = (design.objective - first.objective).abs() / first.objective.abs().max(1e-12);
    let shape_moved =
        design.design.theta0.iter().zip(&first.design.theta0).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    // The same optimum as the certificate judges it (`J` within 1e-6, or a little lower along a
    // flat valley of `K` with the same shape); another local optimum moves more.
    let same = spine_design::solve::settle::same_optimum(first, &design);
    let why_not = if !design.is_clean() {
        Some(NoSensitivity::PolishNotClean {
            status: design.solver.status,
            iterations: design.solver.iterations,
            warnings: design.warnings.clone(),
        })
    } else if !same {
        Some(NoSensitivity::AnotherOptimum {
            relative_change: moved,
            objective: design.objective,
            angle_change: shape_moved,
        })
    } else {
        None
    };
    let (Some(multipliers), None, Some((layout, x))) = (&multipliers, &why_not, point) else {
        return Ok((Err(why_not.unwrap_or(NoSensitivity::NoMultipliers)), polish_seconds));
    };
    let parameters = names
        .iter()
        .zip(&values)
        .map(|(name, &value)| Ok(Parameter { name: name.clone(), value, tangent: c.parameter_tangent(name, problem)? }))
        .collect::<Result<Vec<Parameter>, CaseError>>()?;
    let optimum = Optimum { problem, layout, x: &x, multipliers };
    let report = sensitivities(&optimum, &parameters)
        .map_err(|e| RunError::Case(CaseError::invalid("--param", e.to_string())))?;
    Ok((Ok(report), polish_seconds))
}
