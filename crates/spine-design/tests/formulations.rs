//! Both formulations of eq. (33) on the paper's two static configurations (Sec. 5.1), and the
//! statuses a run can end with.

use spine_design::fixtures::{arch_start, paper_five_link_start, paper_problem};
use spine_design::settings::ExtraOption;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{DesignProblem, DesignResult, Formulation, ScalingMethod, SolverSettings};
use spine_model::Design;

fn run(problem: &DesignProblem, start: &Design, formulation: Formulation) -> DesignResult {
    Solver::new(SolverPreset::Exact, formulation, &SolverSettings::default())
        .solve(problem, start, &mut |_| true)
        .unwrap()
}

/// A run started at a known optimum: Ipopt's barrier must not push the start away from its
/// active bounds (small `bound_push`, `bound_frac` and initial barrier parameter).
fn run_from_optimum(problem: &DesignProblem, start: &Design, formulation: Formulation) -> DesignResult {
    let mut settings = SolverSettings::default();
    for name in ["bound_push", "bound_frac"] {
        settings.ipopt_options.insert(name.into(), ExtraOption::Num(1e-10));
    }
    settings.ipopt_options.insert("mu_init".into(), ExtraOption::Num(1e-9));
    settings.ipopt_options.insert("acceptable_iter".into(), ExtraOption::Int(0));
    Solver::new(SolverPreset::Exact, formulation, &settings).solve(problem, start, &mut |_| true).unwrap()
}

fn assert_same_optimum(a: &DesignResult, b: &DesignResult, what: &str) {
    let rel = (a.objective - b.objective).abs() / a.objective.abs();
    assert!(rel <= 1e-6, "{what}: J {} vs {} (relative {rel:e})", a.objective, b.objective);
    for (x, y) in a.design.theta0.iter().zip(&b.design.theta0) {
        assert!((x - y).abs() <= 1e-5, "{what}: θ0 {:?} vs {:?}", a.design.theta0, b.design.theta0);
    }
    for (j, (x, y)) in a.design.stiffness.iter().zip(&b.design.stiffness).enumerate() {
        assert!((x - y).abs() <= 1e-5 * x.abs().max(1.0), "{what}: K[{j}] {x} vs {y}");
    }
}

fn assert_clean(r: &DesignResult, what: &str) {
    assert!(r.solver.converged, "{what}: {}", r.solver.status);
    assert!(r.warnings.is_empty(), "{what}: {:?}", r.warnings);
    let v = r.violations.as_ref().unwrap();
    assert!(v.max <= 1e-8, "{what}: violation {v:?}");
    assert!((r.end_displacement.unwrap() - r.delta_d).abs() <= 1e-8);
    assert!(r.passive.as_ref().unwrap().stability.stable && r.loaded.as_ref().unwrap().stability.stable);
    assert!(r.load_path.consistent);
}

/// Each formulation's optimum is an optimum of the other: started there, the other formulation
/// returns to it (J within 1e-6 relative, design within 1e-5). Run from the same start, the two
/// may reach different local optima of this non-convex problem (the paper says it has many).
fn cross_check(problem: &DesignProblem, start: &Design, name: &str) {
    let full = run(problem, start, Formulation::Full);
    assert_clean(&full, &format!("{name} full"));
    let reduced_from_full = run_from_optimum(problem, &full.design, Formulation::Reduced);
    assert_clean(&reduced_from_full, &format!("{name} reduced from the full optimum"));
    assert_same_optimum(&full, &reduced_from_full, &format!("{name}: full → reduced"));

    let reduced = run(problem, start, Formulation::Reduced);
    assert!(reduced.solver.converged, "{name} reduced: {}", reduced.solver.status);
    let full_from_reduced = run_from_optimum(problem, &reduced.design, Formulation::Full);
    assert_clean(&full_from_reduced, &format!("{name} full from the reduced optimum"));
    assert_same_optimum(&reduced, &full_from_reduced, &format!("{name}: reduced → full"));
}

#[test]
fn five_links_both_formulations_reach_the_same_optimum() {
    // Paper: 5 links, −10 N per node, −400 N at the end, start {π/5, 0, 0, 0, −π/5, 10⁴, 250, …, 0}.
    let problem = paper_problem(5, -10.0, -400.0, -0.02, 100.0);
    let start = paper_five_link_start();
    let (_, notes) = problem.project_start(&start);
    assert_eq!(notes.len(), 3, "θ0_1, θ0_5 and K_6 are outside the bounds: {notes:?}");
    cross_check(&problem, &start, "N=5");
    // From the paper's start both formulations reach the same optimum directly.
    let (full, reduced) = (run(&problem, &start, Formulation::Full), run(&problem, &start, Formulation::Reduced));
    assert_same_optimum(&full, &reduced, "N=5 from the paper's start");
}

#[test]
fn ten_links_both_formulations_reach_the_same_optimum() {
    let problem = paper_problem(10, -5.0, -400.0, -0.02, 100.0);
    cross_check(&problem, &arch_start(10, 0.3, 1e3), "N=10");
}

#[test]
fn unreachable_displacement_ends_with_the_infeasibility_status() {
    // δ_d = +0.2 m: the end would have to reach X = 1.2 m, beyond the chain's largest length
    // Σ a_i / cos(π/6) = 1.155 m.
    let problem = paper_problem(5, -10.0, -400.0, 0.2, 100.0);
    for formulation in [Formulation::Full, Formulation::Reduced] {
        let r = run(&problem, &paper_five_link_start(), formulation);
        assert!(!r.solver.converged, "{formulation:?}: {}", r.solver.status);
        assert!(!r.warnings.is_empty());
        if formulation == Formulation::Full {
            assert!(r.solver.infeasible, "{}", r.solver.status);
        }
    }
}

#[test]
fn scaling_off_and_iteration_limits_are_reported() {
    let problem = paper_problem(5, -10.0, -400.0, -0.02, 100.0);
    let settings = SolverSettings { scaling: ScalingMethod::None, ..SolverSettings::default() };
    let r = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
        .solve(&problem, &paper_five_link_start(), &mut |_| true)
        .unwrap();
    assert!(r.solver.optimal, "{}", r.solver.status);
    let settings = SolverSettings { max_iterations: 2, ..SolverSettings::default() };
    let r = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
        .solve(&problem, &paper_five_link_start(), &mut |_| true)
        .unwrap();
    assert_eq!(r.solver.status, spine_ipopt::Status::MaximumIterationsExceeded);
    assert!(r.warnings.iter().any(|w| matches!(w, spine_design::result::DesignWarning::NotConverged { .. })));
    let mut calls = 0;
    let r = Solver::new(SolverPreset::Exact, Formulation::Full, &SolverSettings::default())
        .solve(&problem, &paper_five_link_start(), &mut |_| {
            calls += 1;
            calls < 3
        })
        .unwrap();
    assert_eq!(r.solver.status, spine_ipopt::Status::UserRequestedStop);
}
