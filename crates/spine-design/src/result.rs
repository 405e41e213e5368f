//! What a design run reports, recomputed from the design itself so that both formulations are
//! judged by the same numbers.

pub use crate::solver_report::{LevelReport, RefinementReport, SolverReport};
pub use crate::warnings::{DesignWarning, LoadCase};

use crate::problem::DesignProblem;
use crate::settings::{ExtraOption, Formulation, SolverSettings};
use serde::Serialize;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::kinematics::{end_constraint, end_x, link_lengths, node_positions};
use spine_model::{energy, Design, LinkLoads, State};
use spine_solve::{solve_static, stability, Stability};

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

/// How far the result is from satisfying eq. (33), each part in its own unit.
#[derive(Clone, Debug, Serialize)]
pub struct Violations {
    /// Largest of all below (mixed units: N·m, m, rad, N·m/rad).
    pub max: f64,
    pub passive_equilibrium: f64,
    pub loaded_equilibrium: f64,
    /// `|Φ(θ0)|`, m.
    pub unloaded_end_height: f64,
    /// `|X_{N+1}(θ2) − L_x − δ_d|`, m.
    pub end_displacement: f64,
    /// Bound excess of `θ0`, relative angles (rad), node heights (m), stiffness (N·m/rad).
    pub theta0_bounds: f64,
    pub relative_angle_bounds: f64,
    pub height_bounds: f64,
    pub stiffness_bounds: f64,
}

