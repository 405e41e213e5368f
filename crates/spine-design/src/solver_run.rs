//! What one Ipopt run of eq. (33) returns before it is checked ([`SolverRun`]): serialisable, so
//! a worker process or a shard can send it to the process that checks it.

use crate::full_space::Multipliers;
use crate::problem::DesignProblem;
use crate::result::{DesignResult, RefinementReport, SolverReport};
use crate::settings::{Formulation, SolverSettings};
use serde::{Deserialize, Serialize};
use spine_model::{Design, State};
use std::time::Instant;

/// What Ipopt returned for eq. (33), before it is checked: the design, the states, the solver's
/// report, notes on the start and the ladder's levels. Serialisable without loss (a worker
/// process sends it to the process that checks it); [`SolverRun::check`] turns it into the
/// [`DesignResult`], the same wherever it runs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverRun {
    pub formulation: Formulation,
    pub design: Design,
    pub states: Option<(State, State)>,
    /// `θ3`, the full space's equilibrium under the compliance's load case
    /// ([`crate::Objective::Compliance`]).
    #[serde(default)]
    pub probe: Option<State>,
    pub solver: SolverReport,
    pub start_notes: Vec<String>,
    pub refinement: Option<RefinementReport>,
    /// Ipopt's multipliers at the full space's solution (in the layout of
    /// `solver.state_variables`), for the sensitivities of the optimum ([`crate::sensitivity`]).
    #[serde(default)]
    pub multipliers: Option<Multipliers>,
}

impl SolverRun {
    /// Whether a run read from elsewhere (a shard, a worker's answer) fits `problem`: its design
    /// and states have the chain's lengths (`N` angles, `N + 1` stiffnesses) and finite values.
    /// Checked before [`SolverRun::check`], which indexes them by the chain.
    pub fn fits(&self, problem: &DesignProblem) -> Result<(), spine_check::FieldError> {
        let n = problem.n_links();
        let vector = |field: &str, v: &[f64], len: usize| {
            spine_check::require(v.len() == len, field, || format!("{len} values expected, got {}", v.len()))?;
            spine_check::require(v.iter().all(|x| x.is_finite()), field, || "every value must be finite".into())
        };
        vector("design.theta0", &self.design.theta0, n)?;
        vector("design.stiffness", &self.design.stiffness, n + 1)?;
        if let Some((passive, loaded)) = &self.states {
            for (k, state) in [passive, loaded].into_iter().enumerate() {
                vector(&format!("states[{k}].theta"), &state.theta, n)?;
                vector(&format!("states[{k}].lambda"), &[state.lambda], 1)?;
            }
        }
        if let Some(probe) = &self.probe {
            vector("probe.theta", &probe.theta, n)?;
            vector("probe.lambda", &[probe.lambda], 1)?;
        }
        Ok(())
    }

    /// The run's full-space point: its layout (the run's state form, [`SolverReport::layout`])
    /// and its design, states and node heights packed in it; `None` without states (or without
    /// `θ3` where the criterion needs it).
    pub fn point(&self, problem: &DesignProblem) -> Option<(crate::layout::Layout, Vec<f64>)> {
        let (passive, loaded) = self.states.as_ref()?;
        let layout = self.solver.layout(problem);
        let heights = problem.node_heights(&self.design.theta0);
        let mut x = layout.pack(&self.design, problem.stiffness_scale, passive, loaded, &heights);
        if layout.probe {
            layout.pack_probe(&mut x, self.probe.as_ref()?);
        }
        Some((layout, x))
    }

    /// Recomputes and checks everything the result reports from the design and states
    /// ([`DesignResult::check`]).
    pub fn check(self, problem: &DesignProblem, settings: &SolverSettings) -> DesignResult {
        let check_clock = Instant::now();
        let SolverRun { formulation, design, states, probe, solver, start_notes, refinement, .. } = self;
        let solved_seconds = solver.total_seconds;
        let mut result =
            DesignResult::check(problem, formulation, design, states, probe, solver, start_notes, settings);
        result.solver.check_seconds = check_clock.elapsed().as_secs_f64();
        result.solver.total_seconds = solved_seconds + result.solver.check_seconds;
        result.refinement = refinement;
        result
    }
}
