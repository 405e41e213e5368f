//! Periodic response (Sec. 5.2.2) and the periodic-load design of eq. (37).
//!
//! The response starts at rest at `θ1` and is integrated one forcing period at a time until two
//! consecutive periods agree (the end-displacement traces differ by less than `settle_tolerance`
//! of their swing) or `max_periods` have run. On the last period it reports
//!
//! * the minimum end displacement `min_t (X_{N+1}(t) − L_x)` (the constraint of eq. (37)) and when it
//!   occurs: the lowest sample of a dense grid (4 × `samples_per_period` points and the steps),
//!   refined on the dense output by golden-section search between its neighbours, so that it is
//!   the minimum of the computed motion to round-off and not a grid value;
//! * `reach_time`: from the load's onset until the end has covered `reach_fraction` (0.9) of its swing
//!   from the onset value to the minimum;
//! * `return_time`: from the release until it has come back `reach_fraction` of the way from the
//!   minimum to the passive equilibrium `X_{N+1}(θ1)`; `return_to_start_time`: until it is back
//!   within 1 % of that way ([`RETURN_TO_START`]), the paper's "returns to its original state";
//! * `time_to_target`: from the onset until `X_{N+1} − L_x` first reaches a given `δ_d`.
//!
//! For a pulse train the onset is the rising edge and the release the falling edge; for the
//! sinusoid `½(1 − cos Ωt)` the onset is the force's minimum and the release its maximum.

mod extremes;
mod springs;

pub use springs::{EndValue, LastPeriod, SpringGradients};

use crate::end_x::EndX;
use crate::eom::Dynamics;
use crate::forcing::Forcing;
use crate::integrator::{integrate, Extras, Options, Outcome, Stats, Trajectory};
use crate::response::{sample, Drift, DynamicProblem, DynamicsError, Sample, StaticEnds};
use crate::system::{Parameters, SpineOde};
use extremes::{extremes, relative_change};
use serde::{Deserialize, Serialize};
use spine_solve::ContinuationOptions;

/// Settings of a periodic response.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct PeriodicSettings {
    /// Most forcing periods simulated (≥ 2).
    pub max_periods: usize,
    /// Two periods agree when their end-displacement traces differ by less than this fraction of
    /// the swing.
    pub settle_tolerance: f64,
    /// Samples per period (written, and used to compare periods).
    pub samples_per_period: usize,
    /// Fraction of the swing that defines the reach and return times.
    pub reach_fraction: f64,
    pub integrator: Options,
    pub continuation: ContinuationOptions,
}

impl Default for PeriodicSettings {
    fn default() -> Self {
        Self {
            max_periods: 12,
            settle_tolerance: 1e-4,
            samples_per_period: 400,
            reach_fraction: 0.9,
            integrator: Options::default(),
            continuation: ContinuationOptions::default(),
        }
    }
}

/// The settled periodic motion.
#[derive(Clone, Debug, Serialize)]
pub struct PeriodicResponse {
    pub outcome: Outcome,
    pub ends: StaticEnds,
    pub period: f64,
    pub periods_run: usize,
    /// Two consecutive periods agreed to `settle_tolerance`.
    pub settled: bool,
    /// Largest difference of the end-displacement traces of the last two periods, as a fraction of
    /// the swing.
    pub period_change: f64,
    /// `min_t (X_{N+1}(t) − L_x)` over the last period, m, and the time after its onset, s.
    pub min_end_displacement: f64,
    pub time_of_minimum: f64,
    /// `max_t (X_{N+1}(t) − L_x)` over the last period, m.
    pub max_end_displacement: f64,
    /// Reach time: from the last period's onset until the end covers `reach_fraction` of the way
    /// from its onset value to the period's minimum, s. Return time: from the release until it
    /// covers that fraction of the way back to `X(θ1)`, s.
    pub reach_time: Option<f64>,
    pub return_time: Option<f64>,
    /// From the release until the end is back within 1 % of the way from the period's minimum to
    /// `X(θ1)` ([`RETURN_TO_START`]), s; `None` when it does not get there before the next onset.
    pub return_to_start_time: Option<f64>,
    /// The first on-phase from rest at `θ1`: from the first onset until the end covers
    /// `reach_fraction` of the static swing `X(θ2) − X(θ1)`, s (the step response's `T_90` when the
    /// on-phase is long enough to get there; `None` when it does not within the first period).
    pub first_rise_time: Option<f64>,
    /// From the onset until `X_{N+1} − L_x ≤ δ_d`, s (when a `δ_d` was given and is reached).
    pub time_to_target: Option<f64>,
    /// The last period's swing `max − min` of the end displacement stands above what the
    /// integrator resolves ([`swing_resolution`]). When it does not (a forcing far faster than the
    /// chain can follow), the reach, return and target times are left out: they would be read off
    /// round-off.
    pub swing_resolved: bool,
    pub drift: Drift,
    pub stats: Stats,
    pub time_seconds: f64,
    /// Samples of every simulated period.
    #[serde(skip)]
    pub samples: Vec<Sample>,
}

