//! Responses: the step response of Sec. 5.2.1 (rise time `T_90`, final value, first-order fit,
//! eq. (36) as corrected in `docs/errata.md`) and the building blocks shared with the periodic
//! response (static end states, samples, constraint drift).

use crate::eom::Dynamics;
pub use crate::eq36::{fit_first_order, FirstOrderFit};
use crate::eq36::{rise_from_unloaded, RiseFromUnloaded};
use crate::forcing::Forcing;
use crate::integrator::adjoint::{adjoint, Sensitivities, Term};
use crate::integrator::{first_event, integrate, EventFunction, Extras, Options, Outcome, Stats, Trajectory};
use crate::ode::OdeSystem;
pub use crate::sample::Sample;
use crate::system::{Parameters, SpineOde};
use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};
use spine_model::{Design, Structure};
use spine_solve::{solve_static, ContinuationOptions, EquilibriumStatus, StaticProblem};

/// A design with its dampers and loads: the data of every dynamic run.
#[derive(Clone, Debug)]
pub struct DynamicProblem {
    /// The chain, its passive load and the full actuation (the axial force at the end; `s(t)` of
    /// the forcing scales it).
    pub structure: Structure,
    pub design: Design,
    /// Dampers `C_1..C_{N+1}`, N·m·s/rad.
    pub damping: Vec<f64>,
}

/// The static states a response starts from and settles to.
#[derive(Clone, Debug, Serialize)]
pub struct StaticEnds {
    /// `θ1`: the passive equilibrium (the start, at rest), rad.
    pub theta1: Vec<f64>,
    /// The slider's reaction `λ` at `θ1`, N (the state of eq. (5) with `θ1`; not written).
    #[serde(skip)]
    pub lambda1: f64,
    /// `θ2`: the equilibrium under passive load plus the full actuation, rad.
    pub theta2: Vec<f64>,
    /// The slider's reaction `λ` at `θ2`, N (not written).
    #[serde(skip)]
    pub lambda2: f64,
    /// `X_{N+1}(θ1)` and `X_{N+1}(θ2)`, m.
    pub x1: f64,
    pub x2: f64,
    /// `X_{N+1}(θ1) − L_x` and `X_{N+1}(θ2) − L_x`, m.
    pub passive_displacement: f64,
    pub loaded_displacement: f64,
    /// How the two load paths ended (always stable: an unstable end is [`DynamicsError`]).
    pub passive_status: EquilibriumStatus,
    pub loaded_status: EquilibriumStatus,
}

impl StaticEnds {
    /// The start of every response: at rest at `θ1`, `y = (θ1, 0)`.
    pub fn rest_state(&self) -> Vec<f64> {
        let mut y = self.theta1.clone();
        y.resize(2 * self.theta1.len(), 0.0);
        y
    }
}

/// Why a dynamic run could not start.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DynamicsError {
    /// The passive path from `θ0` did not end at a certified stable `θ1`.
    #[error("the passive equilibrium θ1 is not a stable start: {status}")]
    UnstableStart { status: EquilibriumStatus },
    /// The loaded path did not end at a certified stable `θ2`.
    #[error("the loaded equilibrium θ2 is not stable, so the response has no static final value: {status}")]
    UnstableEnd { status: EquilibriumStatus },
}

impl DynamicProblem {
    /// The same problem with the springs `stiffness` (N·m/rad), as eq. (37)'s searches try them.
    pub fn with_stiffness(&self, stiffness: &[f64]) -> Self {
        let mut p = self.clone();
        p.design.stiffness = stiffness.to_vec();
        p
    }

    /// The equations of motion under `forcing`.
    pub fn dynamics(&self, forcing: Forcing) -> Dynamics {
        Dynamics::new(
            &self.structure.chain,
            &self.design,
            self.damping.clone(),
            &self.structure.passive,
            &self.structure.actuation,
            forcing,
        )
    }

