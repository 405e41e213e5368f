//! Periodic response (Sec. 5.2.2) and the periodic-load design of eq. (37).
//!
//! The response starts at rest at `θ1` and is integrated one forcing period at a time until two
//! consecutive periods agree (the end-displacement traces differ by less than `settle_tolerance`
//! of their swing) or `max_periods` have run. On the last period it reports
//!
//! * the minimum end displacement `min_t (X_{N+1}(t) − L_x)` (the constraint of eq. (37)) and when it
//!   occurs;
//! * `reach_time`: from the load's onset until the end has covered `reach_fraction` (0.9) of its swing
//!   from the onset value to the minimum;
//! * `return_time`: from the release until it has come back `reach_fraction` of the way from the
//!   minimum to the passive equilibrium `X_{N+1}(θ1)`;
//! * `time_to_target`: from the onset until `X_{N+1} − L_x` first reaches a given `δ_d`.
//!
//! For a pulse train the onset is the rising edge and the release the falling edge; for the
//! sinusoid `½(1 − cos Ωt)` the onset is the force's minimum and the release its maximum.

use crate::eom::Dynamics;
use crate::forcing::Forcing;
use crate::integrator::{integrate, Extras, Options, Outcome, Stats, Trajectory};
use crate::response::{sample, Drift, DynamicProblem, DynamicsError, Sample, StaticEnds};
use crate::system::SpineOde;
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
    /// The first on-phase from rest at `θ1`: from the first onset until the end covers
    /// `reach_fraction` of the static swing `X(θ2) − X(θ1)`, s (the step response's `T_90` when the
    /// on-phase is long enough to get there; `None` when it does not within the first period).
    pub first_rise_time: Option<f64>,
    /// From the onset until `X_{N+1} − L_x ≤ δ_d`, s (when a `δ_d` was given and is reached).
    pub time_to_target: Option<f64>,
    pub drift: Drift,
    pub stats: Stats,
    pub time_seconds: f64,
    /// Samples of every simulated period.
    #[serde(skip)]
    pub samples: Vec<Sample>,
}

/// Onset and release of the load within one period (offsets from the period's start, s).
fn onset_and_release(forcing: &Forcing) -> (f64, f64) {
    match *forcing {
        Forcing::PulseTrain { period, duty, delay } => (delay % period, (delay % period) + duty * period),
        Forcing::Sinusoid { angular_frequency } => (0.0, std::f64::consts::PI / angular_frequency),
        _ => (0.0, 0.0),
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
    let clock = std::time::Instant::now();
    let n = d.n_links();
    let period = d.forcing.period().expect("a periodic forcing");
    let ode = SpineOde { dynamics: d, damping_sensitivities: false };
    let mut y = ends.rest_state();
    let mut stats = Stats::default();
    let mut drift = Drift::default();
    let mut samples = Vec::new();
    let mut previous: Option<Vec<f64>> = None;
    let mut last: Option<Trajectory> = None;
    let (mut settled, mut period_change, mut periods_run) = (false, f64::INFINITY, 0);
    let mut outcome = Outcome::Completed;
    let x_of = |y: &[f64]| d.end_x(&y[..n]) - length_x;
    let grad = |y: &[f64]| d.end_x_state_gradient(y);
    let (onset, release) = onset_and_release(&d.forcing);
    let first_level =
        ends.passive_displacement + settings.reach_fraction * (ends.loaded_displacement - ends.passive_displacement);
    let mut first_rise_time = None;
    for k in 0..settings.max_periods.max(2) {
        let t0 = k as f64 * period;
        let traj = integrate(&ode, t0, &y, t0 + period, &settings.integrator, Extras::default());
        periods_run += 1;
        if k == 0 {
            first_rise_time =
                traj.first_root(t0 + onset, &|y| x_of(y) - first_level, &grad).map(|e| e.t - (t0 + onset));
        }
        stats.absorb(&traj.stats);
        let (s, dr) = sample(d, &traj, settings.samples_per_period + 1, ends.x1, length_x);
        drift.absorb(&dr);
        let trace: Vec<f64> = s.iter().map(|p| p.end_displacement).collect();
        samples.extend(s);
        if traj.outcome != Outcome::Completed {
            outcome = traj.outcome.clone();
            last = Some(traj);
            break;
        }
        y = traj.end().to_vec();
        if let Some(prev) = &previous {
            period_change = relative_change(&trace, prev);
            if period_change <= settings.settle_tolerance {
                settled = true;
                last = Some(traj);
                break;
            }
        }
        previous = Some(trace);
        last = Some(traj);
    }
    let traj = last.expect("at least one period");
    let (t_start, _) = traj.span();
    let (min, max) = extremes(&traj, &x_of, settings.samples_per_period * 4);
    let (onset, release) = (t_start + onset, t_start + release);
    let x_onset = x_of(&traj.value(onset));
    let f = settings.reach_fraction;
    let reach_level = x_onset + f * (min.0 - x_onset);
    let reach_time = traj.first_root(onset, &|y| x_of(y) - reach_level, &grad).map(|e| e.t - onset);
    let return_level = min.0 + f * (ends.passive_displacement - min.0);
    let return_time = traj.first_root(release, &|y| x_of(y) - return_level, &grad).map(|e| e.t - release);
    let time_to_target =
        target.and_then(|delta_d| traj.first_root(onset, &|y| x_of(y) - delta_d, &grad)).map(|e| e.t - onset);
    PeriodicResponse {
        outcome,
        ends,
        period,
        periods_run,
        settled,
        period_change,
        min_end_displacement: min.0,
        time_of_minimum: min.1 - onset,
        max_end_displacement: max,
        reach_time,
        return_time,
        first_rise_time,
        time_to_target,
        drift,
        stats,
        time_seconds: clock.elapsed().as_secs_f64(),
        samples,
    }
}

/// The largest difference of two periods' end-displacement traces, as a fraction of the swing of
/// `trace`.
fn relative_change(trace: &[f64], previous: &[f64]) -> f64 {
    let swing =
        trace.iter().cloned().fold(f64::NEG_INFINITY, f64::max) - trace.iter().cloned().fold(f64::INFINITY, f64::min);
    let diff = trace.iter().zip(previous).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    diff / swing.max(1e-300)
}

/// The minimum of `x` (with its time) and the maximum over a trajectory's step points and `dense`
/// equal intervals of its span.
fn extremes(traj: &Trajectory, x_of: &dyn Fn(&[f64]) -> f64, dense: usize) -> ((f64, f64), f64) {
    let (t_start, t_stop) = traj.span();
    let mut min = (f64::INFINITY, t_start);
    let mut max = f64::NEG_INFINITY;
    let dense_points = (0..=dense).map(|k| {
        let t = t_start + (t_stop - t_start) * k as f64 / dense as f64;
        (t, x_of(&traj.value(t)))
    });
    let step_points: Vec<(f64, f64)> = traj.points().map(|(t, y)| (t, x_of(y))).collect();
    for (t, x) in dense_points.chain(step_points) {
        if x < min.0 {
            min = (x, t);
        }
        max = max.max(x);
    }
    (min, max)
}
