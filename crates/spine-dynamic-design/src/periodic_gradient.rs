//! Eq. (37) by gradients: Ipopt on the springs with the exact gradients of the strain energy and of
//! the minimum end displacement over the settled period.
//!
//! * **Objective** `U(θ1(K); K) = ½ Σ K_j r_j²` (`r_j` the joint's relative deflection at the
//!   passive equilibrium `θ1`): `dU/dK_j = ½ r_j² + (∂U/∂θ)ᵀ dθ1/dK_j`, where `∂U/∂θ` is the
//!   springs' joint moments and `dθ1/dK` comes from the equilibrium `R(θ1, λ1; K) = 0` of eq. (5)
//!   by the implicit-function theorem (one factorisation of its bordered tridiagonal Jacobian, a
//!   solve per spring). The same `dθ1/dK` is the start of the trajectory's sensitivities, so the
//!   direct method costs nothing extra here (the adjoint of `spine-design` gives the same `dU/dK`
//!   with one solve, and the tests hold the two to each other through central differences).
//! * **Constraint** `min_t (X_{N+1}(t) − L_x) = δ_d` over the last of a fixed number of forcing
//!   periods: a horizon that does not depend on `K` keeps the function smooth. It is one period more
//!   than the start design needs to settle (`response.settle_tolerance`), at most
//!   `response.max_periods`; the final design's response reports whether its last two periods
//!   agree. The motion starts at rest at `θ1(K)`, so its sensitivities `S = ∂y/∂K` start at
//!   `(dθ1/dK, 0)`. At an interior minimum `Ẋ = 0`, so by the envelope theorem `d min/dK = ∇_y X ·
//!   S(t*)`. By default ([`Sensitivities::Adjoint`]) each simulation runs plain and keeps its
//!   steps; when Ipopt asks for the constraint's gradient (at accepted points only, not at its
//!   line-search trials) one backward sweep of the discrete adjoint of the Radau steps gives
//!   `λ(0)` for both minima, and `d min/dK = λ(0)ᵀ S(0) + ∫-part`
//!   ([`spine_dynamics::integrator::adjoint`]); the cost does not grow with the number of springs.
//!   With [`Sensitivities::Forward`] `S` itself is propagated through every step
//!   ([`spine_dynamics::system::Parameters::Springs`], `N + 1` columns). Both are exact derivatives
//!   of the computed motion and agree to round-off.
//! * **Two minima.** The minimum over time is not smooth where two local minima in time trade
//!   places. Both enter: the lowest local minimum as the equality `(x₁ − δ_d)/|δ_d| = 0` and the
//!   next lowest (or, when the period has one minimum, the end of the period) as
//!   `(x₂ − δ_d)/|δ_d| ≥ 0`. Away from a tie the second is inactive (`x₂ > x₁ = δ_d`); at a tie
//!   both are active with their own gradients, which is the linearisation of `min(x₁, x₂) = δ_d`
//!   on that branch.
//! * **Variables** `log10 K` (as for the searches; stiffness spans two decades), bounds
//!   `[log10 K_min, log10 K_max]`; the objective is scaled by its value at the start. The Hessian
//!   of the Lagrangian is Ipopt's L-BFGS approximation (the constraint's curvature would need
//!   second-order sensitivities).
//! * **Start**: by default the uniform springs that meet the equality (a bracketing root search on
//!   one common `log10 K`, as eq. (35)'s uniform start), or the case's springs (`start: "case"`;
//!   Fig. 10 also starts one run from the genetic algorithm's best).

use crate::bracket::illinois;
pub use crate::eq37_point::{eq37_point, eq37_values, sensitivities_used, Eq37Point};
use crate::error::DynamicDesignError;
use crate::periodic_settings::{GradientStart, PeriodicDesignSettings, Sensitivities};
use serde::Serialize;
use spine_dynamics::forcing::Forcing;
use spine_dynamics::integrator::Outcome;
use spine_dynamics::response::DynamicProblem;
use spine_ipopt::Problem;
use spine_search::{Evaluation, Progress};

/// A spring within this of a bound in `log10 K` (2.3e-5 relative) is reported at it: Ipopt's
/// interior point stops that close to an active bound at its tolerance 1e-6.
pub const AT_BOUND: f64 = 1e-5;