    /// `θ1` and `θ2` by continuation, both certified stable, or the reason not.
    pub fn static_ends(&self, opts: &ContinuationOptions) -> Result<StaticEnds, DynamicsError> {
        let problem = StaticProblem { structure: self.structure.clone(), design: self.design.clone() };
        let sol = solve_static(&problem, opts);
        if sol.passive.status != EquilibriumStatus::Stable {
            return Err(DynamicsError::UnstableStart { status: sol.passive.status });
        }
        // Invariant: the passive status is `Stable` only at load factor 1 (`solve_static`), and the
        // loaded path starts from there.
        let loaded = sol.loaded.as_ref().expect("the passive path reached its load");
        if loaded.status != EquilibriumStatus::Stable {
            return Err(DynamicsError::UnstableEnd { status: loaded.status });
        }
        let d = self.dynamics(Forcing::Off);
        let lx = self.structure.chain.length_x();
        let (x1, x2) = (d.end_x(&sol.passive.state.theta), d.end_x(&loaded.state.theta));
        Ok(StaticEnds {
            theta1: sol.passive.state.theta.clone(),
            lambda1: sol.passive.state.lambda,
            theta2: loaded.state.theta.clone(),
            lambda2: loaded.state.lambda,
            x1,
            x2,
            passive_displacement: x1 - lx,
            loaded_displacement: x2 - lx,
            passive_status: sol.passive.status,
            loaded_status: loaded.status,
        })
    }
}

/// Constraint drift of a run, m and m/s.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Drift {
    /// Largest `|Φ|` and `|Φ̇|` at the accepted steps (after projection).
    pub max_constraint: f64,
    pub max_constraint_rate: f64,
    /// The same on the dense output between the steps (cubic Hermite).
    pub max_constraint_dense: f64,
    pub max_constraint_rate_dense: f64,
    /// Largest correction the projection applied to a step (the drift of one unprojected step).
    pub max_projection: f64,
}

impl Drift {
    /// The larger of two runs' drifts, figure by figure.
    pub fn absorb(&mut self, other: &Drift) {
        self.max_constraint = self.max_constraint.max(other.max_constraint);
        self.max_constraint_rate = self.max_constraint_rate.max(other.max_constraint_rate);
        self.max_constraint_dense = self.max_constraint_dense.max(other.max_constraint_dense);
        self.max_constraint_rate_dense = self.max_constraint_rate_dense.max(other.max_constraint_rate_dense);
        self.max_projection = self.max_projection.max(other.max_projection);
    }
}

/// Samples `count` equally spaced instants of a trajectory, and its drift.
pub fn sample(d: &Dynamics, traj: &Trajectory, count: usize, x_start: f64, length_x: f64) -> (Vec<Sample>, Drift) {
    let n = d.n_links();
    let (t0, t1) = traj.span();
    let mut drift = Drift { max_projection: traj.stats.max_projection, ..Default::default() };
    for (k, (_, y)) in traj.points().enumerate() {
        // A stop (the time limit) ends the scan: a stopped run's drift is that of its steps so far.
        if k % 4096 == 4095 && spine_stop::check().is_some() {
            break;
        }
        drift.max_constraint = drift.max_constraint.max(d.constraint(&y[..n]).abs());
        drift.max_constraint_rate = drift.max_constraint_rate.max(d.constraint_rate(&y[..n], &y[n..]).abs());
    }
    let samples = (0..count)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / (count.max(2) - 1) as f64;
            let y = traj.value(t);
            let (theta, omega) = y.split_at(n);
            drift.max_constraint_dense = drift.max_constraint_dense.max(d.constraint(theta).abs());
            drift.max_constraint_rate_dense =
                drift.max_constraint_rate_dense.max(d.constraint_rate(theta, omega).abs());
            let x = d.end_x(theta);
            Sample {
                t,
                load_factor: d.forcing.factor(t, t),
                delta: x - x_start,
                end_displacement: x - length_x,
                theta: theta.to_vec(),
            }
        })
        .collect();
    (samples, drift)
}

/// A settled response has every angle within this of `θ2`, rad (the same end position reached by a
/// different configuration, e.g. a link turned by 2π, is not the static final state).
pub const SETTLED_ANGLE: f64 = 1e-3;

/// Settings of a step response.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct StepSettings {
    /// Simulated time, s (> 0).
    pub t_end: f64,
    /// Fraction of `Δ∞` that defines the rise time (0.9: `T_90`).
    pub rise_fraction: f64,
    /// Number of equally spaced samples written and used by the first-order fit.
    pub samples: usize,
    /// `Δ(t_end)` counts as settled within this fraction of `|Δ∞|`.
    pub settle_tolerance: f64,
    pub integrator: Options,
    pub continuation: ContinuationOptions,
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            t_end: 1.0,
            rise_fraction: 0.9,
            samples: 1001,
            settle_tolerance: 1e-3,
            integrator: Options::default(),
            continuation: ContinuationOptions::default(),
        }
    }
}

