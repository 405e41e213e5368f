//! The periodic-load design of eq. (37): minimise the passive strain energy `U(θ1; K)` over the
//! springs `K`, subject to the passive equilibrium, the equations of motion under the periodic
//! force, and `min_t (X_{N+1}(t) − L_x) = δ_d` over a settled period.
//!
//! The paper handles the constraint, a minimum over time of a simulated motion, by gradient-free
//! searches ([`spine_search`]): a genetic algorithm or a pattern search. [`SearchMethod::Gradient`]
//! hands it to Ipopt with exact gradients instead ([`crate::periodic_gradient`]: forward
//! sensitivities of the whole periodic motion and the envelope theorem at the minimising time).
//! The variables are `log10 K_i` for every method (stiffness spans two decades); the equality is met
//! within a band `|min_t(X − L_x) − δ_d| ≤ tolerance · |δ_d|`, and points are compared by Deb's
//! feasibility rules with the violation measured in units of `|δ_d|`. A design whose passive or
//! loaded equilibrium is not stable, or whose simulation fails, is worse than any other point.

use crate::error::DynamicDesignError;
use crate::periodic_gradient::{design_by_gradient, stiffness_of, GradientReport};
pub use crate::periodic_settings::{GradientSettings, GradientStart, PeriodicDesignSettings, SearchMethod};
use serde::Serialize;
use spine_dynamics::forcing::Forcing;
use spine_dynamics::periodic::{simulate_periodic, PeriodicResponse};
use spine_dynamics::response::{rise_time, DynamicProblem, DynamicsError, StepSettings};
use spine_search::{genetic_algorithm, pattern_search, Bounds, Evaluation, Progress, SearchResult};
use std::sync::atomic::{AtomicUsize, Ordering};

/// What eq. (37) found.
#[derive(Clone, Debug, Serialize)]
pub struct PeriodicDesign {
    pub method: SearchMethod,
    /// The search's own status (mesh converged, generation limit, …); for the gradient method,
    /// the genetic algorithm's that gave its start (`start: "ga"`), else none.
    pub search: Option<SearchResult>,
    /// Ipopt's run, for the gradient method.
    pub gradient: Option<GradientReport>,
    /// Periodic simulations run in all (start, search or root search and Ipopt's evaluations, the
    /// final one).
    pub simulations: usize,
    /// The design meets the displacement band and both static states are stable.
    pub feasible: bool,
    /// Springs of the best point, N·m/rad.
    pub stiffness: Vec<f64>,
    /// Passive strain energy `U(θ1)`, J.
    pub objective: f64,
    /// `min_t (X_{N+1} − L_x)` of the best point, m, and `|… − δ_d| / |δ_d|`.
    pub min_end_displacement: f64,
    pub relative_error: f64,
    pub delta_d: f64,
    /// The start springs and their value.
    pub start_stiffness: Vec<f64>,
    pub start: Evaluation,
    /// Periodic response of the best design (re-simulated with the response settings).
    pub response: PeriodicResponse,
    /// The reach under a forcing that does not cap it: the best design's step response (the
    /// actuation held on from rest at `θ1`) until the end covers `reach_fraction` of the static
    /// swing `X(θ2) − X(θ1)`, s; `None` when it does not within [`STEP_REACH_HORIZON`]. (One step
    /// simulation, not counted in `simulations`, which counts the periodic ones.)
    pub step_reach_time: Option<f64>,
    pub time_seconds: f64,
}

/// Simulated time of the step response behind [`PeriodicDesign::step_reach_time`], s (it stops at
/// the reach).
pub const STEP_REACH_HORIZON: f64 = 60.0;

/// How the method of eq. (37) ended: Ipopt's status (or the stop) for the gradient method, the
/// search's for the GA and pattern search; printed by its name (`solve_succeeded`,
/// `mesh_converged`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MethodStatus {
    Gradient(crate::periodic_gradient::GradientStatus),
    Search(spine_search::SearchStatus),
    /// Neither ran (no method's report).
    None,
}

impl std::fmt::Display for MethodStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Gradient(g) => write!(f, "{g}"),
            Self::Search(s) => f.write_str(s.name()),
            Self::None => f.write_str("none"),
        }
    }
}

