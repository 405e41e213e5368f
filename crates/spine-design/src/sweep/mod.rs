//! Sweeps that follow one optimum of eq. (33) along a parameter `p` (a load, `δ_d`, `C_K`, a
//! bound, …): predictor–corrector continuation of the optimum branch `x*(p)`.
//!
//! * **Predictor**: the tangent `dx*/dp` of [`crate::sensitivity`] at the last point (the
//!   one-sided derivative in the direction of travel where a bound is weakly active).
//! * **Corrector**: Ipopt from the predicted design, states and the last multipliers
//!   (`warm_start_init_point`, a small `mu_init`), to the polishing tolerance so that the next
//!   active set and tangent can be read.
//! * **Adaptive steps**: a step is accepted when the corrector ends clean within
//!   [`settings::SweepSettings::branch_tolerance`] of the prediction (a fraction of the design box); else it
//!   is halved, up to [`settings::SweepSettings::halvings`] times. A step that cannot be made small enough
//!   is a **jump**: the branch ended (a fold) or the corrector left it; the sweep reports it and
//!   goes on from the optimum the corrector reached.
//! * **Events** between two accepted points, each located by bisection on the parameter: a bound
//!   becoming active or inactive, the reduced Hessian losing (or regaining) definiteness (a fold:
//!   second-order sufficiency fails), an equilibrium losing (or regaining) stability.

mod events;
pub mod settings;
mod station;

use crate::numbers::ProblemTangent;
use crate::problem::{DesignBounds, DesignProblem};
use crate::result::DesignResult;
use crate::sensitivity::Derivative;
use crate::settings::SolverSettings;
use crate::solve::ipopt::DesignError;
use serde::Serialize;
use settings::SweepSettings;
use spine_model::Design;
use station::Station;

/// Why a sweep stopped.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SweepError {
    /// The problem could not be built at a parameter value.
    #[error("parameter: {0}")]
    Parameter(#[source] spine_check::FieldError),
    /// The sensitivities along the branch could not be computed.
    #[error(transparent)]
    Sensitivity(#[from] crate::sensitivity::SensitivityError),
    /// Ipopt could not start.
    #[error(transparent)]
    Solver(#[from] DesignError),
    /// The start optimum is not clean, so there is no branch to follow.
    #[error("the optimum at the sweep's start is not clean ({0}): there is no branch to follow")]
    Start(spine_ipopt::Status),
}

/// How a reported point was reached.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PointStatus {
    /// On the followed branch, every step accepted.
    Followed,
    /// After a jump (see [`EventKind::Jump`]): on the optimum the corrector reached.
    Jumped,
    /// The corrector did not end clean at this value; the row holds its last iterate.
    Failed,
}

impl PointStatus {
    /// The snake_case name written in results (`followed`, `jumped`, `failed`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Followed => "followed",
            Self::Jumped => "jumped",
            Self::Failed => "failed",
        }
    }
}

/// One reported point of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepPoint {
    pub parameter: f64,
    pub status: PointStatus,
    /// `J*`, J; the end displacement `X_{N+1}(θ2) − L_x`, m.
    pub objective: f64,
    pub end_displacement: Option<f64>,
    pub design: Design,
    /// Ipopt's status and iterations of the corrector that gave this point.
    pub ipopt_status: spine_ipopt::Status,
    pub iterations: usize,
    /// The strictly active inequality bounds, second-order sufficiency, and the stability of the
    /// passive and the loaded equilibrium.
    pub active: Vec<String>,
    pub second_order_sufficient: bool,
    pub stable: [bool; 2],
    /// The second-order certificate of the point ([`crate::certificate`]; computed at the
    /// corrector's tight solution).
    pub certificate: Option<crate::certificate::Certificate>,
    /// The tangent `dx*/dp` (two-sided, or one-sided in the direction of travel).
    pub tangent: Option<Derivative>,
}

/// What changed between two points, located by bisection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    BoundActive,
    BoundInactive,
    /// Second-order sufficiency lost: the reduced Hessian is no longer positive definite.
    Fold,
    SecondOrderRestored,
    StabilityLost,
    StabilityRestored,
    /// The branch could not be followed with the smallest step: it ended or the corrector left it.
    Jump,
}

impl EventKind {
    /// The snake_case name written in results (`bound_active`, `fold`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::BoundActive => "bound_active",
            Self::BoundInactive => "bound_inactive",
            Self::Fold => "fold",
            Self::SecondOrderRestored => "second_order_restored",
            Self::StabilityLost => "stability_lost",
            Self::StabilityRestored => "stability_restored",
            Self::Jump => "jump",
        }
    }
}

