//! The damping design of eq. (35): `min ½ Σ C_i²` over the dampers, `C_min ≤ C_i ≤ C_max`
//! (the paper: 1 ≤ C ≤ 10³ N·m·s/rad), subject to the equations of motion and `T_90 = T_d`.
//!
//! Ipopt solves it with the constraint written as `T_90(C) / T_d − 1 = 0`; its gradient is the event
//! sensitivity `dT_90/dC = −(∇g · S(T_90))/ġ`, by one adjoint sweep of the plain run
//! (`spine_dynamics::integrator::adjoint`; forward sensitivities for TR-BDF2), and the Hessian of the
//! Lagrangian is Ipopt's L-BFGS approximation (the constraint's curvature has no cheap exact form).
//! The start is the uniform damping that meets `T_90 = T_d` (a bracketing root search on one common
//! `ln C`: Illinois regula falsi, 8 to 11 simulations where bisection took 23), so the
//! optimiser starts feasible and only redistributes damping.

use crate::bracket::illinois;
use crate::error::DynamicDesignError;
use serde::{Deserialize, Serialize};
use spine_dynamics::eom::Dynamics;
use spine_dynamics::forcing::Forcing;
use spine_dynamics::response::{rise_time, simulate_step, DynamicProblem, StaticEnds, StepResponse, StepSettings};
use spine_ipopt::{Problem, Status};

/// Settings of eq. (35).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct DampingSettings {
    /// Lower and upper damper bounds, N·m·s/rad.
    pub damping_min: f64,
    pub damping_max: f64,
    /// Ipopt's tolerance and iteration limit.
    pub tolerance: f64,
    pub max_iterations: usize,
    /// The step response used for every evaluation (its `rise_fraction` defines `T_90`).
    pub step: StepSettings,
    /// Raise `damping_min` until the design's step response is over-damped, as the paper sets its
    /// lower limit "through trial and error" (Sec. 4.2): a bisection on `ln C_min` between the
    /// stated limit and the uniform start (to 2 %), one eq. (35) solve per trial.
    pub overdamped: bool,
}

impl Default for DampingSettings {
    fn default() -> Self {
        let mut step = StepSettings::default();
        step.integrator.rtol = 1e-8;
        step.integrator.atol = 1e-10;
        step.samples = 401;
        Self { damping_min: 1.0, damping_max: 1e3, tolerance: 1e-7, max_iterations: 200, step, overdamped: false }
    }
}

/// What the damping design found.
#[derive(Clone, Debug, Serialize)]
pub struct DampingDesign {
    /// Ipopt's status, or that no uniform damping in the bounds reaches `T_d`.
    pub status: DampingStatus,
    pub converged: bool,
    pub iterations: usize,
    pub target_rise_time: f64,
    /// The uniform start `C_0` (every damper equal), N·m·s/rad.
    pub uniform_start: Option<f64>,
    /// Optimised dampers, N·m·s/rad.
    pub damping: Vec<f64>,
    /// `½ Σ C_i²`.
    pub objective: f64,
    /// `T_90` of the final design (re-simulated), s, and `|T_90 − T_d| / T_d`.
    pub rise_time: Option<f64>,
    pub rise_time_error: Option<f64>,
    /// Step responses simulated (with sensitivities or without).
    pub simulations: usize,
    pub time_seconds: f64,
    /// The final design's step response.
    pub response: StepResponse,
    /// The search for an over-damping lower limit, when [`DampingSettings::overdamped`] asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lower_limit: Option<LowerLimitSearch>,
}

/// The "trial and error" on the dampers' lower limit: each limit tried and whether its design's
/// step response was over-damped.
#[derive(Clone, Debug, Serialize)]
pub struct LowerLimitSearch {
    /// The case's `damping_min`, N·m·s/rad.
    pub stated: f64,
    /// The limit of the reported design (the smallest over-damped one found), N·m·s/rad; `None`
    /// when no limit up to the uniform start gives an over-damped design (then the design at the
    /// stated limit is reported).
    pub used: Option<f64>,
    /// `(limit, over-damped)` in the order tried.
    pub trials: Vec<(f64, bool)>,
}

