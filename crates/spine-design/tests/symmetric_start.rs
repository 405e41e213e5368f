//! Fig. 6's start lies on a knife edge. Its problem is mirror-symmetric (docs/findings.md) and so
//! is its start (the arch is antisymmetric in `θ0`, every `K` equal): the start is its own mirror
//! image, and which way Ipopt's path leaves the symmetric designs is decided by rounding.
//! Moved by 1e-6 in every variable, the start reaches one optimum (or its mirror image) with
//! either linear solver; the exactly symmetric start with MUMPS reached another one
//! (J = 6.7978e-3 against 7.2704e-3), which is therefore not the optimum of fig. 6's start but
//! an accident of MUMPS's rounding.
//!
//! What is compared is the first-order point Ipopt's path reaches ([`spine_design::solve::Solver::run`]). The reported
//! optimum ([`spine_design::solve::Solver::solve`]) may go on below it: 7.2704e-3 is a weak minimum (curvature ~1e-10
//! against a Hessian scale of 1e4), and its probe along the flat direction reaches 6.7978e-3 where
//! the certificate's rounding calls it weak rather than strict (with MUMPS on Ipopt 3.14 it does).
//! The test checks that the reported optimum is never above the point reached.

use spine_design::fixtures::{arch_start, paper_problem};
use spine_design::multistart::mirror;
use spine_design::settings::LinearSolver;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{DesignResult, Formulation, SolverSettings};
use spine_model::Design;

/// The first-order point Ipopt's path reaches from `start`, checked; and the reported optimum.
fn solve(start: &Design, linear_solver: LinearSolver) -> DesignResult {
    let problem = paper_problem(10, -5.0, -400.0, -0.02, 1.0);
    let settings = SolverSettings { linear_solver, ..SolverSettings::default() };
    let reached = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
        .run(&problem, start, &mut |_| true)
        .unwrap()
        .check(&problem, &settings);
    let reported =
        Solver::new(SolverPreset::Exact, Formulation::Full, &settings).solve(&problem, start, &mut |_| true).unwrap();
    assert!(
        reported.objective <= reached.objective * (1.0 + 1e-9),
        "the reported optimum {} is above the point reached {}",
        reported.objective,
        reached.objective
    );
    reached
}

/// The arch start of fig. 6 with every variable moved by at most `size` (relative for `K`), in
/// one of several fixed directions that favour neither end.
fn moved_start(direction: usize, size: f64) -> Design {
    let mut start = arch_start(10, 0.3, 1000.0);
    let wiggle = |i: usize| (7.3 * i as f64 + 1.1 * direction as f64 + 0.4).sin();
    for (i, t) in start.theta0.iter_mut().enumerate() {
        *t += size * wiggle(i);
    }
    for (j, k) in start.stiffness.iter_mut().enumerate() {
        *k *= 1.0 + size * wiggle(j + 10);
    }
    start
}

#[test]
fn near_the_symmetric_start_both_linear_solvers_reach_one_optimum_up_to_its_mirror_image() {
    let reference = solve(&moved_start(0, 1e-6), LinearSolver::Spine);
    assert!(reference.is_clean(), "{:?}", reference.warnings);
    let image = mirror(&reference.design);
    for direction in 0..4 {
        for linear_solver in [LinearSolver::Spine, LinearSolver::Mumps] {
            let r = solve(&moved_start(direction, 1e-6), linear_solver);
            let what = format!("direction {direction}, {linear_solver:?}");
            assert!(r.is_clean(), "{what}: {:?}", r.warnings);
            let rel = (r.objective - reference.objective).abs() / reference.objective;
            assert!(rel <= 1e-8, "{what}: J = {} against {}", r.objective, reference.objective);
            let near = |d: &Design| d.theta0.iter().zip(&r.design.theta0).all(|(a, b)| (a - b).abs() <= 1e-6);
            assert!(near(&reference.design) || near(&image), "{what}: θ0 = {:?}", r.design.theta0);
        }
    }
}

/// The knife-edge check finds this edge: fig. 6's start with two antithetic pairs of moved starts
/// (the case's default) reaches the optimum and its mirror image, whatever the unmoved start does
/// with this build's rounding; the two are one `J` and told apart by `θ0`.
#[test]
fn the_knife_edge_check_finds_both_sides_of_the_symmetric_start() {
    use spine_design::knife_edge::{moved_starts, KnifeEdge, KnifeEdgeSettings};
    let problem = paper_problem(10, -5.0, -400.0, -0.02, 1.0);
    let start = arch_start(10, 0.3, 1000.0);
    let settings = KnifeEdgeSettings::default();
    let solver = Solver::new(SolverPreset::Exact, Formulation::Full, &SolverSettings::default());
    let mut results = vec![solver.solve(&problem, &start, &mut |_| true).unwrap()];
    for moved in moved_starts(&problem, &start, &settings) {
        results.push(solver.solve(&problem, &moved, &mut |_| true).unwrap());
    }
    let edge = KnifeEdge::of(&settings, &results);
    assert!(edge.split, "{edge:#?}");
    assert_eq!(edge.branches.len(), 2, "{edge:#?}");
    let (a, b) = (&edge.branches[0], &edge.branches[1]);
    assert!(a.clean && b.clean);
    assert_eq!(b.mirror_of, Some(0), "{edge:#?}");
    assert!((a.objective - b.objective).abs() <= 1e-8 * a.objective, "{} against {}", a.objective, b.objective);
    // Each antithetic pair falls on both sides.
    for pair in [[1, 2], [3, 4]] {
        assert_ne!(edge.branch_of(pair[0]), edge.branch_of(pair[1]), "{edge:#?}");
    }
    assert_eq!(edge.failed, vec![]);
}