/// An event of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepEvent {
    pub kind: EventKind,
    /// Which bound or equilibrium (empty for a fold or a jump).
    pub what: String,
    /// The parameter value (the middle of `bracket`), and the interval it lies in.
    pub parameter: f64,
    pub bracket: [f64; 2],
}

/// A followed sweep.
#[derive(Clone, Debug, Serialize)]
pub struct SweepResult {
    pub parameter: String,
    pub settings: SweepSettings,
    pub points: Vec<SweepPoint>,
    pub events: Vec<SweepEvent>,
    /// Corrector solves (accepted, rejected and bisection ones), and their Ipopt iterations.
    pub solves: usize,
    pub iterations: usize,
    pub rejected_steps: usize,
    /// Why the sweep ended before `settings.to` (the time limit, an interrupt): `points` holds
    /// only the points computed, the last one before the stop.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stopped: Option<spine_stop::StopReason>,
    /// Why nothing was followed (the optimum at the sweep's start is not clean): `points` is empty.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_followed: Option<String>,
}

impl SweepResult {
    /// A sweep that followed nothing, and why.
    pub fn unfollowed(parameter: &str, settings: SweepSettings, why: String) -> Self {
        SweepResult {
            parameter: parameter.to_string(),
            settings,
            points: Vec::new(),
            events: Vec::new(),
            solves: 0,
            iterations: 0,
            rejected_steps: 0,
            stopped: None,
            not_followed: Some(why),
        }
    }
}

/// How [`Sweep::advance`] ended: at its target, or stopped on the way.
// One value per step, moved once: boxing the station would buy nothing.
#[allow(clippy::large_enum_variant)]
enum Advance {
    Reached(Station, PointStatus),
    Stopped(spine_stop::StopReason),
}

/// A sweep of one problem family along one parameter.
pub struct Sweep<'a> {
    /// The parameter's name (for the sensitivities' report).
    pub name: &'a str,
    /// The problem at a parameter value, and the rates of its numbers along the parameter there
    /// (for the stations' exact sensitivities).
    pub problem_at: &'a (dyn Fn(f64) -> Result<DesignProblem, spine_check::FieldError> + 'a),
    pub tangent_at: &'a (dyn Fn(f64) -> Result<ProblemTangent, spine_check::FieldError> + 'a),
    /// The case's solver settings (the corrector tightens them).
    pub solver: &'a SolverSettings,
    pub settings: SweepSettings,
    /// The design box the branch distance is measured in.
    pub bounds: DesignBounds,
    counters: std::cell::Cell<(usize, usize)>,
}