/// Bisection steps of the lower-limit search at most (the bracket shrinks to 2 % well before).
const MAX_LIMIT_TRIALS: usize = 12;

/// Solves eq. (35) for the rise time `target` (s); with [`DampingSettings::overdamped`], raises
/// the dampers' lower limit until the design is over-damped ([`LowerLimitSearch`]).
pub fn design_damping(
    problem: &DynamicProblem,
    target: f64,
    settings: &DampingSettings,
) -> Result<DampingDesign, DynamicDesignError> {
    let clock = std::time::Instant::now();
    let first = design_with_limit(problem, target, settings, None)?;
    if !settings.overdamped {
        return Ok(first);
    }
    let over = |d: &DampingDesign| d.converged && d.response.overdamping.is_overdamped();
    let mut trials = vec![(settings.damping_min, over(&first))];
    let mut simulations = first.simulations;
    // The over-damped design of the smallest limit tried above the stated one.
    let mut raised = None;
    if let (false, Some(c0)) = (trials[0].1, first.uniform_start) {
        let mut limited = |c_min: f64, trials: &mut Vec<(f64, bool)>| -> Result<DampingDesign, DynamicDesignError> {
            // At the uniform start the limit leaves one feasible point, the uniform design itself.
            let uniform = (c_min == c0).then_some(c0);
            let d = design_with_limit(
                problem,
                target,
                &DampingSettings { damping_min: c_min, ..settings.clone() },
                uniform,
            )?;
            simulations += d.simulations;
            trials.push((c_min, over(&d)));
            Ok(d)
        };
        let top = limited(c0, &mut trials)?;
        if over(&top) {
            let (mut lo, mut hi) = (settings.damping_min.ln(), c0.ln());
            raised = Some(top);
            while hi - lo > 0.02_f64.ln_1p() && trials.len() < MAX_LIMIT_TRIALS {
                let mid = 0.5 * (lo + hi);
                let d = limited(mid.exp(), &mut trials)?;
                if over(&d) {
                    (hi, raised) = (mid, Some(d));
                } else {
                    lo = mid;
                }
            }
        }
    }
    // The reported design is the stated limit's when it is over-damped or nothing above it is.
    let used = trials.iter().filter(|t| t.1).map(|t| t.0).reduce(f64::min);
    let mut design = raised.unwrap_or(first);
    design.simulations = simulations;
    design.time_seconds = clock.elapsed().as_secs_f64();
    design.lower_limit = Some(LowerLimitSearch { stated: settings.damping_min, used, trials });
    Ok(design)
}

/// How an eq. (35) design ended: Ipopt's status, or no feasible uniform start (then Ipopt is not
/// run). Serialised as Ipopt's snake_case name, `"uniform-start-infeasible"` or `"uniform-only"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DampingStatus {
    Ipopt(Status),
    /// No uniform damping in `[C_min, C_max]` reaches `T_d`.
    UniformStartInfeasible,
    /// The lower limit is the uniform start `C_0`: since `T_90` grows with every damper, every
    /// damper at `C_0` is the only point with `C ≥ C_0` and `T_90 = T_d`, so it is eq. (35)'s
    /// solution without an Ipopt run (Ipopt, started on that bound, has no interior to move in).
    UniformOnly,
}

impl DampingStatus {
    /// The name written to result files.
    pub fn name(self) -> String {
        match self {
            Self::Ipopt(s) => s.name(),
            Self::UniformStartInfeasible => "uniform-start-infeasible".into(),
            Self::UniformOnly => "uniform-only".into(),
        }
    }
}

impl std::fmt::Display for DampingStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(&self.name())
    }
}

impl Serialize for DampingStatus {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.name())
    }
}

/// `|T_90 − T_d| / T_d` at which an eq. (35) design is accepted as meeting its target (0.5 %).
pub const RISE_TIME_ACCEPTANCE: f64 = 5e-3;

