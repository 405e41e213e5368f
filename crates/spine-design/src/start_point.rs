//! The full space's start point in named parts, for a peer model (a CasADi script) to start from
//! the point [`crate::solve::Solver`] hands Ipopt.

use crate::full_space::FullSpaceNlp;
use crate::layout::{Layout, StateForm};
use crate::problem::DesignProblem;
use spine_model::{Design, State};

/// The full space's start point from a start design, in named parts: what
/// [`crate::solve::Solver`] hands Ipopt (variables in [`Layout`]'s order), for a peer model (a
/// CasADi script, `benchmarks/peers/casadi_static.py`) to start from the same point.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct FullSpaceStart {
    /// `θ0` (rad, `N`), projected into the bounds.
    pub theta0: Vec<f64>,
    /// `k = K / C_K` (`N + 1`), eq. (34)'s scaled springs.
    pub k: Vec<f64>,
    /// The passive equilibrium of the start design and its multiplier (N).
    pub theta1: Vec<f64>,
    pub lambda1: f64,
    /// The loaded equilibrium of the start design and its multiplier (N).
    pub theta2: Vec<f64>,
    pub lambda2: f64,
    /// Interior node heights `Y0_2..Y0_N`, m.
    pub heights: Vec<f64>,
}

impl FullSpaceStart {
    /// From `start` projected into the bounds, with both equilibria solved by continuation at it
    /// (the states [`crate::solve::Solver`] starts from).
    pub fn new(problem: &DesignProblem, start: &Design, continuation: &spine_solve::ContinuationOptions) -> Self {
        let (projected, _) = problem.project_start(start);
        let (passive, loaded) = crate::problem::start_states(problem, &projected, continuation, &mut Vec::new());
        Self::from_states(problem, &projected, &passive, &loaded)
    }

    /// From a design and given start states (a warm start: a prolongated coarser optimum).
    pub fn from_states(problem: &DesignProblem, design: &Design, passive: &State, loaded: &State) -> Self {
        let n = problem.n_links();
        // The peer is handed absolute angles; the design part and the heights are the same in both forms.
        let x0 = FullSpaceNlp::new(problem, StateForm::Absolute, design, passive, loaded).start;
        let layout = Layout::of(problem, StateForm::Absolute);
        Self {
            theta0: x0[..n].to_vec(),
            k: x0[n..2 * n + 1].to_vec(),
            theta1: passive.theta.clone(),
            lambda1: passive.lambda,
            theta2: loaded.theta.clone(),
            lambda2: loaded.lambda,
            heights: (1..n).filter_map(|j| layout.height(j).map(|h| x0[h])).collect(),
        }
    }
}
