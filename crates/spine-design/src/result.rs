//! What a design run reports, recomputed from the design itself so that both formulations are
//! judged by the same numbers.

use crate::problem::DesignProblem;
use crate::refine::{Ladder, LevelStart, WarmStart};
use crate::settings::{ExtraOption, Formulation, SolverSettings};
use serde::{Deserialize, Serialize};
use spine_ipopt::{EvaluationCounts, Solution};
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::kinematics::{end_constraint, end_x, link_lengths, node_positions};
use spine_model::{energy, Design, LinkLoads, State};
use spine_solve::{solve_static, stability, Stability};

/// Which of the two equilibria of eq. (33).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LoadCase {
    /// `θ1`, under the passive load.
    Passive,
    /// `θ2`, under the passive load plus the actuation.
    Loaded,
}

/// Why a design result is not clean.
#[derive(Clone, Debug, PartialEq)]
pub enum DesignWarning {
    /// Ipopt ended without converging (its status).
    NotConverged { status: spine_ipopt::Status },
    /// An equilibrium of the final design is not stable (its smallest reduced-Hessian
    /// eigenvalue, N·m/rad, when it has one).
    Unstable { equilibrium: LoadCase, min_eigenvalue: Option<f64> },
    /// The final design has no equilibria on its load path.
    NoEquilibria,
    /// The optimiser's equilibria are not the ones reached by loading the design (largest angle
    /// differences, rad, and the statuses of the two paths).
    OffLoadPath { passive_difference: f64, loaded_difference: f64, passive_status: String, loaded_status: String },
    /// The reported design and states break a constraint of eq. (33) by more than allowed: the
    /// part (a field of [`Violations`]), its recomputed violation and the allowance (its unit).
    /// Ipopt's status alone does not show this: it judges its own last iterate, which a bound
    /// clipping after the solve (`honor_original_bounds`) or an "acceptable" stop can leave.
    ConstraintViolated { part: &'static str, violation: f64, allowed: f64 },
}

impl std::fmt::Display for DesignWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotConverged { status } => write!(f, "Ipopt did not converge: {status}"),
            Self::Unstable { equilibrium, min_eigenvalue } => {
                let name = match equilibrium {
                    LoadCase::Passive => "θ1 (passive)",
                    LoadCase::Loaded => "θ2 (passive + actuation)",
                };
                let eigenvalue = min_eigenvalue.map_or("none".into(), |e| format!("{e:.3e} N·m/rad"));
                write!(f, "the equilibrium {name} is unstable (smallest reduced-Hessian eigenvalue {eigenvalue})")
            }
            Self::NoEquilibria => write!(f, "the final design has no equilibria on its load path"),
            Self::OffLoadPath { passive_difference, loaded_difference, passive_status, loaded_status } => write!(
                f,
                "the optimiser's equilibria are not the ones reached by loading the design (differences {passive_difference:.3e} and {loaded_difference:.3e} rad; paths: {passive_status}, {loaded_status})"
            ),
            Self::ConstraintViolated { part, violation, allowed } => write!(
                f,
                "the reported design violates eq. (33): {part} {violation:.3e} (allowed {allowed:.1e}); its numbers are not those of an optimum"
            ),
        }
    }
}

impl Serialize for DesignWarning {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Ipopt's account of the run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverReport {
    /// The Ipopt the program is built against ([`spine_ipopt::IPOPT_VERSION`]).
    pub ipopt_version: String,
    /// Every option passed to Ipopt (the cold solve's; warm levels add `refinement.warm_start`).
    pub ipopt_options: std::collections::BTreeMap<String, String>,
    /// Ipopt's return status (serialised as its snake_case name).
    pub status: spine_ipopt::Status,
    /// Converged to the requested tolerances.
    pub optimal: bool,
    /// Converged to the requested or the acceptable tolerances.
    pub converged: bool,
    /// Ipopt concluded the constraints cannot be met.
    pub infeasible: bool,
    pub iterations: usize,
    /// Primal and dual infeasibility at the last iteration (Ipopt's scaled measures).
    pub final_primal_infeasibility: f64,
    pub final_dual_infeasibility: f64,
    /// Wall time inside Ipopt, s, and the part spent in our function evaluations, s (last level
    /// of a refined run).
    pub ipopt_seconds: f64,
    pub evaluation_seconds: f64,
    /// Start equilibria by continuation before Ipopt (cold full space), the final check of the
    /// design (equilibria, stability, load path), and the whole run with every level, s.
    pub start_seconds: f64,
    pub check_seconds: f64,
    pub total_seconds: f64,
    #[serde(serialize_with = "serialize_counts", deserialize_with = "deserialize_counts")]
    pub evaluations: EvaluationCounts,
    /// Reduced space: distinct designs at which both equilibria were solved.
    pub equilibrium_solves: usize,
}

fn deserialize_counts<'de, D: serde::Deserializer<'de>>(d: D) -> Result<EvaluationCounts, D::Error> {
    #[derive(Deserialize)]
    struct Counts {
        objective: usize,
        gradient: usize,
        constraints: usize,
        jacobian: usize,
        hessian: usize,
    }
    let Counts { objective, gradient, constraints, jacobian, hessian } = Counts::deserialize(d)?;
    Ok(EvaluationCounts { objective, gradient, constraints, jacobian, hessian })
}

fn serialize_counts<S: serde::Serializer>(c: &EvaluationCounts, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let mut st = s.serialize_struct("EvaluationCounts", 5)?;
    st.serialize_field("objective", &c.objective)?;
    st.serialize_field("gradient", &c.gradient)?;
    st.serialize_field("constraints", &c.constraints)?;
    st.serialize_field("jacobian", &c.jacobian)?;
    st.serialize_field("hessian", &c.hessian)?;
    st.end()
}

impl SolverReport {
    pub fn from_ipopt(solution: &Solution, equilibrium_solves: usize) -> Self {
        SolverReport {
            ipopt_version: spine_ipopt::IPOPT_VERSION.to_string(),
            ipopt_options: Default::default(),
            status: solution.status,
            optimal: solution.status.is_optimal(),
            converged: solution.status.is_converged(),
            infeasible: solution.status.is_infeasible(),
            iterations: solution.iterations,
            final_primal_infeasibility: solution.last_iteration.primal_infeasibility,
            final_dual_infeasibility: solution.last_iteration.dual_infeasibility,
            ipopt_seconds: solution.wall_time.as_secs_f64(),
            evaluation_seconds: solution.callback_time.as_secs_f64(),
            start_seconds: 0.0,
            check_seconds: 0.0,
            total_seconds: 0.0,
            evaluations: solution.evaluations,
            equilibrium_solves,
        }
    }
}

/// One level of a mesh-sequenced run ([`crate::refine`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelReport {
    /// Links of this level's chain.
    pub links: usize,
    pub start: LevelStart,
    /// Ipopt's status at this level; `optimal`: `solve_succeeded`.
    pub status: spine_ipopt::Status,
    pub optimal: bool,
    pub iterations: usize,
    /// `J` of this level's (coarse) problem, J.
    pub objective: f64,
    /// Preparing the start (prolongation and equilibria), and the whole level, s.
    pub start_seconds: f64,
    pub wall_seconds: f64,
}

/// How a mesh-sequenced run went.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RefinementReport {
    pub ladder: Ladder,
    pub warm_start: WarmStart,
    /// A coarse level did not converge and the chain itself was solved cold.
    pub fell_back_to_cold: bool,
    pub levels: Vec<LevelReport>,
}

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