/// The fraction of the way back from the period's minimum to `X(θ1)` after which the end counts as
/// returned "to its original state" (Sec. 5.2.2): within 1 % of the swing.
pub const RETURN_TO_START: f64 = 0.99;

/// The smallest swing of the end displacement, m, that a response integrated with `options` over a
/// chain of horizontal length `length_x` resolves: a hundred times the error the tolerances allow
/// in each angle, `(atol + rtol) rad`, carried over the chain's length.
pub fn swing_resolution(options: &Options, length_x: f64) -> f64 {
    100.0 * (options.atol + options.rtol) * length_x.abs().max(1e-3)
}

impl PeriodicResponse {
    /// Settled, and its swing resolved: the numbers of the last period mean what they say.
    pub fn is_meaningful(&self) -> bool {
        self.settled && self.swing_resolved
    }

    /// Why the response's numbers do not mean what they say, if they do not.
    pub fn not_meaningful_reason(&self) -> Option<String> {
        if !self.swing_resolved {
            let swing = self.max_end_displacement - self.min_end_displacement;
            return Some(format!(
                "the end's swing over a period, {swing:.3e} m, is within what the integrator resolves: the forcing (period {} s) is far faster than the chain can follow, so no reach, return or target time is read off it",
                self.period
            ));
        }
        (!self.settled).then(|| {
            format!(
                "no two periods agreed within {} periods (largest change {:.3e} of the swing)",
                self.periods_run, self.period_change
            )
        })
    }
}

/// Onset and release of the load within one period (offsets from the period's start, s).
fn onset_and_release(forcing: &Forcing) -> (f64, f64) {
    match *forcing {
        Forcing::PulseTrain { period, duty, delay } => (delay % period, (delay % period) + duty * period),
        Forcing::Sinusoid { angular_frequency } => (0.0, std::f64::consts::PI / angular_frequency),
        _ => (0.0, 0.0),
    }
}

/// The lowest and highest samples from `t_start` on, as [`extremes`] gives them (`(value, t)` of
/// the minimum, the maximum's value); zeros at `t_start` when there are none.
fn sampled_extremes(samples: &[Sample], t_start: f64) -> (Vec<(f64, f64)>, f64) {
    let last: Vec<&Sample> = samples.iter().filter(|s| s.t >= t_start).collect();
    let min = last.iter().fold((f64::INFINITY, t_start), |m, s| {
        if s.end_displacement < m.0 {
            (s.end_displacement, s.t)
        } else {
            m
        }
    });
    let max = last.iter().fold(f64::NEG_INFINITY, |m, s| m.max(s.end_displacement));
    match last.is_empty() {
        true => (vec![(0.0, t_start)], 0.0),
        false => (vec![min], max),
    }
}

/// Runs the periodic response of `problem` under a periodic `forcing`.
pub fn periodic_response(
    problem: &DynamicProblem,
    forcing: Forcing,
    target: Option<f64>,
    settings: &PeriodicSettings,
) -> Result<PeriodicResponse, DynamicsError> {
    let ends = problem.static_ends(&settings.continuation)?;
    let d = problem.dynamics(forcing);
    Ok(simulate_periodic(&d, ends, problem.structure.chain.length_x(), target, settings))
}

/// [`periodic_response`] from known static ends.
pub fn simulate_periodic(
    d: &Dynamics,
    ends: StaticEnds,
    length_x: f64,
    target: Option<f64>,
    settings: &PeriodicSettings,
) -> PeriodicResponse {
    run_periodic(d, ends, length_x, target, settings, None).0
}

