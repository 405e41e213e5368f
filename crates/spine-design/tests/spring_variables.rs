//! The full space with the springs as Ipopt's variables `k` and `ln k`
//! (`solver.spring_variables`): one form against the other. Both are the same NLP after a change
//! of variables, so an optimum of one, handed to the other with a barrier close to zero, stays
//! put, and the multipliers Ipopt returns in `ln k`, carried back to `k`, make the Lagrangian
//! stationary in `k`.

mod common;

use spine_design::fixtures::{arch_start, scaled_family};
use spine_design::full_space::FullSpaceNlp;
use spine_design::refine::{Refine, RefineMode};
use spine_design::settings::SolverPreset;
use spine_design::settings::SpringVariables;
use spine_design::solve::Solver;
use spine_design::{DesignProblem, DesignResult, Formulation, SolverSettings};
use spine_ipopt::{Problem, Solution};
use spine_model::Design;

fn solve(problem: &DesignProblem, start: &Design, springs: SpringVariables) -> DesignResult {
    let settings = SolverSettings {
        refine: Refine::Mode(RefineMode::Off),
        spring_variables: springs,
        ..SolverSettings::default()
    };
    Solver::new(SolverPreset::Exact, Formulation::Full, &settings).solve(problem, start, &mut |_| true).unwrap()
}

/// Ipopt with the springs as `springs`, started at a result's design and states with `mu_init`
/// 1e-9, and the NLP it ran on (for the stationarity check).
fn restart<'p>(problem: &'p DesignProblem, springs: SpringVariables, r: &DesignResult) -> (Solution, FullSpaceNlp<'p>) {
    common::restart_at(problem, r.solver.state_variables.expect("full space"), springs, r)
}

/// Largest `|∇f + Jᵀλ − z_L + z_U|` of `nlp` at `solution`, relative to the largest `|∇f|`.
fn stationarity(nlp: &mut FullSpaceNlp<'_>, solution: &Solution) -> f64 {
    let x = &solution.x;
    let mut r = vec![0.0; x.len()];
    assert!(nlp.objective_gradient(x, true, &mut r));
    let scale = r.iter().fold(0.0f64, |a, b| a.max(b.abs())).max(1e-300);
    let pattern = nlp.jacobian_structure();
    let mut values = vec![0.0; pattern.len()];
    assert!(nlp.jacobian_values(x, false, &mut values));
    for (&(row, col), v) in pattern.iter().zip(&values) {
        r[col] += solution.lambda[row] * v;
    }
    for (i, r) in r.iter_mut().enumerate() {
        *r += solution.z_upper[i] - solution.z_lower[i];
    }
    r.iter().fold(0.0f64, |a, b| a.max(b.abs())) / scale
}

#[test]
fn log_and_linear_springs_share_their_optima() {
    for n in [10, 20] {
        let problem = scaled_family(n);
        let start = arch_start(n, 0.3, 1e3 * (n as f64 / 10.0).powi(2));
        let log = solve(&problem, &start, SpringVariables::Log);
        let linear = solve(&problem, &start, SpringVariables::Linear);
        for (r, own, other) in [
            (&log, SpringVariables::Log, SpringVariables::Linear),
            (&linear, SpringVariables::Linear, SpringVariables::Log),
        ] {
            assert!(r.solver.optimal && r.is_clean(), "N = {n}: {} {:?}", r.solver.status, r.warnings);
            assert_eq!(r.solver.spring_variables, Some(own), "N = {n}: the result names its springs");
            let (solution, mut nlp) = restart(&problem, other, r);
            let j = solution.objective;
            eprintln!(
                "N = {n}: J = {:.9e} ({:?}, {} its) restarted with {other:?} springs: {} iterations, J = {j:.9e}",
                r.objective,
                r.certificate.as_ref().map(|c| c.status),
                r.solver.iterations,
                solution.iterations
            );
            assert!(solution.status.is_optimal(), "N = {n}: the restart with {other:?} springs did not converge");
            assert!((j - r.objective).abs() <= 1e-7 * r.objective, "N = {n}: J moved from {} to {j}", r.objective);
            assert!(solution.iterations <= 15, "N = {n}: {} iterations to stay at an optimum", solution.iterations);
            let s = stationarity(&mut nlp, &solution);
            assert!(s <= 1e-6, "N = {n}, {other:?}: the Lagrangian's gradient in k is {s:e} of ∇f's");
        }
    }
}

/// The case-file field: `"auto"` by default (logarithms from 100 links on), `"log"`, `"linear"`
/// as the paper writes eq. (34), anything else an error naming the field's values.
#[test]
fn spring_variables_field_parses_and_auto_resolves_by_size() {
    let auto = SolverSettings::default().spring_variables;
    assert_eq!(auto, SpringVariables::Auto);
    assert_eq!(auto.resolve(&scaled_family(99)), SpringVariables::Linear);
    assert_eq!(auto.resolve(&scaled_family(100)), SpringVariables::Log);
    assert_eq!(SpringVariables::Linear.resolve(&scaled_family(500)), SpringVariables::Linear);
    assert_eq!(SpringVariables::Log.resolve(&scaled_family(5)), SpringVariables::Log);
    let linear: SolverSettings = serde_json::from_str(r#"{ "spring_variables": "linear" }"#).unwrap();
    assert_eq!(linear.spring_variables, SpringVariables::Linear);
    let bad = serde_json::from_str::<SolverSettings>(r#"{ "spring_variables": "cubic" }"#).unwrap_err().to_string();
    assert!(bad.contains("auto") && bad.contains("log") && bad.contains("linear"), "{bad}");
}