/// What the gradient method did.
#[derive(Clone, Debug, Serialize)]
pub struct GradientReport {
    /// Ipopt's status, or the stop (`time_limit`, `interrupted`) when the run was stopped from
    /// outside; and whether it converged.
    pub status: GradientStatus,
    pub converged: bool,
    pub iterations: usize,
    /// Where the method started: `uniform`, `case` or `ga` (the genetic algorithm's best).
    pub start: GradientStart,
    /// Uniform springs were asked for but none meet δ_d: the case's springs were the start.
    pub uniform_not_found: bool,
    /// Forcing periods of every simulation (one more than the start needs to settle).
    pub periods: usize,
    /// The uniform start's springs, N·m/rad, when it was found.
    pub uniform_stiffness: Option<f64>,
    /// Simulations of the root search and the start's settling, and of Ipopt's evaluations (with
    /// forward sensitivities, or plain with their steps kept for the adjoint).
    pub root_search_simulations: usize,
    pub gradient_simulations: usize,
    /// The constraint gradients' method, and the adjoint sweeps run (one per point where Ipopt
    /// asked for them; 0 with forward sensitivities).
    pub sensitivities: Sensitivities,
    pub adjoint_sweeps: usize,
    /// The two constraint values at the end, `(x − δ_d)/|δ_d|` of the lowest and the next local
    /// minimum, and Ipopt's multipliers of them.
    pub constraints: [f64; 2],
    pub multipliers: [f64; 2],
    /// Springs at a bound at the end (within [`AT_BOUND`] in `log10 K`), lower and upper.
    pub at_lower_bound: Vec<usize>,
    pub at_upper_bound: Vec<usize>,
}

/// The cached last point of the Ipopt problem.
type Cached = (Vec<f64>, Option<Eq37Point>);

struct Eq37<'a> {
    problem: &'a DynamicProblem,
    forcing: &'a Forcing,
    delta_d: f64,
    settings: &'a PeriodicDesignSettings,
    periods: usize,
    start: Vec<f64>,
    energy_scale: f64,
    cache: Option<Cached>,
    simulations: usize,
    /// Adjoint sweeps run (constraint gradients asked for at a new point).
    sweeps: usize,
    progress: &'a mut dyn FnMut(Progress),
}

impl Eq37<'_> {
    /// The functions at `u` (one plain simulation per new point).
    fn point(&mut self, u: &[f64]) -> Option<&Eq37Point> {
        if self.cache.as_ref().is_none_or(|(x, _)| x.as_slice() != u) {
            self.simulations += 1;
            let point =
                eq37_values(self.problem, self.forcing, &stiffness_of(u), self.delta_d, self.settings, self.periods);
            self.cache = Some((u.to_vec(), point));
        }
        self.cache.as_ref().and_then(|(_, p)| p.as_ref())
    }

    /// The functions at `u` with the constraint gradients (an adjoint sweep the first time they are
    /// asked for at a point: Ipopt asks at accepted points only).
    fn point_with_gradients(&mut self, u: &[f64]) -> Option<&Eq37Point> {
        self.point(u)?;
        let point = self.cache.as_mut().and_then(|(_, p)| p.as_mut())?;
        if point.pending() {
            self.sweeps += 1;
            if !point.constraint_gradients() {
                return None;
            }
        }
        self.cache.as_ref().and_then(|(_, p)| p.as_ref())
    }
}

/// The springs `K = 10^u`, N·m/rad, of the variables `u = log10 K` that every eq. (37) method
/// works in.
pub(crate) fn stiffness_of(u: &[f64]) -> Vec<f64> {
    u.iter().map(|v| 10f64.powf(*v)).collect()
}

/// `d/d log10 K = K ln 10 · d/dK`.
fn in_log10<'a>(u: &'a [f64], gradient: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
    let ln10 = std::f64::consts::LN_10;
    gradient.iter().zip(u).map(move |(g, v)| g * 10f64.powf(*v) * ln10)
}

