//! Helpers shared by the tests that compare two forms of the full space's variables.

use spine_design::full_space::{FullSpaceNlp, StateForm};
use spine_design::settings::{ExtraOption, SpringVariables};
use spine_design::solve::ipopt::ipopt_solve_full;
use spine_design::{DesignProblem, DesignResult, SolverSettings};
use spine_ipopt::Solution;
use spine_model::State;

/// Ipopt on the full space with the states in `form` and the springs as `springs`, started at a
/// result's design and states with `mu_init` 1e-9 (pushes 1e-10): the solution and the NLP it
/// ran on. An optimum handed to another form of the same NLP this way stays put.
pub fn restart_at<'p>(
    problem: &'p DesignProblem,
    form: StateForm,
    springs: SpringVariables,
    r: &DesignResult,
) -> (Solution, FullSpaceNlp<'p>) {
    let mut settings = SolverSettings::default();
    for (k, v) in [("mu_init", 1e-9), ("bound_push", 1e-10), ("bound_frac", 1e-10)] {
        settings.ipopt_options.insert(k.into(), ExtraOption::Num(v));
    }
    let state = |s: &Option<spine_design::result::StateReport>| {
        let s = s.as_ref().expect("a clean result has both states");
        State { theta: s.theta.clone(), lambda: s.lambda }
    };
    let mut nlp = FullSpaceNlp::new(problem, form, &r.design, &state(&r.passive), &state(&r.loaded));
    let solution = ipopt_solve_full(&mut nlp, &settings.ipopt(), springs).unwrap();
    (solution, nlp)
}
