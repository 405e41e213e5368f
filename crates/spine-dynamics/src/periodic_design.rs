//! The periodic-load design of eq. (37): minimise the passive strain energy `U(θ1; K)` over the
//! springs `K`, subject to the passive equilibrium, the equations of motion under the periodic
//! force, and `min_t (X_{N+1}(t) − L_x) = δ_d` over a settled period.
//!
//! The constraint is a minimum over time of a simulated motion, so it is not smooth; as in the paper
//! it is handled by gradient-free searches ([`spine_search`]): a genetic algorithm or a pattern
//! search. The search variables are `log10 K_i` (stiffness spans two decades); the equality is met
//! within a band `|min_t(X − L_x) − δ_d| ≤ tolerance · |δ_d|`, and points are compared by Deb's
//! feasibility rules with the violation measured in units of `|δ_d|`. A design whose passive or
//! loaded equilibrium is not stable, or whose simulation fails, is worse than any other point.

use crate::forcing::Forcing;
use crate::integrator::Options;
use crate::periodic::{simulate_periodic, PeriodicResponse, PeriodicSettings};
use crate::response::{DynamicProblem, DynamicsError};
use serde::{Deserialize, Serialize};
use spine_search::{
    genetic_algorithm, pattern_search, Bounds, Evaluation, GaSettings, PatternSettings, Progress, SearchResult,
};

/// Which search solves eq. (37).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SearchMethod {
    Ga,
    Pattern,
}

impl std::fmt::Display for SearchMethod {
    /// As in a case file: `ga`, `pattern`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(match self {
            Self::Ga => "ga",
            Self::Pattern => "pattern",
        })
    }
}

/// Settings of eq. (37).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct PeriodicDesignSettings {
    /// Stiffness bounds, N·m/rad (the paper's 10² and 10⁴).
    pub stiffness_min: f64,
    pub stiffness_max: f64,
    /// Width of the equality band, as a fraction of `|δ_d|`.
    pub tolerance: f64,
    pub ga: GaSettings,
    pub pattern: PatternSettings,
    /// The periodic response of every candidate.
    pub response: PeriodicSettings,
}

impl Default for PeriodicDesignSettings {
    fn default() -> Self {
        // The searches compare hundreds of responses through J and a 1 % displacement band, which
        // need far less than the single-simulation default (T_90 to 1e-6, about 8 times dearer).
        let integrator = Options { rtol: 1e-6, atol: 1e-8, ..Options::default() };
        let response = PeriodicSettings {
            max_periods: 6,
            settle_tolerance: 1e-3,
            samples_per_period: 200,
            integrator,
            ..Default::default()
        };
        Self {
            stiffness_min: 1e2,
            stiffness_max: 1e4,
            tolerance: 0.01,
            ga: GaSettings { population: 24, generations: 25, stall_generations: 10, ..Default::default() },
            pattern: PatternSettings {
                initial_mesh: 0.125,
                mesh_tolerance: 1e-3,
                max_evaluations: 600,
                ..Default::default()
            },
            response,
        }
    }
}

/// What eq. (37) found.
#[derive(Clone, Debug, Serialize)]
pub struct PeriodicDesign {
    pub method: SearchMethod,
    /// The search's own status (mesh converged, generation limit, …).
    pub search: SearchResult,
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
    pub time_seconds: f64,
}

/// Passive strain energy and periodic response of `problem` with springs `stiffness`.
fn evaluate(
    problem: &DynamicProblem,
    forcing: &Forcing,
    stiffness: &[f64],
    delta_d: f64,
    settings: &PeriodicDesignSettings,
) -> Result<(Evaluation, PeriodicResponse), DynamicsError> {
    let mut p = problem.clone();
    p.design.stiffness = stiffness.to_vec();
    let ends = p.static_ends(&settings.response.continuation)?;
    let strain = spine_model::energy::strain_energy(&ends.theta1, &p.design.theta0, stiffness);
    let d = p.dynamics(forcing.clone());
    let r = simulate_periodic(&d, ends, p.structure.chain.length_x(), Some(delta_d), &settings.response);
    let violation = if r.outcome == crate::Outcome::Completed {
        (((r.min_end_displacement - delta_d).abs() / delta_d.abs()) - settings.tolerance).max(0.0)
    } else {
        f64::INFINITY
    };
    Ok((Evaluation { objective: strain, violation }, r))
}

/// Solves eq. (37) for the springs of `problem` (its design's `θ0` is kept; its `K` is the start).
pub fn design_periodic(
    problem: &DynamicProblem,
    forcing: Forcing,
    delta_d: f64,
    method: SearchMethod,
    settings: &PeriodicDesignSettings,
    progress: &mut dyn FnMut(Progress),
) -> Result<PeriodicDesign, DynamicsError> {
    let clock = std::time::Instant::now();
    let n_springs = problem.design.stiffness.len();
    let (lo, hi) = (settings.stiffness_min.log10(), settings.stiffness_max.log10());
    let bounds = Bounds { lower: vec![lo; n_springs], upper: vec![hi; n_springs] };
    let to_stiffness = |u: &[f64]| u.iter().map(|v| 10f64.powf(*v)).collect::<Vec<f64>>();
    let start_stiffness: Vec<f64> =
        problem.design.stiffness.iter().map(|k| k.clamp(settings.stiffness_min, settings.stiffness_max)).collect();
    let start_u: Vec<f64> = start_stiffness.iter().map(|k| k.log10()).collect();
    let objective = |u: &[f64]| match evaluate(problem, &forcing, &to_stiffness(u), delta_d, settings) {
        Ok((e, _)) => e,
        Err(_) => Evaluation::failed(),
    };
    match method {
        SearchMethod::Ga => settings.ga.validate()?,
        SearchMethod::Pattern => settings.pattern.validate()?,
    }
    let start = objective(&start_u);
    let search = match method {
        SearchMethod::Ga => genetic_algorithm(&objective, &bounds, Some(&start_u), &settings.ga, progress)?,
        SearchMethod::Pattern => pattern_search(&mut |u| objective(u), &bounds, &start_u, &settings.pattern, progress)?,
    };
    let stiffness = to_stiffness(&search.x);
    // The best point's response in full, also when a time limit ended the search (one more
    // evaluation, so that the result reports a usable design).
    let (best, response) =
        spine_stop::without_time_limit(|| evaluate(problem, &forcing, &stiffness, delta_d, settings))?;
    Ok(PeriodicDesign {
        method,
        feasible: best.violation == 0.0,
        objective: best.objective,
        min_end_displacement: response.min_end_displacement,
        relative_error: (response.min_end_displacement - delta_d).abs() / delta_d.abs(),
        delta_d,
        stiffness,
        search,
        start_stiffness,
        start,
        response,
        time_seconds: clock.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::SearchMethod;

    #[test]
    fn the_printed_search_method_is_its_case_file_name() {
        for m in [SearchMethod::Ga, SearchMethod::Pattern] {
            assert_eq!(serde_json::to_value(m).unwrap(), m.to_string().as_str());
        }
    }
}
