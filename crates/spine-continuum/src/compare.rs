//! The chain against the rod it discretises, at a number of links `N`: the critical load against
//! Euler's, and equilibria against the elastica at the same arclength.

use crate::buckling::chain_critical_load;
use crate::elastica::Elastica;
use crate::rod::Rod;
use serde::Serialize;
use spine_model::jacobian::residual_and_state_jacobian;
use spine_model::{Design, State, Structure};
use spine_solve::linalg::BorderedLu;
use spine_solve::{solve_path, solve_static, ContinuationOptions, EquilibriumSolution, LoadPath, StaticProblem};

/// The Newton tolerance of the comparisons (N·m): at the rounding floor, which the solver uses
/// where this is below it.
const RESIDUAL_TOLERANCE: f64 = 1e-14;

/// A chain equilibrium beside the elastica.
#[derive(Clone, Debug, Serialize)]
pub struct NodeComparison {
    pub links: usize,
    /// Largest distance of a node from the elastica's point at its arclength, over `L`.
    pub error: f64,
    /// `error · N²`: constant when the error is `O(1/N²)`.
    pub scaled_error: f64,
    pub status: spine_solve::EquilibriumStatus,
    pub stable: bool,
    pub min_eigenvalue: Option<f64>,
    pub newton_iterations: usize,
    pub time_seconds: f64,
}

impl NodeComparison {
    fn new(elastica: &Elastica, n: usize, sol: &EquilibriumSolution, structure: &Structure, design: &Design) -> Self {
        let theta = refined(structure, design, &sol.state);
        let error = crate::node_error(elastica, &theta) / elastica.rod.length;
        Self {
            links: n,
            error,
            scaled_error: error * (n * n) as f64,
            status: sol.status,
            stable: sol.stability.stable,
            min_eigenvalue: sol.stability.min_eigenvalue,
            newton_iterations: sol.stats.newton_iterations,
            time_seconds: sol.stats.time_seconds,
        }
    }
}

/// The chain's critical load beside Euler's.
#[derive(Clone, Debug, Serialize)]
pub struct CriticalLoad {
    pub links: usize,
    /// The chain's, N.
    pub chain: f64,
    /// `(P_chain − P_Euler)/P_Euler` and that times `N²`.
    pub relative_error: f64,
    pub scaled_error: f64,
}

/// The critical load of the chain of `n` links for `rod`, against Euler's.
pub fn critical_load(rod: &Rod, n: usize) -> CriticalLoad {
    let chain = chain_critical_load(rod, n);
    let euler = rod.euler_critical_load();
    let relative_error = (chain - euler) / euler;
    CriticalLoad { links: n, chain, relative_error, scaled_error: relative_error * (n * n) as f64 }
}

/// The chain's equilibrium on the elastica's branch: Newton from the elastica's angles at each
/// link's start (an `O(a)` guess, so Newton has to move), under the rod's full load. For a branch
/// the load path from the straight state does not reach (post-buckled: the straight path meets a
/// bifurcation); the certificate says whether the chain's state is stable.
pub fn on_branch(elastica: &Elastica, n: usize) -> NodeComparison {
    let rod = &elastica.rod;
    let (structure, design) = rod.chain(n);
    let a = rod.length / n as f64;
    let theta = (0..n).map(|i| elastica.theta_at(i as f64 * a)).collect();
    let loads = structure.total_loads();
    let path = LoadPath {
        spans: &structure.chain.spans,
        design: &design,
        from: loads.clone(),
        to: loads,
        start: State { theta, lambda: elastica.reaction },
    };
    let sol = solve_path(&path, &options());
    NodeComparison::new(elastica, n, &sol, &structure, &design)
}

/// The chain's equilibrium reached by loading the straight chain (passive load, then the end
/// force: the load path of every static problem here), against the elastica.
pub fn loaded(elastica: &Elastica, n: usize) -> NodeComparison {
    let (structure, design) = elastica.rod.chain(n);
    let problem = StaticProblem { structure, design };
    let sol = solve_static(&problem, &options());
    let last = sol.loaded.as_ref().unwrap_or(&sol.passive);
    NodeComparison::new(elastica, n, last, &problem.structure, &problem.design)
}

/// Two more Newton steps past the solver's stopping rule: its residual floor (`32 ε` times the
/// springs' row sums) stops Newton at `N = 10⁴` where the angles still move by `~1e-8` rad, above
/// the discretisation error the comparison measures. A step is kept only while it lowers the
/// residual.
fn refined(structure: &Structure, design: &Design, state: &State) -> Vec<f64> {
    let loads = structure.total_loads();
    let spans = &structure.chain.spans;
    let mut state = state.clone();
    let norm = |r: &[f64]| r.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (mut residual, mut jac) = residual_and_state_jacobian(spans, design, &loads, &state);
    for _ in 0..2 {
        let Ok(lu) = BorderedLu::factor(&jac) else { break };
        let step = lu.solve(&residual);
        let mut next = state.clone();
        for (t, d) in next.theta.iter_mut().zip(&step) {
            *t -= d;
        }
        next.lambda -= step[state.theta.len()];
        let (r, j) = residual_and_state_jacobian(spans, design, &loads, &next);
        if norm(&r) >= norm(&residual) {
            break;
        }
        (state, residual, jac) = (next, r, j);
    }
    state.theta
}

fn options() -> ContinuationOptions {
    ContinuationOptions { residual_tolerance: RESIDUAL_TOLERANCE, ..Default::default() }
}
