//! Ipopt's account of a design run: status, iterations, infeasibilities, counts, times, and the
//! levels of a mesh-sequenced run.

use crate::refine::{Ladder, LevelStart, WarmStart};
use serde::{Deserialize, Serialize};
use spine_ipopt::{EvaluationCounts, Solution};

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
    /// Ipopt iterations: of the run (the finest level of a refined one, every restart's counted),
    /// and where the reported point was reached by leaving others
    /// ([`crate::DesignResult::escapes`]) of every run on that path (the first run's, then each
    /// escape's `iterations`).
    pub iterations: usize,
    /// Primal and dual infeasibility at the last iteration (Ipopt's scaled measures).
    pub final_primal_infeasibility: f64,
    pub final_dual_infeasibility: f64,
    /// Wall time inside Ipopt, s, and the part spent in our function evaluations, s (last level
    /// of a refined run; with escapes, every run on the path, as `iterations`).
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
    /// Full space: how the states were Ipopt's variables in the last level (`solver.state_variables`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_variables: Option<crate::layout::StateForm>,
    /// Full space: how Ipopt saw the springs, `log` or `linear` (`solver.spring_variables`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spring_variables: Option<crate::variables::SpringVariables>,
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
    /// The full space's index map of this run of `problem`: its state form (absolute angles for
    /// a run that has none, the reduced space).
    pub fn layout(&self, problem: &crate::problem::DesignProblem) -> crate::layout::Layout {
        let states = self.state_variables.unwrap_or(crate::layout::StateForm::Absolute);
        crate::layout::Layout::of(problem, states)
    }

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
            state_variables: None,
            spring_variables: None,
        }
    }
}

/// One level of a mesh-sequenced run ([`crate::refine`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelReport {
    /// Links of this level's chain.
    pub links: usize,
    pub start: LevelStart,
    /// The barrier parameter `μ_m` of [`crate::refine::WarmStart::barrier`]: a coarse level's
    /// barrier problem, the warm start of the chain itself; `None` without a schedule.
    #[serde(default)]
    pub barrier: Option<f64>,
    /// Ipopt's status at this level; `optimal`: `solve_succeeded`.
    pub status: spine_ipopt::Status,
    pub optimal: bool,
    /// Ipopt iterations at this level, over all its restarts.
    pub iterations: usize,
    /// Times the level was restarted ([`crate::refine::WarmStart::restart_after`]).
    #[serde(default)]
    pub restarts: usize,
    /// `J` of this level's (coarse) problem, J.
    pub objective: f64,
    /// A warm level's end-displacement violation `|X_{N+1}(θ2) − L_x − δ_d|` (m) before and after
    /// it was restored ([`crate::refine::restore_end_displacement`]); `None` when it was not.
    #[serde(default)]
    pub end_displacement_restored: Option<[f64; 2]>,
    /// Preparing the start (prolongation and equilibria), and the whole level, s.
    pub start_seconds: f64,
    pub wall_seconds: f64,
}

/// Ipopt's iterations and times of runs on the path to a reported point (a run, then the
/// certificate's re-solves and escapes: [`crate::solve::settle`]), which its report counts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PathCost {
    iterations: usize,
    ipopt_seconds: f64,
    evaluation_seconds: f64,
}

impl PathCost {
    pub(crate) fn of(solver: &SolverReport) -> Self {
        PathCost {
            iterations: solver.iterations,
            ipopt_seconds: solver.ipopt_seconds,
            evaluation_seconds: solver.evaluation_seconds,
        }
    }
    pub(crate) fn add(&mut self, solver: &SolverReport) {
        self.add_cost(Self::of(solver));
    }
    pub(crate) fn add_cost(&mut self, other: PathCost) {
        self.iterations += other.iterations;
        self.ipopt_seconds += other.ipopt_seconds;
        self.evaluation_seconds += other.evaluation_seconds;
    }
    /// Adds these runs to `solver`'s report.
    pub(crate) fn add_to(mut self, solver: &mut SolverReport) {
        self.add(solver);
        self.put_in(solver);
    }
    /// Makes `solver`'s report count exactly these runs.
    pub(crate) fn put_in(self, solver: &mut SolverReport) {
        solver.iterations = self.iterations;
        solver.ipopt_seconds = self.ipopt_seconds;
        solver.evaluation_seconds = self.evaluation_seconds;
    }
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
