//! What a design run reports, recomputed from the design itself so that both formulations are
//! judged by the same numbers.

pub use crate::solver_report::{LevelReport, RefinementReport, SolverReport};
pub use crate::warnings::{DesignWarning, LoadCase};

use crate::objective::{Equilibria, Measures};
use crate::problem::DesignProblem;
use crate::settings::{Formulation, SolverSettings};
pub use crate::violations::{Violations, IPOPT_BOUND_RELAX_FACTOR};
use serde::{Deserialize, Serialize};
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::kinematics::{end_x, link_lengths, node_positions};
use spine_model::{Design, LinkLoads, State};
use spine_solve::{solve_static, stability, EquilibriumSolution, EquilibriumStatus, Stability, StaticSolution};

/// One load state of the result.
#[derive(Clone, Debug, Serialize)]
pub struct StateReport {
    /// Absolute link angles, rad.
    pub theta: Vec<f64>,
    /// Slider reaction λ, N.
    pub lambda: f64,
    /// Node coordinates `(X_j, Y_j)`, m, `j = 1..N+1`.
    pub nodes: Vec<(f64, f64)>,
    /// Largest equilibrium residual (joint rows N·m, Φ row m).
    pub residual: f64,
    /// Smallest eigenvalue of the reduced Hessian and the verdict.
    pub stability: Stability,
}

/// Whether the optimiser's `θ1`, `θ2` are the equilibria reached by loading the design from `θ0`
/// (continuation), which is what the physical structure does.
#[derive(Clone, Debug, Serialize)]
pub struct LoadPathCheck {
    /// Both paths reach their full load and end within `1e-6` rad of the optimiser's states.
    pub consistent: bool,
    /// How the passive path ended.
    pub passive_status: EquilibriumStatus,
    /// How the loaded path ended; `null` when the passive path did not reach its load.
    pub loaded_status: Option<EquilibriumStatus>,
    /// Largest `|θ_optimiser − θ_path|`, rad (∞ when a path did not reach its load).
    pub passive_angle_difference: f64,
    pub loaded_angle_difference: f64,
}

impl LoadPathCheck {
    /// Compares the optimiser's states with the ends of the two load paths.
    fn compare(passive: Option<&StateReport>, loaded: Option<&StateReport>, path: &StaticSolution) -> Self {
        let difference = |a: Option<&StateReport>, b: Option<&EquilibriumSolution>| match (a, b) {
            (Some(a), Some(b)) if b.load_factor == 1.0 => {
                a.theta.iter().zip(&b.state.theta).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            }
            _ => f64::INFINITY,
        };
        let passive_angle_difference = difference(passive, Some(&path.passive));
        let loaded_angle_difference = difference(loaded, path.loaded.as_ref());
        LoadPathCheck {
            consistent: passive_angle_difference <= 1e-6 && loaded_angle_difference <= 1e-6,
            passive_status: path.passive.status,
            loaded_status: path.loaded.as_ref().map(|l| l.status),
            passive_angle_difference,
            loaded_angle_difference,
        }
    }
}