/// The step response of Sec. 5.2.1.
#[derive(Clone, Debug, Serialize)]
pub struct StepResponse {
    pub outcome: Outcome,
    pub ends: StaticEnds,
    /// `Δ∞ = X_{N+1}(θ2) − X_{N+1}(θ1)`, m.
    pub delta_inf: f64,
    /// Rise time: first `t` with `Δ(t) = rise_fraction · Δ∞`, s (`None` if never reached).
    pub rise_time: Option<f64>,
    /// `dT_90/dC_i`, s per N·m·s/rad, when sensitivities were asked for.
    pub rise_time_gradient: Option<Vec<f64>>,
    /// `τ = −ln(1 − rise_fraction) / T_90` (eq. (36) corrected), 1/s.
    pub tau_from_rise_time: Option<f64>,
    /// The rise with the end displacement measured from `θ0`, as eq. (36) measures `δ_d`.
    pub from_unloaded: RiseFromUnloaded,
    pub fit: FirstOrderFit,
    /// `Δ(t_end)`, m, and `|Δ(t_end) − Δ∞| / |Δ∞|`.
    pub final_delta: f64,
    pub settle_error: f64,
    /// `|Δ(t_end) − Δ∞| ≤ settle_tolerance |Δ∞|` and every angle within [`SETTLED_ANGLE`] of `θ2`.
    pub settled: bool,
    /// `max_i |θ_i(t_end) − θ2_i|`, rad: that it settles in the continuation's `θ2`.
    pub final_state_gap: f64,
    pub drift: Drift,
    /// Whether the end point moves toward `Δ∞` without turning back (on the samples).
    pub overdamping: crate::overdamping::Overdamping,
    pub stats: Stats,
    /// Wall time of the integration, s.
    pub time_seconds: f64,
    #[serde(skip)]
    pub samples: Vec<Sample>,
}

/// Runs the step response: at rest at `θ1`, the full actuation from `t = 0`. With `gradient` also
/// `dT_90/dC` by forward sensitivities through the integrator.
pub fn step_response(
    problem: &DynamicProblem,
    settings: &StepSettings,
    gradient: bool,
) -> Result<StepResponse, DynamicsError> {
    let ends = problem.static_ends(&settings.continuation)?;
    let d = problem.dynamics(Forcing::Step);
    Ok(simulate_step(&d, ends, settings, gradient))
}

/// Integrates the step response from `θ1` and locates the rise event; with `stop_at_rise` the run
/// ends at the first step past the event (all an optimiser needs). With `gradient`, the event's
/// `dT_90/dC`: by forward sensitivities through every step, or by one adjoint sweep of the plain
/// run with the output `∇g · S(T_90)` (`S(0) = 0`: `θ1` does not depend on the dampers), both
/// `−(∇g · S(T_90)) / ġ` ([`first_event`]).
fn run_step(
    d: &Dynamics,
    ends: &StaticEnds,
    settings: &StepSettings,
    gradient: Option<Sensitivities>,
    stop_at_rise: bool,
) -> (Trajectory, Option<crate::integrator::Event>) {
    let n = d.n_links();
    let gradient = gradient.map(|s| s.for_method(settings.integrator.method));
    let forward = gradient == Some(Sensitivities::Forward);
    let ode = SpineOde { dynamics: d, parameters: if forward { Parameters::Dampers } else { Parameters::None } };
    let target = ends.x1 + settings.rise_fraction * (ends.x2 - ends.x1);
    let sign0 = (d.end_x(&ends.theta1) - target).signum();
    let passed = |_: f64, y: &[f64]| (d.end_x(&y[..n]) - target) * sign0 <= 0.0;
    let extras = Extras {
        sensitivities: forward.then(|| DMatrix::zeros(2 * n, n + 1)),
        steps: None,
        stop: if stop_at_rise { Some(&passed) } else { None },
    };
    let traj = integrate(&ode, 0.0, &ends.rest_state(), settings.t_end, &settings.integrator, extras);
    let g = |y: &[f64]| d.end_x(&y[..n]) - target;
    let grad = |y: &[f64]| d.end_x_state_gradient(y);
    let lipschitz = d.end_x_lipschitz();
    // Located on the dense output, then moved onto the steps (order 5, not 3).
    let mut event =
        first_event(&ode, &settings.integrator, &traj, 0.0, &EventFunction::new(&g, &grad).with_lipschitz(&lipschitz));
    if let (Some(Sensitivities::Adjoint), Some(e)) = (gradient, event.as_mut()) {
        e.t_sensitivity = rise_time_adjoint(d, &traj, e);
    }
    (traj, event)
}

