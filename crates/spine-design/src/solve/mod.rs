//! The eq. (33) solve, one stage a module, in the order a design run passes them. In the manner
//! of argmin's `Executor`: the problem, the settings and the preset go in ([`Solver`]), the
//! typed, checked and certified [`DesignResult`] comes out ([`Solver::solve`]).
//!
//! | stage | module | what it does |
//! |---|---|---|
//! | 1. refinement ladder | [`ladder`] | coarser chains first, each level warm-starting the next ([`crate::refine`]) |
//! | 2. Ipopt | [`ipopt`] | one NLP handed to Ipopt, its linear solver made ready, the springs by their logarithm where asked |
//! | 1 + 2 | [`run`] | the unsettled run from a start ([`SolverRun`]), the same in a worker process |
//! | 3. check, certificate | [`settle`] | every reported quantity recomputed ([`crate::result::Violations`]), the second-order certificate ([`crate::certificate`]) |
//! | 4. tight re-solve | [`tight`], [`polish`] | a point whose certificate is not strict solved again tightly, cold from its design |
//! | 5. escape | [`escape`] | a point that is not a minimum left along its negative curvature, a weak one probed along its flat direction |
//!
//! [`settle`] runs stages 3 to 5 as one loop, at most [`settle::MAX_ESCAPES`] times round. The
//! fmincon-like preset ([`SolverPreset::FminconLike`]) stops after stage 3's check: what the
//! paper's kind of optimiser returns is its last iterate, neither certified nor polished.
//!
//! What each stage may import: `ipopt` the NLPs ([`crate::full_space`],
//! [`crate::log_variables`]) and the settings; `ladder` and `run` also the problem, the refinement
//! ([`crate::refine`]) and the reports; `polish` and `tight` the run; `escape` the run and the
//! certificate's types; `settle` every stage below it and [`crate::certificate`]. No stage imports
//! [`crate::sensitivity`] or [`crate::multistart`], which stand above the solve.
//!
//! ```
//! use spine_design::fixtures::{paper_five_link_start, paper_problem};
//! use spine_design::settings::{Formulation, SolverPreset, SolverSettings};
//! use spine_design::solve::Solver;
//! // The paper's 5-link case (Sec. 5.1): −10 N per node, −400 N at the end, δ_d = −0.02 m, C_K = 1.
//! let problem = paper_problem(5, -10.0, -400.0, -0.02, 1.0);
//! let solver = Solver::new(SolverPreset::Exact, Formulation::Full, &SolverSettings::default());
//! let result = solver.solve(&problem, &paper_five_link_start(), &mut |_| true).unwrap();
//! assert!(result.is_clean());
//! assert!(result.certificate.is_some());
//! ```

pub mod escape;
pub mod ipopt;
pub mod ladder;
pub mod polish;
pub mod run;
pub mod settle;
pub mod tight;

use crate::problem::DesignProblem;
use crate::result::DesignResult;
use crate::settings::{Formulation, SolverPreset, SolverSettings};
use crate::solver_run::SolverRun;
use ipopt::DesignError;
use spine_ipopt::IterationInfo;
use spine_model::Design;

/// How eq. (33) is solved: a preset applied over a formulation and settings
/// ([`SolverPreset::apply`]). The one way into the solve; the command line, Python and a library
/// caller build it from the same case fields and get the same result.
#[derive(Clone, Debug, PartialEq)]
pub struct Solver {
    preset: SolverPreset,
    formulation: Formulation,
    settings: SolverSettings,
}

impl Solver {
    /// `preset` applied over `formulation` and `settings`. Applying a preset twice changes
    /// nothing, so settings that already carry it (a checked case's) may be given again.
    pub fn new(preset: SolverPreset, formulation: Formulation, settings: &SolverSettings) -> Self {
        let (formulation, settings) = preset.apply(formulation, settings);
        Self { preset, formulation, settings }
    }

    pub fn preset(&self) -> SolverPreset {
        self.preset
    }

    pub fn formulation(&self) -> Formulation {
        self.formulation
    }

    /// The settings the solve runs with (the preset applied).
    pub fn settings(&self) -> &SolverSettings {
        &self.settings
    }

    /// Eq. (33) from `start` (projected into the bounds first), every stage in its order: the
    /// reported optimum, checked, and for [`SolverPreset::Exact`] certified and never a point
    /// that is not a minimum where a lower one can be reached from it. `observer` sees every
    /// Ipopt iteration of the first solve (of every level) and may stop it by returning `false`.
    /// The same as [`Solver::run`] then [`Solver::report`].
    pub fn solve(
        &self,
        problem: &DesignProblem,
        start: &Design,
        observer: &mut dyn FnMut(&IterationInfo) -> bool,
    ) -> Result<DesignResult, DesignError> {
        self.report(problem, self.run(problem, start, observer)?)
    }

    /// Stages 1 and 2 alone: the unsettled run from `start`, what a worker process or a shard
    /// sends back ([`SolverRun`] is serialisable without loss).
    pub fn run(
        &self,
        problem: &DesignProblem,
        start: &Design,
        observer: &mut dyn FnMut(&IterationInfo) -> bool,
    ) -> Result<SolverRun, DesignError> {
        run::run_solver(problem, start, self.formulation, &self.settings, observer)
    }

    /// Stages 3 to 5 on a run of this solver: the result it reports, whichever process solved
    /// it. [`SolverPreset::Exact`]: checked, certified and left for a lower minimum where it is
    /// not one ([`settle`]). [`SolverPreset::FminconLike`]: checked only; a tight
    /// re-solve would move it to the exact solver's optimum (design5: `J` 7.60450e-3 at
    /// fmincon's 1e-6 becomes 7.60312e-3), and what the paper's kind of optimiser returns is
    /// what that reading is for.
    pub fn report(&self, problem: &DesignProblem, run: SolverRun) -> Result<DesignResult, DesignError> {
        match self.preset {
            SolverPreset::Exact => settle::settle(problem, run, &self.settings),
            SolverPreset::FminconLike => Ok(run.check(problem, &self.settings)),
        }
    }
}