/// The result of one design run.
#[derive(Clone, Debug, Serialize)]
pub struct DesignResult {
    pub formulation: Formulation,
    pub solver: SolverReport,
    /// The criterion minimised ([`crate::objective::Objective`]; `strain_energy` for the paper's eq. (33)).
    pub criterion: crate::objective::Objective,
    /// The NLP's objective, recomputed from the final design and states: for the paper's
    /// criterion `J = U(θ1; θ0, K)`, J ([`crate::objective::Objective::value`] gives each criterion's).
    pub objective: f64,
    /// Every criterion's measure of the reported design (`None` without equilibria).
    pub measures: Option<crate::objective::Measures>,
    pub design: Design,
    pub stiffness_scale: f64,
    /// Unloaded node coordinates, m.
    pub unloaded_nodes: Vec<(f64, f64)>,
    /// `θ1` (passive load) and `θ2` (passive + actuation); absent when the reduced space ended at a
    /// design without equilibria.
    pub passive: Option<StateReport>,
    pub loaded: Option<StateReport>,
    /// `θ3`, the equilibrium under the compliance's load case ([`crate::objective::Objective::Compliance`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub probe: Option<StateReport>,
    /// `X_{N+1}(θ2) − L_x`, m, and the target `δ_d`.
    pub end_displacement: Option<f64>,
    pub delta_d: f64,
    pub violations: Option<Violations>,
    pub load_path: LoadPathCheck,
    /// Notes on the start point (projection into the bounds, start states).
    pub start_notes: Vec<String>,
    /// Everything a reader must not miss: non-convergence, unstable equilibria, a state off the
    /// load path. Empty for a clean optimum. (Written to `result.json` as sentences.)
    pub warnings: Vec<DesignWarning>,
    /// The levels of a mesh-sequenced run (absent for a single solve).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refinement: Option<RefinementReport>,
    /// The second-order certificate of the reported point ([`crate::certificate`]); `None` for a
    /// run that did not converge (no first-order point to certify) or was not certified.
    pub certificate: Option<crate::certificate::Certificate>,
    /// Points left on the way here because they were not minima ([`crate::solve::settle`]).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub escapes: Vec<Escape>,
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn state_report(problem: &DesignProblem, design: &Design, loads: &LinkLoads, state: &State) -> StateReport {
    let spans = &problem.structure.chain.spans;
    let (residual, jac) = residual_and_state_jacobian(spans, design, loads, state);
    let lengths = link_lengths(spans, &design.theta0);
    StateReport {
        theta: state.theta.clone(),
        lambda: state.lambda,
        nodes: node_positions(&lengths, &state.theta),
        residual: max_abs(&residual),
        stability: stability::certify(&jac),
    }
}

impl DesignResult {
    /// Recomputes every reported quantity from `design` and the states (`probe`: `θ3` of the
    /// compliance criterion), checks the constraints, the stability of the equilibria and the
    /// load path, and lists warnings.
    #[allow(clippy::too_many_arguments)]
    pub fn check(
        problem: &DesignProblem,
        formulation: Formulation,
        design: Design,
        states: Option<(State, State)>,
        probe: Option<State>,
        solver: SolverReport,
        start_notes: Vec<String>,
        settings: &SolverSettings,
    ) -> Self {
        let continuation = &settings.continuation;
        let spans = &problem.structure.chain.spans;
        let lx = problem.structure.chain.length_x();
        let lengths = link_lengths(spans, &design.theta0);
        let unloaded_nodes = node_positions(&lengths, &design.theta0);
        let path = solve_static(&problem.static_problem(&design), continuation);
        let mut warnings = Vec::new();
        if !solver.converged {
            warnings.push(DesignWarning::NotConverged { status: solver.status });
        }

        let probe_loads = problem.objective.probe_loads(&problem.structure.chain);
        let probe_report = match (&probe, &probe_loads) {
            (Some(state), Some(loads)) => Some(state_report(problem, &design, loads, state)),
            _ => None,
        };
        if let Some(report) = &probe_report {
            if !report.stability.stable {
                let min_eigenvalue = report.stability.min_eigenvalue;
                warnings.push(DesignWarning::Unstable { equilibrium: LoadCase::Probe, min_eigenvalue });
            }
            let allowed = settings.constraint_tolerance;
            if report.residual.is_nan() || report.residual > allowed {
                let (part, violation) = ("probe_equilibrium", report.residual);
                warnings.push(DesignWarning::ConstraintViolated { part, violation, allowed });
            }
        }
        let (passive, loaded, end_displacement, violations, objective, measures) = match &states {
            Some((s1, s2)) => {
                let r1 = state_report(problem, &design, &problem.passive_loads(), s1);
                let r2 = state_report(problem, &design, &problem.total_loads(), s2);
                let end = end_x(spans, &design.theta0, &s2.theta) - lx;
                let v = Violations::measure(problem, &design, (r1.residual, r2.residual), end);
                for (equilibrium, report) in [(LoadCase::Passive, &r1), (LoadCase::Loaded, &r2)] {
                    if !report.stability.stable {
                        let min_eigenvalue = report.stability.min_eigenvalue;
                        warnings.push(DesignWarning::Unstable { equilibrium, min_eigenvalue });
                    }
                }
                for (part, violation, allowed) in v.parts(problem, settings) {
                    if violation.is_nan() || violation > allowed {
                        warnings.push(DesignWarning::ConstraintViolated { part, violation, allowed });
                    }
                }
                let equilibria = Equilibria { passive: s1, loaded: s2, probe: probe.as_ref() };
                let spans = &problem.structure.chain.spans;
                let objective = problem.objective.value(spans, &design, &equilibria);
                let measures = Measures::of(&problem.objective, spans, &design, &equilibria);
                if let Some(budget) = problem.strain_energy_max {
                    let violation = (measures.strain_energy - budget).max(0.0);
                    let allowed = Violations::inequality_allowance(settings, budget);
                    if violation.is_nan() || violation > allowed {
                        let part = "strain_energy_max";
                        warnings.push(DesignWarning::ConstraintViolated { part, violation, allowed });
                    }
                }
                (Some(r1), Some(r2), Some(end), Some(v), objective, Some(measures))
            }
            None => {
                warnings.push(DesignWarning::NoEquilibria);
                (None, None, None, None, f64::NAN, None)
            }
        };

        let load_path = LoadPathCheck::compare(passive.as_ref(), loaded.as_ref(), &path);
        if states.is_some() && !load_path.consistent {
            warnings.push(DesignWarning::OffLoadPath {
                passive_difference: load_path.passive_angle_difference,
                loaded_difference: load_path.loaded_angle_difference,
                passive_status: load_path.passive_status,
                loaded_status: load_path.loaded_status,
            });
        }

        DesignResult {
            formulation,
            solver,
            criterion: problem.objective.clone(),
            objective,
            measures,
            stiffness_scale: problem.stiffness_scale,
            design,
            unloaded_nodes,
            passive,
            loaded,
            probe: probe_report,
            end_displacement,
            delta_d: problem.delta_d,
            violations,
            load_path,
            start_notes,
            warnings,
            refinement: None,
            certificate: None,
            escapes: Vec::new(),
        }
    }