/// `dT_90/dC = −(∇g · S(T_90)) / ġ` by one adjoint sweep of the plain run `traj` (module docs of
/// [`crate::integrator::adjoint`]); `None` when the sweep fails.
fn rise_time_adjoint(d: &Dynamics, traj: &Trajectory, event: &crate::integrator::Event) -> Option<Vec<f64>> {
    let ode = SpineOde { dynamics: d, parameters: Parameters::Dampers };
    let step = traj.intervals.iter().find(|iv| iv.t0 < event.t && event.t <= iv.t1)?;
    let dg = d.end_x_state_gradient(&event.y);
    let mut f = vec![0.0; dg.len()];
    ode.rhs_into(event.t, step.piece(), &event.y, &mut f);
    let rate: f64 = dg.iter().zip(&f).map(|(a, b)| a * b).sum();
    let (gradients, _) = adjoint(&ode, &[traj], &[vec![Term { t: event.t, weights: dg }]])?;
    Some(gradients[0].direct.iter().map(|v| -v / rate).collect())
}

/// `T_90` and, with `gradient`, `dT_90/dC` by the adjoint (forward sensitivities for TR-BDF2),
/// integrating only until the rise (s, s per N·m·s/rad).
pub fn rise_time(
    d: &Dynamics,
    ends: &StaticEnds,
    settings: &StepSettings,
    gradient: bool,
) -> (Option<f64>, Option<Vec<f64>>) {
    rise_time_by(d, ends, settings, gradient.then_some(Sensitivities::Adjoint))
}

/// [`rise_time`] with the gradient's method.
pub fn rise_time_by(
    d: &Dynamics,
    ends: &StaticEnds,
    settings: &StepSettings,
    gradient: Option<Sensitivities>,
) -> (Option<f64>, Option<Vec<f64>>) {
    let (_, event) = run_step(d, ends, settings, gradient, true);
    event.map_or((None, None), |e| (Some(e.t), e.t_sensitivity))
}

/// [`step_response`] from known static ends.
pub fn simulate_step(d: &Dynamics, ends: StaticEnds, settings: &StepSettings, gradient: bool) -> StepResponse {
    let n = d.n_links();
    let clock = std::time::Instant::now();
    let (traj, event) = run_step(d, &ends, settings, gradient.then_some(Sensitivities::Adjoint), false);
    let time_seconds = clock.elapsed().as_secs_f64();
    let delta_inf = ends.x2 - ends.x1;
    let length_x = ends.x1 - ends.passive_displacement;
    let (samples, drift) = sample(d, &traj, settings.samples, ends.x1, length_x);
    let rise_time = event.as_ref().map(|e| e.t);
    let times: Vec<f64> = samples.iter().map(|s| s.t).collect();
    let deltas: Vec<f64> = samples.iter().map(|s| s.delta).collect();
    let fit = fit_first_order(&times, &deltas, delta_inf);
    let y_end = traj.value(settings.t_end);
    let final_delta = d.end_x(&y_end[..n]) - ends.x1;
    let settle_error = (final_delta - delta_inf).abs() / delta_inf.abs();
    let final_state_gap = y_end[..n].iter().zip(&ends.theta2).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    StepResponse {
        outcome: traj.outcome.clone(),
        delta_inf,
        rise_time,
        rise_time_gradient: event.and_then(|e| e.t_sensitivity),
        tau_from_rise_time: rise_time.map(|t| -(1.0 - settings.rise_fraction).ln() / t),
        from_unloaded: rise_from_unloaded(
            d,
            (ends.x1, ends.x2, length_x),
            &settings.integrator,
            settings.rise_fraction,
            &traj,
        ),
        fit,
        final_delta,
        settle_error,
        settled: traj.outcome == Outcome::Completed
            && settle_error <= settings.settle_tolerance
            && final_state_gap <= SETTLED_ANGLE,
        final_state_gap,
        drift,
        overdamping: crate::overdamping::Overdamping::measure(&samples, delta_inf),
        stats: traj.stats,
        time_seconds,
        samples,
        ends,
    }
}