impl Problem for Eq37<'_> {
    fn num_variables(&self) -> usize {
        self.start.len()
    }
    fn num_constraints(&self) -> usize {
        2
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(self.settings.stiffness_min.log10());
        upper.fill(self.settings.stiffness_max.log10());
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(0.0);
        upper[0] = 0.0;
        upper[1] = 2e19; // Ipopt's infinity
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.start);
    }
    fn objective(&mut self, x: &[f64], _: bool) -> Option<f64> {
        let scale = self.energy_scale;
        self.point(x).map(|p| p.energy / scale)
    }
    fn objective_gradient(&mut self, x: &[f64], _: bool, gradient: &mut [f64]) -> bool {
        let scale = self.energy_scale;
        let Some(p) = self.point(x) else { return false };
        let g: Vec<f64> = in_log10(x, &p.energy_gradient).map(|g| g / scale).collect();
        gradient.copy_from_slice(&g);
        true
    }
    fn constraints(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> bool {
        let delta_d = self.delta_d;
        let Some(p) = self.point(x) else { return false };
        for (gi, m) in g.iter_mut().zip(&p.minima) {
            *gi = (m.value - delta_d) / delta_d.abs();
        }
        true
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        (0..2).flat_map(|r| (0..self.start.len()).map(move |c| (r, c))).collect()
    }
    fn jacobian_values(&mut self, x: &[f64], _: bool, values: &mut [f64]) -> bool {
        let scale = self.delta_d.abs();
        let Some(p) = self.point_with_gradients(x) else { return false };
        let rows: Vec<f64> = p.minima.iter().flat_map(|m| in_log10(x, &m.gradient).map(|g| g / scale)).collect();
        values.copy_from_slice(&rows);
        true
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        None
    }
    fn hessian_values(&mut self, _: &[f64], _: bool, _: f64, _: &[f64], _: bool, _: &mut [f64]) -> bool {
        false
    }
    /// Reports the iteration (`U(θ1)` in J, the constraint violation in units of `|δ_d|`) and
    /// stops Ipopt when the run's time limit passes or a stop is requested.
    fn intermediate(&mut self, info: &spine_ipopt::IterationInfo) -> bool {
        let best = Evaluation { objective: info.objective * self.energy_scale, violation: info.primal_infeasibility };
        (self.progress)(Progress { iteration: info.iteration, evaluations: self.simulations, best });
        spine_stop::check().is_none()
    }
}

/// How eq. (37) by gradient ended: Ipopt's status, or the stop from outside that ended it (in
/// JSON the name of either: `solve_succeeded`, `time_limit`, …).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum GradientStatus {
    Ipopt(spine_ipopt::Status),
    Stopped(spine_stop::StopReason),
}

impl std::fmt::Display for GradientStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Ipopt(s) => f.write_str(&s.name()),
            Self::Stopped(r) => f.write_str(r.name()),
        }
    }
}

/// The start of eq. (37) by gradients in `log10 K`: the given springs (the case's or the GA's
/// best), or the uniform springs whose periodic response just meets δ_d (a root search, the given
/// springs where no uniform value meets it); with the start's name, the uniform value (N·m/rad)
/// and the simulations the search took.
fn gradient_start(
    problem: &DynamicProblem,
    forcing: &Forcing,
    delta_d: f64,
    settings: &PeriodicDesignSettings,
    given: &[f64],
) -> (Vec<f64>, GradientStart, Option<f64>, usize) {
    let (lo, hi) = (settings.stiffness_min.log10(), settings.stiffness_max.log10());
    let mut root_search_simulations = 0;
    let (start, name, uniform) = match settings.gradient.start {
        GradientStart::Case => (given.iter().map(|k| k.log10()).collect(), GradientStart::Case, None),
        GradientStart::Ga => (given.iter().map(|k| k.log10()).collect(), GradientStart::Ga, None),
        GradientStart::Uniform => {
            // min_t X − δ_d rises with the springs (a stiffer arch moves less); a design that
            // buckles or whose simulation fails counts as too soft (−∞).
            let mut residual = |u: f64| {
                root_search_simulations += 1;
                let mut p = problem.clone();
                p.design.stiffness = vec![10f64.powf(u); given.len()];
                match spine_dynamics::periodic::periodic_response(
                    &p,
                    forcing.clone(),
                    Some(delta_d),
                    &settings.response,
                ) {
                    Ok(r) if r.outcome == Outcome::Completed => (r.min_end_displacement - delta_d) / delta_d.abs(),
                    _ => f64::NEG_INFINITY,
                }
            };
            let ends = (residual(lo), residual(hi));
            if ends.0 < 0.0 && ends.1 >= 0.0 {
                let u = illinois((lo, hi), ends, &mut residual, &|r| r.abs() <= 1e-3 * settings.tolerance, 1e-9);
                (vec![u; given.len()], GradientStart::Uniform, Some(10f64.powf(u)))
            } else {
                let start = given.iter().map(|k| k.log10()).collect();
                (start, GradientStart::Case, None)
            }
        }
    };
    (start, name, uniform, root_search_simulations)
}

/// Ipopt's options for eq. (37): the gradient settings' tolerance, iteration limit and barrier
/// strategy, the equality's band, L-BFGS.
fn ipopt_options(settings: &PeriodicDesignSettings) -> spine_ipopt::Options {
    let gradient = &settings.gradient;
    spine_ipopt::Options::new()
        .number("tol", gradient.tolerance)
        // Ipopt needs a positive value; a band as narrow as the case format allows (1e-322)
        // would give 0 here.
        .number("constr_viol_tol", (1e-3 * settings.tolerance).max(1e-300))
        .integer("max_iter", gradient.max_iterations as i64)
        .string("hessian_approximation", "limited-memory")
        .string("mu_strategy", gradient.barrier_strategy.name())
}