impl<'a> Sweep<'a> {
    pub fn new(
        name: &'a str,
        problem_at: &'a (dyn Fn(f64) -> Result<DesignProblem, spine_check::FieldError> + 'a),
        tangent_at: &'a (dyn Fn(f64) -> Result<ProblemTangent, spine_check::FieldError> + 'a),
        solver: &'a SolverSettings,
        settings: SweepSettings,
    ) -> Result<Self, SweepError> {
        let bounds = problem_at(settings.from).map_err(SweepError::Parameter)?.bounds;
        Ok(Sweep { name, problem_at, tangent_at, solver, settings, bounds, counters: Default::default() })
    }

    fn problem(&self, parameter: f64) -> Result<DesignProblem, SweepError> {
        (self.problem_at)(parameter).map_err(SweepError::Parameter)
    }

    /// Follows the optimum `start` (an optimum of the problem at `settings.from`) to `settings.to`.
    /// A stop ([`spine_stop::check`]: the time limit, an interrupt), seen before each corrector
    /// solve, ends the sweep with the points computed so far and [`SweepResult::stopped`] set; a
    /// solve the stop cut short is not reported as a point.
    pub fn follow(&self, start: &Design) -> Result<SweepResult, SweepError> {
        let mut result = SweepResult {
            parameter: self.name.to_string(),
            settings: self.settings,
            points: Vec::new(),
            events: Vec::new(),
            solves: 0,
            iterations: 0,
            rejected_steps: 0,
            stopped: spine_stop::check(),
            not_followed: None,
        };
        if result.stopped.is_some() {
            return Ok(result);
        }
        let first = self.counted(self.restart(self.settings.from, start))?;
        if let Some(reason) = spine_stop::check() {
            result.stopped = Some(reason);
            return Ok(self.finish(result));
        }
        if !first.clean() {
            return Err(SweepError::Start(first.result.solver.status));
        }
        result.points.push(self.point(&first, PointStatus::Followed));
        let mut current = first;
        for k in 1..self.settings.points {
            let target = self.settings.value(k);
            match self.advance(current, target, &mut result.events, &mut result.rejected_steps)? {
                Advance::Reached(next, status) => {
                    result.points.push(self.point(&next, status));
                    current = next;
                }
                Advance::Stopped(reason) => {
                    result.stopped = Some(reason);
                    break;
                }
            }
        }
        Ok(self.finish(result))
    }

    /// The result with the solve counters.
    fn finish(&self, mut result: SweepResult) -> SweepResult {
        (result.solves, result.iterations) = self.counters.get();
        result
    }

    /// From `current` to `target` in accepted steps (halved where the corrector leaves the
    /// branch), with the events between accepted points. Where the smallest step still leaves the
    /// branch, a jump: the sweep goes on from the corrector's optimum, or, where that is not clean,
    /// from a tight solve at `target` started from the last design (a failed point if that is not
    /// clean either; the next target starts from it).
    fn advance(
        &self,
        mut current: Station,
        target: f64,
        events: &mut Vec<SweepEvent>,
        rejected: &mut usize,
    ) -> Result<Advance, SweepError> {
        let mut status = PointStatus::Followed;
        let mut step = target - current.parameter;
        let mut halvings = 0;
        while current.parameter != target {
            if let Some(reason) = spine_stop::check() {
                return Ok(Advance::Stopped(reason));
            }
            let p = if (target - current.parameter).abs() <= step.abs() { target } else { current.parameter + step };
            let prediction = current.predict(p);
            let next = self.counted(self.settle(p, &prediction))?;
            if let Some(reason) = spine_stop::check() {
                // The corrector may have been cut short: not a point.
                return Ok(Advance::Stopped(reason));
            }
            let accepted = next.clean() && self.distance(&next, &prediction) <= self.settings.branch_tolerance;
            if !accepted && halvings < self.settings.halvings {
                *rejected += 1;
                halvings += 1;
                step *= 0.5;
                continue;
            }
            let next = match (accepted, next.clean()) {
                (true, _) => {
                    events.extend(self.events_between(&current, &next)?);
                    next
                }
                (false, clean) => {
                    let to = if clean { p } else { target };
                    let next = if clean { next } else { self.counted(self.restart(target, &current.result.design))? };
                    if let Some(reason) = spine_stop::check() {
                        return Ok(Advance::Stopped(reason));
                    }
                    if !next.clean() {
                        return Ok(Advance::Reached(next, PointStatus::Failed));
                    }
                    let bracket = [current.parameter, to];
                    let parameter = 0.5 * (bracket[0] + bracket[1]);
                    events.push(SweepEvent { kind: EventKind::Jump, what: String::new(), parameter, bracket });
                    status = PointStatus::Jumped;
                    next
                }
            };
            current = next;
            halvings = 0;
            step = target - current.parameter;
        }
        Ok(Advance::Reached(current, status))
    }

    /// Counts a corrector's solve and iterations.
    fn counted(&self, station: Result<Station, SweepError>) -> Result<Station, SweepError> {
        let station = station?;
        let (solves, iterations) = self.counters.get();
        self.counters.set((solves + 1, iterations + station.run.solver.iterations));
        Ok(station)
    }

    fn point(&self, s: &Station, status: PointStatus) -> SweepPoint {
        let r: &DesignResult = &s.result;
        SweepPoint {
            parameter: s.parameter,
            status,
            objective: r.objective,
            end_displacement: r.end_displacement,
            design: r.design.clone(),
            ipopt_status: r.solver.status,
            iterations: r.solver.iterations,
            active: s.active(),
            second_order_sufficient: s.second_order(),
            stable: s.stable(),
            certificate: r.certificate.clone(),
            tangent: s.tangent(self.settings.to - self.settings.from).cloned(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names written by hand agree with the names serde writes into `result.json`.
    #[test]
    fn names_agree_with_the_serialised_ones() {
        use PointStatus::*;
        for s in [Followed, Jumped, Failed] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.name());
        }
        use EventKind::*;
        for k in [BoundActive, BoundInactive, Fold, SecondOrderRestored, StabilityLost, StabilityRestored, Jump] {
            assert_eq!(serde_json::to_value(k).unwrap(), k.name());
        }
    }
}
