//! The census along a followed sweep: a multi-start at every k-th point says whether the followed
//! optimum is still the best known, with the multi-start's completeness estimate.

use crate::design::run_design_case;
use crate::error::RunError;
use crate::overrides::DesignOverrides;
use crate::progress::Progress;
use crate::workers::Workers;
use serde::Serialize;
use spine_case::{CaseError, DesignCase, ValidDesign};
use spine_design::census::CensusEstimate;
use spine_design::sweep::{PointStatus, SweepResult};

/// A census along the sweep: a multi-start of `starts` seeded starts at every `every`-th point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CensusPlan {
    pub starts: usize,
    pub every: usize,
}

/// The census at one point of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct CensusPoint {
    /// The point's index and parameter value.
    pub point: usize,
    pub parameter: f64,
    /// The best clean optimum the multi-start found (with the followed one among the candidates),
    /// and the followed optimum's `J*`.
    pub best_objective: Option<f64>,
    pub followed_objective: f64,
    /// The followed optimum is the best known (`J*` within 1e-6 relative of the best, or below).
    pub followed_is_best: bool,
    pub estimate: Option<CensusEstimate>,
    /// Why this census was cut short (the time limit, an interrupt): it ran fewer starts than
    /// planned (`estimate.runs` says how many), so `followed_is_best` rests on fewer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped: Option<spine_stop::StopReason>,
}

/// The case with `name` set to `value`, validated, with the overrides.
pub(crate) fn case_at(
    c: &DesignCase,
    overrides: &DesignOverrides,
    name: &str,
    value: f64,
) -> Result<ValidDesign, CaseError> {
    let mut valid = c.with_parameter(name, value)?.validate()?;
    overrides.apply(&mut valid)?;
    Ok(valid)
}

/// A multi-start of `plan.starts` seeded starts at every `plan.every`-th point of the sweep.
pub(crate) fn census(
    c: &DesignCase,
    overrides: &DesignOverrides,
    workers: Option<&Workers>,
    name: &str,
    followed: &SweepResult,
    plan: CensusPlan,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<CensusPoint>, RunError> {
    let mut out = Vec::new();
    for (k, point) in followed.points.iter().enumerate().step_by(plan.every.max(1)) {
        // A stop ends the census: the points after it have no entry (the result's `stopped` says why).
        if spine_stop::check().is_some() {
            break;
        }
        let overrides = DesignOverrides { starts: Some(plan.starts), ..*overrides };
        let valid = case_at(c, &overrides, name, point.parameter)?;
        let run = run_design_case(c, &valid, workers, progress)?;
        let best = run.multistart.as_ref().and_then(|m| m.best_clean()).map(|o| o.objective());
        let stopped = spine_stop::check();
        if stopped.is_some() && best.is_none() {
            // Stopped before the census found anything: no census at this point (the sweep's
            // `stopped` says why), rather than a comparison with nothing.
            break;
        }
        let followed_objective = point.objective;
        let best_objective = best.map(|b| b.min(followed_objective));
        let followed_is_best = best.is_none_or(|b| followed_objective <= b + 1e-6 * b.abs());
        out.push(CensusPoint {
            point: k,
            parameter: point.parameter,
            best_objective,
            followed_objective,
            followed_is_best: followed_is_best && point.status != PointStatus::Failed,
            estimate: run.multistart.map(|m| m.census),
            stopped,
        });
    }
    Ok(out)
}