/// Eq. (37) by Ipopt from `given` springs (N·m/rad: the case's or the GA's best) or from the
/// uniform springs that meet δ_d (`settings.gradient.start`): the final springs, the final point
/// (its functions and response) and the report.
pub fn design_by_gradient(
    problem: &DynamicProblem,
    forcing: &Forcing,
    delta_d: f64,
    settings: &PeriodicDesignSettings,
    given: &[f64],
    progress: &mut dyn FnMut(Progress),
) -> Result<(Vec<f64>, Option<Eq37Point>, GradientReport), DynamicDesignError> {
    let gradient = &settings.gradient;
    let (lo, hi) = (settings.stiffness_min.log10(), settings.stiffness_max.log10());
    let (start, start_name, uniform_stiffness, mut root_search_simulations) =
        gradient_start(problem, forcing, delta_d, settings, given);
    // The horizon: one period more than the start needs to settle.
    let mut p = problem.clone();
    p.design.stiffness = stiffness_of(&start);
    root_search_simulations += 1;
    let settle = spine_dynamics::periodic::periodic_response(&p, forcing.clone(), Some(delta_d), &settings.response)
        .map_or(settings.response.max_periods, |r| r.periods_run);
    let periods = (settle + 1).clamp(2, settings.response.max_periods.max(2));
    let mut eq37 = Eq37 {
        problem,
        forcing,
        delta_d,
        settings,
        periods,
        energy_scale: 1.0,
        start: start.clone(),
        cache: None,
        simulations: 0,
        sweeps: 0,
        progress,
    };
    eq37.energy_scale = eq37.point(&start).map_or(1.0, |p| p.energy.abs().max(1e-300));
    let sol = spine_ipopt::solve(&mut eq37, &ipopt_options(settings))
        .map_err(|source| DynamicDesignError::Ipopt { equation: "37", source })?;
    // The final point out of the cache (evaluated there unless Ipopt's last trial was elsewhere),
    // with its constraint gradients.
    eq37.point_with_gradients(&sol.x);
    let point = eq37.cache.take().and_then(|(_, p)| p);
    let at_bound = |bound: f64| (0..sol.x.len()).filter(|&j| (sol.x[j] - bound).abs() <= AT_BOUND).collect();
    // A stop from outside makes the evaluations fail before Ipopt's next iteration asks: say so
    // instead of Ipopt's reading of the failures (`invalid_number_detected`).
    let converged = sol.status.is_converged();
    let stopped = if converged { None } else { spine_stop::check() };
    let report = GradientReport {
        status: stopped.map_or(GradientStatus::Ipopt(sol.status), GradientStatus::Stopped),
        converged,
        iterations: sol.iterations,
        start: start_name,
        uniform_not_found: gradient.start == GradientStart::Uniform && start_name == GradientStart::Case,
        periods,
        uniform_stiffness,
        root_search_simulations,
        gradient_simulations: eq37.simulations,
        sensitivities: sensitivities_used(settings),
        adjoint_sweeps: eq37.sweeps,
        constraints: [sol.g[0], sol.g[1]],
        multipliers: [sol.lambda[0], sol.lambda[1]],
        at_lower_bound: at_bound(lo),
        at_upper_bound: at_bound(hi),
    };
    Ok((stiffness_of(&sol.x), point, report))
}

#[cfg(test)]
mod tests {
    use super::*;
    use spine_ipopt::{BarrierStrategy, OptionValue};

    /// The gradient settings reach Ipopt: the barrier strategy as `mu_strategy`, the tolerance,
    /// the iteration limit and the band.
    #[test]
    fn the_gradient_settings_become_ipopts_options() {
        for strategy in [BarrierStrategy::Adaptive, BarrierStrategy::Monotone] {
            let mut settings = PeriodicDesignSettings::default();
            settings.gradient.barrier_strategy = strategy;
            (settings.gradient.tolerance, settings.gradient.max_iterations, settings.tolerance) = (1e-7, 42, 0.02);
            let options = ipopt_options(&settings);
            assert_eq!(options.get("mu_strategy"), Some(&OptionValue::Str(strategy.name().into())));
            assert_eq!(options.get("tol"), Some(&OptionValue::Num(1e-7)));
            assert_eq!(options.get("max_iter"), Some(&OptionValue::Int(42)));
            assert_eq!(options.get("constr_viol_tol"), Some(&OptionValue::Num(2e-5)));
        }
        assert_eq!(PeriodicDesignSettings::default().gradient.barrier_strategy, BarrierStrategy::Adaptive);
    }
}
