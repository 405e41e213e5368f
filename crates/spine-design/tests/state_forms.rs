//! The full space with the states as absolute angles and as deflections `θ − θ0`
//! (`solver.state_variables`): one formulation against the other. Both are the same NLP after a
//! linear change of variables, so an optimum of one, handed to the other with a barrier close to
//! zero, stays put.

mod common;

use spine_design::fixtures::{arch_start, scaled_family};
use spine_design::full_space::StateForm;
use spine_design::refine::{Refine, RefineMode};
use spine_design::settings::SolverPreset;
use spine_design::settings::{SpringVariables, StateVariables};
use spine_design::solve::Solver;
use spine_design::{DesignProblem, DesignResult, Formulation, SolverSettings};
use spine_model::Design;

fn solve(problem: &DesignProblem, start: &Design, states: StateVariables) -> DesignResult {
    let settings =
        SolverSettings { refine: Refine::Mode(RefineMode::Off), state_variables: states, ..SolverSettings::default() };
    Solver::new(SolverPreset::Exact, Formulation::Full, &settings).solve(problem, start, &mut |_| true).unwrap()
}

/// Ipopt on `form` started at a result's design and states with `mu_init` 1e-9: J and iterations.
fn restart(problem: &DesignProblem, form: StateForm, r: &DesignResult) -> (f64, usize, bool) {
    let springs = r.solver.spring_variables.unwrap_or(SpringVariables::Linear);
    let (solution, _) = common::restart_at(problem, form, springs, r);
    (solution.objective, solution.iterations, solution.status.is_optimal())
}

#[test]
fn absolute_and_deflection_states_share_their_optima() {
    for n in [10, 20] {
        let problem = scaled_family(n);
        let start = arch_start(n, 0.3, 1e3 * (n as f64 / 10.0).powi(2));
        let absolute = solve(&problem, &start, StateVariables::Absolute);
        let deflection = solve(&problem, &start, StateVariables::Deflection);
        assert_eq!(absolute.solver.state_variables, Some(StateForm::Absolute));
        assert_eq!(deflection.solver.state_variables, Some(StateForm::Deflection));
        for (r, other) in [(&absolute, StateForm::Deflection), (&deflection, StateForm::Absolute)] {
            assert!(r.solver.optimal && r.is_clean(), "N = {n}: {} {:?}", r.solver.status, r.warnings);
            let (j, iterations, optimal) = restart(&problem, other, r);
            eprintln!("N = {n}: J = {:.9e} restarted on {other:?}: {iterations} iterations, J = {j:.9e}", r.objective);
            assert!(optimal, "N = {n}: the restart on {other:?} did not converge");
            assert!((j - r.objective).abs() <= 1e-7 * r.objective, "N = {n}: J moved from {} to {j}", r.objective);
            assert!(iterations <= 15, "N = {n}: {iterations} iterations to stay at an optimum");
        }
    }
}