/// [`simulate_periodic`] with the springs' gradients of the last period's values: always
/// `periods` periods (at least 2; a horizon that does not depend on the springs, so that the
/// minima are smooth functions of them; `settled` and `period_change` are still reported), the
/// local minima of the last period, lowest first, and the value at the period's end, with their
/// gradients by forward sensitivities, or without them and the runs kept for the adjoint
/// ([`SpringGradients`]; none of these when the simulation failed).
pub fn simulate_periodic_springs(
    d: &Dynamics,
    ends: StaticEnds,
    length_x: f64,
    target: Option<f64>,
    settings: &PeriodicSettings,
    gradients: SpringGradients,
    periods: usize,
) -> (PeriodicResponse, Option<LastPeriod>) {
    let settings = PeriodicSettings { max_periods: periods, ..settings.clone() };
    run_periodic(d, ends, length_x, target, &settings, Some(gradients))
}

impl EndX<'_> {
    /// `(t, value)` with its gradient in the springs, `∇_y X · S(t)`.
    fn with_gradient(&self, traj: &Trajectory, t: f64, value: f64) -> EndValue {
        let dx = self.d.end_x_state_gradient(&traj.value(t));
        // Invariant: `EndX` with gradients is built only over a trajectory integrated with the springs'
        // sensitivities (`SpringGradients` given).
        let s = traj.sensitivity(t).expect("sensitivities were propagated");
        let gradient = (0..s.ncols()).map(|p| (0..s.nrows()).map(|i| dx[i] * s[(i, p)]).sum()).collect();
        EndValue { t, value, gradient }
    }
}

/// The periods simulated one after another until two in a row agree (or, with a fixed horizon,
/// all of them), with what they add up to.
struct Periods {
    /// The last period simulated.
    last: Trajectory,
    /// The periods before it, when kept for the adjoint.
    earlier: Vec<Trajectory>,
    outcome: Outcome,
    periods_run: usize,
    settled: bool,
    period_change: f64,
    first_rise_time: Option<f64>,
    stats: Stats,
    drift: Drift,
    samples: Vec<Sample>,
}

/// Simulates period after period from the rest state (module docs).
fn simulate_periods(
    end: &EndX<'_>,
    ends: &StaticEnds,
    settings: &PeriodicSettings,
    gradients: Option<SpringGradients>,
) -> Periods {
    let d = end.d;
    // Invariant: a periodic task's case is checked to have a periodic forcing before it runs.
    let period = d.forcing.period().expect("a periodic forcing");
    let fixed_horizon = gradients.is_some();
    let keep = matches!(gradients, Some(SpringGradients::Adjoint));
    let mut sensitivities = match gradients {
        Some(SpringGradients::Forward(s0)) => Some(s0),
        _ => None,
    };
    let mut earlier = Vec::new();
    let (onset, _) = onset_and_release(&d.forcing);
    let first_level =
        ends.passive_displacement + settings.reach_fraction * (ends.loaded_displacement - ends.passive_displacement);
    let mut y = ends.rest_state();
    let (mut stats, mut drift, mut samples) = (Stats::default(), Drift::default(), Vec::new());
    let mut previous: Option<Vec<f64>> = None;
    let (mut settled, mut period_change, mut periods_run) = (false, f64::INFINITY, 0);
    let (mut outcome, mut first_rise_time) = (Outcome::Completed, None);
    let mut k = 0;
    let last = loop {
        let t0 = k as f64 * period;
        let extras = Extras { sensitivities: sensitivities.take(), ..Extras::default() };
        let traj = integrate(&end.ode, t0, &y, t0 + period, &settings.integrator, extras);
        sensitivities = traj.end_sensitivity();
        periods_run += 1;
        let stopped = matches!(traj.outcome, Outcome::TimeLimit { .. } | Outcome::Interrupted { .. });
        if k == 0 && !stopped {
            first_rise_time = end.crossing(&traj, t0 + onset, first_level).map(|t| t - (t0 + onset));
        }
        stats.absorb(&traj.stats);
        let (s, dr) = sample(d, &traj, settings.samples_per_period + 1, ends.x1, end.length_x);
        drift.absorb(&dr);
        let trace: Vec<f64> = s.iter().map(|p| p.end_displacement).collect();
        samples.extend(s);
        if traj.outcome != Outcome::Completed {
            outcome = traj.outcome.clone();
            break traj;
        }
        y = traj.end().to_vec();
        if let Some(prev) = &previous {
            period_change = relative_change(&trace, prev);
            settled = period_change <= settings.settle_tolerance;
            if settled && !fixed_horizon {
                break traj;
            }
        }
        previous = Some(trace);
        k += 1;
        if k >= settings.max_periods.max(2) {
            break traj;
        }
        if keep {
            earlier.push(traj);
        }
    };
    Periods { last, earlier, outcome, periods_run, settled, period_change, first_rise_time, stats, drift, samples }
}