    /// A clean optimum: Ipopt converged, the reported design meets eq. (33) within its tolerances
    /// (recomputed here, see [`Violations::parts`]), both equilibria stable and on the load path.
    pub fn is_clean(&self) -> bool {
        self.solver.converged && self.warnings.is_empty()
    }

    /// The reported design meets eq. (33) within its tolerances, both equilibria stable and on the
    /// load path, whether or not the solver converged or certified it (a run stopped at its
    /// iteration limit returns its last iterate, as fmincon does).
    pub fn is_feasible(&self) -> bool {
        use crate::warnings::DesignWarning::{NotAMinimum, NotConverged};
        self.warnings.iter().all(|w| matches!(w, NotConverged { .. } | NotAMinimum { .. }))
    }
}

/// How a point that was not a minimum was left.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EscapeHow {
    /// The tight re-solve from it descended to a lower `J` elsewhere.
    TightResolve,
    /// A step along its direction of negative curvature, then eq. (33) again.
    NegativeCurvature,
    /// A weak minimum: a step along its direction of zero curvature, then eq. (33) again, ended
    /// lower.
    FlatDirection,
    /// Eq. (33) again from its design with the run's own settings (where the inertia shows
    /// negative curvature but no direction was formed: above [`crate::certificate::MAX_DENSE_FREE`] free
    /// variables or [`crate::optimality::active_set::MAX_WEAK`] weakly active bounds).
    Restart,
}

impl EscapeHow {
    /// The name written in results (`tight_resolve`, `negative_curvature`).
    pub fn name(self) -> &'static str {
        match self {
            Self::TightResolve => "tight_resolve",
            Self::NegativeCurvature => "negative_curvature",
            Self::FlatDirection => "flat_direction",
            Self::Restart => "restart",
        }
    }
}

/// A point left on the way to the reported optimum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Escape {
    /// `J` at the point left, J.
    pub objective: f64,
    /// Its certificate where one was computed (a run without multipliers has none).
    pub status: Option<crate::certificate::MinimumStatus>,
    pub how: EscapeHow,
    /// The negative curvature it was left along (for [`EscapeHow::NegativeCurvature`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curvature: Option<f64>,
    /// `J` where the next solve ended, J.
    pub reached: f64,
    /// Ipopt iterations of the solve that reached `reached` from the point left (after a tight
    /// re-solve, with its carrying to the case's tolerance); the attempts that ended higher are not
    /// counted.
    #[serde(default)]
    pub iterations: usize,
}