impl PeriodicDesign {
    /// How the method ended: Ipopt's status for the gradient method, else the search's.
    pub fn status(&self) -> MethodStatus {
        match (&self.gradient, &self.search) {
            (Some(g), _) => MethodStatus::Gradient(g.status),
            (None, Some(s)) => MethodStatus::Search(s.status),
            (None, None) => MethodStatus::None,
        }
    }

    /// The method ended by its own rule: Ipopt converged, or a search was not stopped from
    /// outside or by the clock.
    pub fn finished(&self) -> bool {
        match (&self.gradient, &self.search) {
            (Some(g), _) => g.converged,
            (None, Some(s)) => s.status.finished(),
            (None, None) => false,
        }
    }

    /// Ipopt iterations for the gradient method, else generations or pattern iterations.
    pub fn iterations(&self) -> usize {
        match (&self.gradient, &self.search) {
            (Some(g), _) => g.iterations,
            (None, Some(s)) => s.iterations,
            (None, None) => 0,
        }
    }
}

/// Passive strain energy and periodic response of `problem` with springs `stiffness`.
fn evaluate(
    problem: &DynamicProblem,
    forcing: &Forcing,
    stiffness: &[f64],
    delta_d: f64,
    settings: &PeriodicDesignSettings,
) -> Result<(Evaluation, PeriodicResponse), DynamicsError> {
    let p = problem.with_stiffness(stiffness);
    let ends = p.static_ends(&settings.response.continuation)?;
    let strain = spine_model::energy::strain_energy(&ends.theta1, &p.design.theta0, stiffness);
    let d = p.dynamics(forcing.clone());
    let r = simulate_periodic(&d, ends, p.structure.chain.length_x(), Some(delta_d), &settings.response);
    Ok((evaluation_of(&r, strain, delta_d, settings), r))
}

/// A response's value for the searches: its strain energy, and its distance outside the band.
fn evaluation_of(r: &PeriodicResponse, strain: f64, delta_d: f64, settings: &PeriodicDesignSettings) -> Evaluation {
    let violation = if r.outcome == spine_dynamics::Outcome::Completed {
        (((r.min_end_displacement - delta_d).abs() / delta_d.abs()) - settings.tolerance).max(0.0)
    } else {
        f64::INFINITY
    };
    Evaluation { objective: strain, violation }
}