impl DampingDesign {
    /// Ipopt converged and the re-simulated `T_90` is within [`RISE_TIME_ACCEPTANCE`] of `T_d`.
    pub fn meets_target(&self) -> bool {
        self.converged && self.rise_time_error.is_some_and(|e| e <= RISE_TIME_ACCEPTANCE)
    }
}

/// The last dampers `C` evaluated, with `T_90(C)` and `dT_90/dC` (absent when the response does not rise).
type Cached = (Vec<f64>, Option<f64>, Option<Vec<f64>>);

struct Eq35<'a> {
    base: &'a Dynamics,
    ends: &'a StaticEnds,
    settings: &'a DampingSettings,
    target: f64,
    start: Vec<f64>,
    cache: Option<Cached>,
    simulations: usize,
}

impl Eq35<'_> {
    fn evaluate(&mut self, c: &[f64]) -> (Option<f64>, Option<Vec<f64>>) {
        if let Some((x, t, g)) = &self.cache {
            if x.as_slice() == c {
                return (*t, g.clone());
            }
        }
        let mut d = self.base.clone();
        d.damping = c.to_vec();
        let (t, g) = rise_time(&d, self.ends, &self.settings.step, true);
        self.simulations += 1;
        self.cache = Some((c.to_vec(), t, g.clone()));
        (t, g)
    }
}

impl Problem for Eq35<'_> {
    fn num_variables(&self) -> usize {
        self.start.len()
    }
    fn num_constraints(&self) -> usize {
        1
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(self.settings.damping_min);
        upper.fill(self.settings.damping_max);
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower[0] = 0.0;
        upper[0] = 0.0;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.start);
    }
    fn objective(&mut self, x: &[f64], _: bool) -> Option<f64> {
        Some(0.5 * x.iter().map(|c| c * c).sum::<f64>())
    }
    fn objective_gradient(&mut self, x: &[f64], _: bool, gradient: &mut [f64]) -> bool {
        gradient.copy_from_slice(x);
        true
    }
    fn constraints(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> bool {
        match self.evaluate(x).0 {
            Some(t) => {
                g[0] = t / self.target - 1.0;
                true
            }
            None => false,
        }
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        (0..self.start.len()).map(|j| (0, j)).collect()
    }
    fn jacobian_values(&mut self, x: &[f64], _: bool, values: &mut [f64]) -> bool {
        match self.evaluate(x).1 {
            Some(grad) => {
                for (v, g) in values.iter_mut().zip(grad) {
                    *v = g / self.target;
                }
                true
            }
            None => false,
        }
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        None
    }
    fn hessian_values(&mut self, _: &[f64], _: bool, _: f64, _: &[f64], _: bool, _: &mut [f64]) -> bool {
        false
    }
    /// Stops Ipopt when the run's time limit passes or a stop is requested.
    fn intermediate(&mut self, _: &spine_ipopt::IterationInfo) -> bool {
        spine_stop::check().is_none()
    }
}

/// `T_90` of uniform damping `c`.
fn uniform_rise_time(base: &Dynamics, ends: &StaticEnds, settings: &StepSettings, c: f64) -> Option<f64> {
    let mut d = base.clone();
    d.damping = vec![c; d.damping.len()];
    rise_time(&d, ends, settings, false).0
}