impl Violations {
    /// Each part of eq. (33) with its violation and what is allowed: the equalities (equilibria,
    /// unloaded end height, end displacement) `constraint_tolerance`, Ipopt's `constr_viol_tol`;
    /// the bounds that plus Ipopt's relaxation of every bound, `bound_relax_factor · max(1, |b|)`
    /// in the variable's own scale (for `K`, the scaled `k = K / C_K` of eq. (34)), which Ipopt
    /// applies to the problem it solves and which `honor_original_bounds = no` keeps.
    pub fn parts(&self, problem: &DesignProblem, settings: &SolverSettings) -> [(&'static str, f64, f64); 8] {
        let tol = settings.constraint_tolerance;
        let relax = match settings.ipopt_options.get("bound_relax_factor") {
            Some(ExtraOption::Num(x)) => *x,
            Some(ExtraOption::Int(i)) => *i as f64,
            _ => IPOPT_BOUND_RELAX_FACTOR,
        };
        let b = &problem.bounds;
        let c_k = problem.stiffness_scale;
        let k_max = b.stiffness_max.iter().fold(0.0f64, |m, k| m.max(k.abs()));
        let angle = tol + relax * b.theta0_max.abs().max(1.0);
        let relative = tol + relax * b.relative_angle_max.abs().max(1.0);
        let height = tol + relax * b.height_min.abs().max(b.height_max.abs()).max(1.0);
        let stiffness = tol * c_k + relax * k_max.max(c_k);
        [
            ("passive_equilibrium", self.passive_equilibrium, tol),
            ("loaded_equilibrium", self.loaded_equilibrium, tol),
            ("unloaded_end_height", self.unloaded_end_height, tol),
            ("end_displacement", self.end_displacement, tol),
            ("theta0_bounds", self.theta0_bounds, angle),
            ("relative_angle_bounds", self.relative_angle_bounds, relative),
            ("height_bounds", self.height_bounds, height),
            ("stiffness_bounds", self.stiffness_bounds, stiffness),
        ]
    }
}

/// Ipopt's default `bound_relax_factor`.
pub const IPOPT_BOUND_RELAX_FACTOR: f64 = 1e-8;

/// Whether the optimiser's `θ1`, `θ2` are the equilibria reached by loading the design from `θ0`
/// (continuation), which is what the physical structure does.
#[derive(Clone, Debug, Serialize)]
pub struct LoadPathCheck {
    /// Both paths reach their full load and end within `1e-6` rad of the optimiser's states.
    pub consistent: bool,
    pub passive_status: String,
    pub loaded_status: String,
    /// Largest `|θ_optimiser − θ_path|`, rad (∞ when a path did not reach its load).
    pub passive_angle_difference: f64,
    pub loaded_angle_difference: f64,
}

/// The result of one design run.
#[derive(Clone, Debug, Serialize)]
pub struct DesignResult {
    pub formulation: Formulation,
    pub solver: SolverReport,
    /// `J = U(θ1; θ0, K)`, J, recomputed from the final design and state.
    pub objective: f64,
    pub design: Design,
    pub stiffness_scale: f64,
    /// Unloaded node coordinates, m.
    pub unloaded_nodes: Vec<(f64, f64)>,
    /// `θ1` (passive load) and `θ2` (passive + actuation); absent when the reduced space ended at a
    /// design without equilibria.
    pub passive: Option<StateReport>,
    pub loaded: Option<StateReport>,
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
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

fn excess(value: f64, lo: f64, hi: f64) -> f64 {
    (lo - value).max(value - hi).max(0.0)
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
    /// Recomputes every reported quantity from `design` and the states, checks the constraints,
    /// the stability of both equilibria and the load path, and lists warnings.
    pub fn check(
        problem: &DesignProblem,
        formulation: Formulation,
        design: Design,
        states: Option<(State, State)>,
        solver: SolverReport,
        start_notes: Vec<String>,
        settings: &SolverSettings,
    ) -> Self {
        let continuation = &settings.continuation;
        let spans = &problem.structure.chain.spans;
        let lx = problem.structure.chain.length_x();
        let b = &problem.bounds;
        let lengths = link_lengths(spans, &design.theta0);
        let unloaded_nodes = node_positions(&lengths, &design.theta0);
        let path = solve_static(&problem.static_problem(&design), continuation);
        let mut warnings = Vec::new();
        if !solver.converged {
            warnings.push(DesignWarning::NotConverged { status: solver.status });
        }

        let (passive, loaded, end_displacement, violations, objective) = match &states {
            Some((s1, s2)) => {
                let r1 = state_report(problem, &design, &problem.passive_loads(), s1);
                let r2 = state_report(problem, &design, &problem.total_loads(), s2);
                let end = end_x(spans, &design.theta0, &s2.theta) - lx;
                let heights = problem.node_heights(&design.theta0);
                let n = design.theta0.len();
                let v = Violations {
                    max: 0.0,
                    passive_equilibrium: r1.residual,
                    loaded_equilibrium: r2.residual,
                    unloaded_end_height: end_constraint(spans, &design.theta0, &design.theta0).abs(),
                    end_displacement: (end - problem.delta_d).abs(),
                    theta0_bounds: design
                        .theta0
                        .iter()
                        .map(|t| excess(*t, -b.theta0_max, b.theta0_max))
                        .fold(0.0, f64::max),
                    relative_angle_bounds: design
                        .theta0
                        .windows(2)
                        .map(|w| excess(w[0] - w[1], -b.relative_angle_max, b.relative_angle_max))
                        .fold(0.0, f64::max),
                    height_bounds: heights[1..n]
                        .iter()
                        .map(|y| excess(*y, b.height_min, b.height_max))
                        .fold(0.0, f64::max),
                    stiffness_bounds: design
                        .stiffness
                        .iter()
                        .enumerate()
                        .map(|(j, k)| excess(*k, b.stiffness_min[j], b.stiffness_max[j]))
                        .fold(0.0, f64::max),
                };
                let max = [
                    v.passive_equilibrium,
                    v.loaded_equilibrium,
                    v.unloaded_end_height,
                    v.end_displacement,
                    v.theta0_bounds,
                    v.relative_angle_bounds,
                    v.height_bounds,
                    v.stiffness_bounds,
                ]
                .into_iter()
                .fold(0.0, f64::max);
                for (equilibrium, report) in [(LoadCase::Passive, &r1), (LoadCase::Loaded, &r2)] {
                    if !report.stability.stable {
                        let min_eigenvalue = report.stability.min_eigenvalue;
                        warnings.push(DesignWarning::Unstable { equilibrium, min_eigenvalue });
                    }
                }
                let v = Violations { max, ..v };
                for (part, violation, allowed) in v.parts(problem, settings) {
                    if violation.is_nan() || violation > allowed {
                        warnings.push(DesignWarning::ConstraintViolated { part, violation, allowed });
                    }
                }
                let objective = energy::strain_energy(&s1.theta, &design.theta0, &design.stiffness);
                (Some(r1), Some(r2), Some(end), Some(v), objective)
            }
            None => {
                warnings.push(DesignWarning::NoEquilibria);
                (None, None, None, None, f64::NAN)
            }
        };

        let difference = |a: Option<&StateReport>, b: Option<&spine_solve::EquilibriumSolution>| match (a, b) {
            (Some(a), Some(b)) if b.load_factor == 1.0 => {
                a.theta.iter().zip(&b.state.theta).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            }
            _ => f64::INFINITY,
        };
        let passive_angle_difference = difference(passive.as_ref(), Some(&path.passive));
        let loaded_angle_difference = difference(loaded.as_ref(), path.loaded.as_ref());
        let load_path = LoadPathCheck {
            consistent: passive_angle_difference <= 1e-6 && loaded_angle_difference <= 1e-6,
            passive_status: path.passive.status.describe(),
            loaded_status: path.loaded.as_ref().map_or("not reached".into(), |l| l.status.describe()),
            passive_angle_difference,
            loaded_angle_difference,
        };
        if states.is_some() && !load_path.consistent {
            warnings.push(DesignWarning::OffLoadPath {
                passive_difference: passive_angle_difference,
                loaded_difference: loaded_angle_difference,
                passive_status: load_path.passive_status.clone(),
                loaded_status: load_path.loaded_status.clone(),
            });
        }

        DesignResult {
            formulation,
            solver,
            objective,
            stiffness_scale: problem.stiffness_scale,
            design,
            unloaded_nodes,
            passive,
            loaded,
            end_displacement,
            delta_d: problem.delta_d,
            violations,
            load_path,
            start_notes,
            warnings,
            refinement: None,
        }
    }

    /// A clean optimum: Ipopt converged, the reported design meets eq. (33) within its tolerances
    /// (recomputed here, see [`Violations::parts`]), both equilibria stable and on the load path.
    pub fn is_clean(&self) -> bool {
        self.solver.converged && self.warnings.is_empty()
    }
}