/// The periodic response; with `springs` (`S(0)`), the spring sensitivities and the last period's
/// minima (module docs).
fn run_periodic(
    d: &Dynamics,
    ends: StaticEnds,
    length_x: f64,
    target: Option<f64>,
    settings: &PeriodicSettings,
    springs: Option<SpringGradients>,
) -> (PeriodicResponse, Option<LastPeriod>) {
    let clock = std::time::Instant::now();
    // Invariant: as above, the forcing is checked periodic before the task runs.
    let period = d.forcing.period().expect("a periodic forcing");
    let fixed_horizon = springs.is_some();
    let forward = matches!(springs, Some(SpringGradients::Forward(_)));
    let parameters = if forward { Parameters::Springs } else { Parameters::None };
    let ode = SpineOde { dynamics: d, parameters };
    let end = EndX::new(ode, &settings.integrator, length_x);
    let run = simulate_periods(&end, &ends, settings, springs);
    let traj = &run.last;
    let (t_start, _) = traj.span();
    // A run stopped from outside (its time limit) is read off its samples, not refined on every
    // step: its numbers are partial anyway, and the run must end now.
    let stopped = matches!(run.outcome, Outcome::TimeLimit { .. } | Outcome::Interrupted { .. });
    let (minima, max) = match stopped {
        false => extremes(traj, &|y: &[f64]| end.at(y), settings.samples_per_period * 4),
        true => sampled_extremes(&run.samples, t_start),
    };
    let min = minima[0];
    let (onset, release) = onset_and_release(&d.forcing);
    let (onset, release) = (t_start + onset, t_start + release);
    let x_onset = end.at(&traj.value(onset));
    let f = settings.reach_fraction;
    let reach_time = end.crossing(traj, onset, x_onset + f * (min.0 - x_onset)).map(|t| t - onset);
    let return_level = min.0 + f * (ends.passive_displacement - min.0);
    let return_time = end.crossing(traj, release, return_level).map(|t| t - release);
    let start_level = min.0 + RETURN_TO_START * (ends.passive_displacement - min.0);
    let return_to_start_time = end.crossing(traj, release, start_level).map(|t| t - release);
    let time_to_target = target.and_then(|delta_d| end.crossing(traj, onset, delta_d)).map(|t| t - onset);
    let swing_resolved = max - min.0 > swing_resolution(&settings.integrator, length_x);
    let (reach_time, return_time, return_to_start_time, time_to_target) = match swing_resolved {
        true => (reach_time, return_time, return_to_start_time, time_to_target),
        false => (None, None, None, None),
    };
    let values = (fixed_horizon && run.outcome == Outcome::Completed).then(|| {
        let (_, t_end) = traj.span();
        let value = |t: f64, value: f64| match forward {
            true => end.with_gradient(traj, t, value),
            false => EndValue { t, value, gradient: Vec::new() },
        };
        let last = value(t_end, end.at(traj.end()));
        (minima.iter().map(|&(v, t)| value(t, v)).collect::<Vec<_>>(), last)
    });
    let response = PeriodicResponse {
        outcome: run.outcome,
        ends,
        period,
        periods_run: run.periods_run,
        settled: run.settled,
        period_change: run.period_change,
        min_end_displacement: min.0,
        time_of_minimum: min.1 - onset,
        max_end_displacement: max,
        reach_time,
        return_time,
        return_to_start_time,
        first_rise_time: run.first_rise_time,
        time_to_target,
        swing_resolved,
        drift: run.drift,
        stats: run.stats,
        time_seconds: clock.elapsed().as_secs_f64(),
        samples: run.samples,
    };
    let values = values.map(|(minima, end)| {
        let mut runs = run.earlier;
        if !forward {
            runs.push(run.last);
        }
        LastPeriod { minima, end, runs }
    });
    (response, values)
}