/// Solves eq. (37) for the springs of `problem` (its design's `θ0` is kept; its `K` is the start).
pub fn design_periodic(
    problem: &DynamicProblem,
    forcing: Forcing,
    delta_d: f64,
    method: SearchMethod,
    settings: &PeriodicDesignSettings,
    progress: &mut dyn FnMut(Progress),
) -> Result<PeriodicDesign, DynamicDesignError> {
    let clock = std::time::Instant::now();
    let n_springs = problem.design.stiffness.len();
    let (lo, hi) = (settings.stiffness_min.log10(), settings.stiffness_max.log10());
    let bounds = Bounds { lower: vec![lo; n_springs], upper: vec![hi; n_springs] };
    let to_stiffness = stiffness_of;
    let start_stiffness: Vec<f64> =
        problem.design.stiffness.iter().map(|k| k.clamp(settings.stiffness_min, settings.stiffness_max)).collect();
    let start_u: Vec<f64> = start_stiffness.iter().map(|k| k.log10()).collect();
    let simulations = AtomicUsize::new(0);
    let objective = |u: &[f64]| {
        simulations.fetch_add(1, Ordering::Relaxed);
        match evaluate(problem, &forcing, &to_stiffness(u), delta_d, settings) {
            Ok((e, _)) => e,
            Err(_) => Evaluation::failed(),
        }
    };
    match method {
        SearchMethod::Ga => settings.ga.validate()?,
        SearchMethod::Pattern => settings.pattern.validate()?,
        SearchMethod::Gradient => {
            settings.gradient.validate()?;
            if settings.gradient.start == GradientStart::Ga {
                settings.ga.validate()?;
            }
        }
    }
    simulations.fetch_add(1, Ordering::Relaxed);
    let (start, start_response) = match evaluate(problem, &forcing, &to_stiffness(&start_u), delta_d, settings) {
        Ok((e, r)) => (e, Some(r)),
        Err(_) => (Evaluation::failed(), None),
    };
    if let Some(r) = start_response.filter(|r| !r.swing_resolved && r.outcome == spine_dynamics::Outcome::Completed) {
        let start_response = r;
        return Err(DynamicDesignError::Unresolved {
            field: if matches!(forcing, Forcing::Sinusoid { .. }) {
                "forcing.angular_frequency"
            } else {
                "forcing.period"
            },
            period: start_response.period,
            swing: start_response.max_end_displacement - start_response.min_end_displacement,
            resolution: spine_dynamics::periodic::swing_resolution(
                &settings.response.integrator,
                problem.structure.chain.length_x(),
            ),
        });
    }
    let (stiffness, search, gradient, response) = match method {
        SearchMethod::Ga | SearchMethod::Pattern => {
            let search = match method {
                SearchMethod::Ga => genetic_algorithm(&objective, &bounds, Some(&start_u), &settings.ga, progress)?,
                _ => pattern_search(&mut |u| objective(u), &bounds, &start_u, &settings.pattern, progress)?,
            };
            (to_stiffness(&search.x), Some(search), None, None)
        }
        SearchMethod::Gradient => {
            let (given, ga) = match settings.gradient.start {
                GradientStart::Ga => {
                    let ga = genetic_algorithm(&objective, &bounds, Some(&start_u), &settings.ga, progress)?;
                    (to_stiffness(&ga.x), Some(ga))
                }
                GradientStart::Uniform | GradientStart::Case => (start_stiffness.clone(), None),
            };
            let (stiffness, point, report) =
                design_by_gradient(problem, &forcing, delta_d, settings, &given, progress)?;
            simulations.fetch_add(report.root_search_simulations + report.gradient_simulations, Ordering::Relaxed);
            (stiffness, ga, Some(report), point.map(|p| (p.energy, p.response)))
        }
    };
    // The best point's response in full, also when a time limit ended the search (one more
    // evaluation, so that the result reports a usable design). The gradient method's own last
    // point is that response already (on its fixed horizon).
    let (best, response) = match response {
        Some((energy, r)) => (evaluation_of(&r, energy, delta_d, settings), r),
        None => {
            simulations.fetch_add(1, Ordering::Relaxed);
            spine_stop::finishing(|| evaluate(problem, &forcing, &stiffness, delta_d, settings))
                .map_err(|source| DynamicDesignError::FinalDesign { delta_d, source })?
        }
    };
    let step_reach_time = step_reach_time(problem, &stiffness, &response, settings);
    Ok(PeriodicDesign {
        method,
        feasible: best.violation == 0.0,
        objective: best.objective,
        min_end_displacement: response.min_end_displacement,
        relative_error: (response.min_end_displacement - delta_d).abs() / delta_d.abs(),
        delta_d,
        stiffness,
        search,
        gradient,
        simulations: simulations.into_inner(),
        start_stiffness,
        start,
        response,
        step_reach_time,
        time_seconds: clock.elapsed().as_secs_f64(),
    })
}

/// [`PeriodicDesign::step_reach_time`] of the springs `stiffness`, from the static ends of their
/// periodic `response`.
fn step_reach_time(
    problem: &DynamicProblem,
    stiffness: &[f64],
    response: &PeriodicResponse,
    settings: &PeriodicDesignSettings,
) -> Option<f64> {
    let p = problem.with_stiffness(stiffness);
    let step = StepSettings {
        t_end: STEP_REACH_HORIZON,
        rise_fraction: settings.response.reach_fraction,
        integrator: settings.response.integrator.clone(),
        continuation: settings.response.continuation.clone(),
        ..StepSettings::default()
    };
    rise_time(&p.dynamics(Forcing::Step), &response.ends, &step, false).0
}

#[cfg(test)]
mod tests {
    use super::SearchMethod;

    #[test]
    fn the_printed_search_method_is_its_case_file_name() {
        for m in SearchMethod::ALL {
            assert_eq!(serde_json::to_value(m).unwrap(), m.to_string().as_str());
        }
    }
}