/// Solves eq. (35) for the rise time `target` (s) with the dampers' bounds of `settings`; with
/// `uniform` (the uniform start `C_0`, found before, equal to `damping_min`), the uniform design
/// is the solution ([`DampingStatus::UniformOnly`]).
fn design_with_limit(
    problem: &DynamicProblem,
    target: f64,
    settings: &DampingSettings,
    uniform: Option<f64>,
) -> Result<DampingDesign, DynamicDesignError> {
    let clock = std::time::Instant::now();
    let ends = problem.static_ends(&settings.step.continuation)?;
    let mut settings = settings.clone();
    settings.step.t_end = settings.step.t_end.max(3.0 * target);
    let settings = &settings;
    let base = problem.dynamics(Forcing::Step);
    let n_dampers = base.damping.len();
    let mut simulations = 0;

    // Uniform start: T_90 grows with the damping in the overdamped range; a bracketing root
    // search on ln C (Illinois regula falsi, a bisection step where the slow end has no rise).
    let (lo, hi) = (settings.damping_min.ln(), settings.damping_max.ln());
    let mut root_search = || {
        let t_lo = uniform_rise_time(&base, &ends, &settings.step, lo.exp());
        let t_hi = uniform_rise_time(&base, &ends, &settings.step, hi.exp());
        simulations += 2;
        // Not reaching the rise within t_end counts as slower than any target below t_end.
        let bracketed = matches!(t_lo, Some(a) if a <= target) && t_hi.is_none_or(|b| target <= b);
        bracketed.then(|| {
            // Not reaching the rise within t_end counts as slower than any target (+∞).
            let mut residual = |x: f64| {
                simulations += 1;
                uniform_rise_time(&base, &ends, &settings.step, x.exp()).map_or(f64::INFINITY, |t| t - target)
            };
            let ends_at = (t_lo.map_or(f64::INFINITY, |t| t - target), t_hi.map_or(f64::INFINITY, |t| t - target));
            illinois((lo, hi), ends_at, &mut residual, &|r| r.abs() <= 1e-10 * target, 1e-6).exp()
        })
    };
    let uniform_start = if uniform.is_some() { uniform } else { root_search() };

    let (status, converged, iterations, damping) = match uniform_start {
        None => (DampingStatus::UniformStartInfeasible, false, 0, vec![settings.damping_min; n_dampers]),
        Some(c0) if uniform.is_some() => (DampingStatus::UniformOnly, true, 0, vec![c0; n_dampers]),
        Some(c0) => {
            let mut eq35 = Eq35 {
                base: &base,
                ends: &ends,
                settings,
                target,
                start: vec![c0; n_dampers],
                cache: None,
                simulations: 0,
            };
            let options = spine_ipopt::Options::new()
                .number("tol", settings.tolerance)
                .number("constr_viol_tol", 1e-9)
                .integer("max_iter", settings.max_iterations as i64)
                .string("hessian_approximation", "limited-memory")
                .string("mu_strategy", "adaptive");
            let sol = spine_ipopt::solve(&mut eq35, &options)
                .map_err(|source| DynamicDesignError::Ipopt { equation: "35", source })?;
            simulations += eq35.simulations;
            (DampingStatus::Ipopt(sol.status), sol.status.is_converged(), sol.iterations, sol.x)
        }
    };
    let mut d = base.clone();
    d.damping = damping.clone();
    let response = simulate_step(&d, ends, &settings.step, false);
    simulations += 1;
    let rise_time = response.rise_time;
    Ok(DampingDesign {
        status,
        converged,
        iterations,
        target_rise_time: target,
        uniform_start,
        objective: 0.5 * damping.iter().map(|c| c * c).sum::<f64>(),
        damping,
        rise_time,
        rise_time_error: rise_time.map(|t| (t - target).abs() / target),
        simulations,
        time_seconds: clock.elapsed().as_secs_f64(),
        response,
        lower_limit: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With the lower limit at the uniform start, the design is the uniform one: converged,
    /// every damper at `C_0`, and `T_90 = T_d` to the root search's accuracy.
    #[test]
    fn a_lower_limit_at_the_uniform_start_leaves_the_uniform_design() {
        let (p, target) = (spine_dynamics::fixtures::arch_problem(5, 20.0), 0.2);
        let settings = DampingSettings::default();
        let c0 = design_with_limit(&p, target, &settings, None).unwrap().uniform_start.unwrap();
        let at = DampingSettings { damping_min: c0, ..settings };
        let d = design_with_limit(&p, target, &at, Some(c0)).unwrap();
        assert_eq!((d.status, d.converged, d.iterations), (DampingStatus::UniformOnly, true, 0));
        assert!(d.damping.iter().all(|&c| c == c0) && d.damping.len() == 6, "{:?}", d.damping);
        assert!(d.meets_target() && d.rise_time_error.unwrap() < 1e-5, "T90 = {:?}", d.rise_time);
        assert_eq!(d.status.name(), "uniform-only");
    }
}
