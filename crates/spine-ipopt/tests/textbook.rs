//! The binding on textbook problems with known solutions.

use spine_ipopt::{solve, IterationInfo, LinearSolver, Options, Problem, SetupError, Status};

/// Hock–Schittkowski problem 71:
/// min x1 x4 (x1 + x2 + x3) + x3  s.t.  x1 x2 x3 x4 ≥ 25,  Σ xi² = 40,  1 ≤ xi ≤ 5.
/// Known optimum x* = (1, 4.742999, 3.8211503, 1.3794082), f* = 17.0140171402 (Ipopt's own example output).
struct Hs071 {
    exact_hessian: bool,
    stop_after: Option<usize>,
    panic_in_objective_after: Option<usize>,
    objective_calls: usize,
    lower_product: f64,
}

impl Hs071 {
    fn new() -> Self {
        Hs071 {
            exact_hessian: true,
            stop_after: None,
            panic_in_objective_after: None,
            objective_calls: 0,
            lower_product: 25.0,
        }
    }
}

impl Problem for Hs071 {
    fn num_variables(&self) -> usize {
        4
    }
    fn num_constraints(&self) -> usize {
        2
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower.fill(1.0);
        upper.fill(5.0);
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        lower[0] = self.lower_product;
        upper[0] = f64::INFINITY;
        lower[1] = 40.0;
        upper[1] = 40.0;
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[1.0, 5.0, 5.0, 1.0]);
    }
    fn objective(&mut self, x: &[f64], _: bool) -> Option<f64> {
        self.objective_calls += 1;
        if let Some(limit) = self.panic_in_objective_after {
            if self.objective_calls > limit {
                panic!("deliberate panic in the objective");
            }
        }
        Some(x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2])
    }
    fn objective_gradient(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> bool {
        g[0] = x[3] * (2.0 * x[0] + x[1] + x[2]);
        g[1] = x[0] * x[3];
        g[2] = x[0] * x[3] + 1.0;
        g[3] = x[0] * (x[0] + x[1] + x[2]);
        true
    }
    fn constraints(&mut self, x: &[f64], _: bool, g: &mut [f64]) -> bool {
        g[0] = x[0] * x[1] * x[2] * x[3];
        g[1] = x.iter().map(|v| v * v).sum();
        true
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        (0..2).flat_map(|r| (0..4).map(move |c| (r, c))).collect()
    }
    fn jacobian_values(&mut self, x: &[f64], _: bool, v: &mut [f64]) -> bool {
        v[0] = x[1] * x[2] * x[3];
        v[1] = x[0] * x[2] * x[3];
        v[2] = x[0] * x[1] * x[3];
        v[3] = x[0] * x[1] * x[2];
        for i in 0..4 {
            v[4 + i] = 2.0 * x[i];
        }
        true
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        self.exact_hessian.then(|| (0..4).flat_map(|r| (0..=r).map(move |c| (r, c))).collect())
    }
    fn hessian_values(&mut self, x: &[f64], _: bool, s: f64, l: &[f64], _: bool, v: &mut [f64]) -> bool {
        // Lower triangle, row by row: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2) (3,3).
        v[0] = s * 2.0 * x[3] + l[1] * 2.0;
        v[1] = s * x[3] + l[0] * x[2] * x[3];
        v[2] = l[1] * 2.0;
        v[3] = s * x[3] + l[0] * x[1] * x[3];
        v[4] = l[0] * x[0] * x[3];
        v[5] = l[1] * 2.0;
        v[6] = s * (2.0 * x[0] + x[1] + x[2]) + l[0] * x[1] * x[2];
        v[7] = s * x[0] + l[0] * x[0] * x[2];
        v[8] = s * x[0] + l[0] * x[0] * x[1];
        v[9] = l[1] * 2.0;
        true
    }
    fn intermediate(&mut self, info: &IterationInfo) -> bool {
        self.stop_after.is_none_or(|limit| info.iteration < limit)
    }
}

const X_STAR: [f64; 4] = [1.0, 4.742_999_64, 3.821_149_98, 1.379_408_29];
const F_STAR: f64 = 17.014_017_140_2;

fn tight() -> Options {
    Options::new().number("tol", 1e-10)
}

#[test]
fn hs071_exact_hessian_reaches_the_known_optimum() {
    let solution = solve(&mut Hs071::new(), &tight()).unwrap();
    assert_eq!(solution.status, Status::SolveSucceeded);
    assert!((solution.objective - F_STAR).abs() < 1e-7, "f = {}", solution.objective);
    for (x, x_star) in solution.x.iter().zip(X_STAR) {
        assert!((x - x_star).abs() < 1e-6, "{:?}", solution.x);
    }
    assert!((solution.g[1] - 40.0).abs() < 1e-8);
    // Ipopt relaxes bounds by `bound_relax_factor` (1e-8, relative).
    assert!(solution.g[0] >= 25.0 * (1.0 - 1e-8) - 1e-12, "g = {:?}", solution.g);
    // Active inequality: its multiplier is nonzero; Ipopt's sign convention gives λ ≤ 0 for a
    // lower bound on g that is active.
    assert!(solution.lambda[0] < -1e-3, "{:?}", solution.lambda);
    // x1 sits at its lower bound 1.
    assert!(solution.z_lower[0] > 1e-3);
    assert!(solution.iterations > 0 && solution.iterations < 30);
    assert!(solution.evaluations.hessian > 0);
    assert!(solution.callback_time <= solution.wall_time);
}

/// Debian's Ipopt 3.11 reads its CPU clock (`Ipopt::CpuTime()`, a `getrusage` call in the library)
/// about 70 times per iteration; the binding's definition of that function interposes the
/// library's (`ffi.rs`), and the library calls it: the reads counted here, and those of its wall
/// clock, replaced the same way. `max_cpu_time` still
/// stops a run, on the replacement's clock.
#[test]
fn ipopt_3_11_reads_the_replaced_cpu_clock() {
    let before = (spine_ipopt::replaced_clock_reads(), spine_ipopt::replaced_wall_clock_reads());
    let solution = solve(&mut Hs071::new(), &tight()).unwrap();
    assert_eq!(solution.status, Status::SolveSucceeded);
    let reads = spine_ipopt::replaced_clock_reads() - before.0;
    let wall = spine_ipopt::replaced_wall_clock_reads() - before.1;
    if spine_ipopt::IPOPT_VERSION.starts_with("3.11") {
        assert!(reads >= 10 * solution.iterations, "{reads} reads in {} iterations", solution.iterations);
        // Its wall clock too (`Ipopt::WallclockTime()`, a `gettimeofday` in the library).
        assert!(wall >= 10 * solution.iterations, "{wall} wall-clock reads in {} iterations", solution.iterations);
    }
    let limited = solve(&mut Hs071::new(), &tight().number("max_cpu_time", 1e-9)).unwrap();
    assert_eq!(limited.status, Status::MaximumCpuTimeExceeded);
}

/// Debian's Ipopt 3.11 with MUMPS aborts (and exits 0) when two solves overlap in one process;
/// the binding serialises them. Four threads solve at once: every solve reaches the optimum.
/// MUMPS solves from several threads are serialised by the wrapper's lock; the workspace's own
/// linear solver keeps its state in Ipopt's handle, so four solves run at once. Both give the
/// optimum from every thread.
#[test]
fn solves_from_several_threads_all_succeed_with_either_linear_solver() {
    spine_kkt::install().unwrap();
    for linear_solver in [LinearSolver::Mumps, LinearSolver::Pardiso] {
        let threads: Vec<_> = (0..4)
            .map(|_| {
                std::thread::spawn(move || {
                    let options = tight().string("linear_solver", linear_solver.name());
                    let solution = solve(&mut Hs071::new(), &options).unwrap();
                    (solution.status, solution.objective)
                })
            })
            .collect();
        for t in threads {
            let (status, objective) = t.join().unwrap();
            assert_eq!(status, Status::SolveSucceeded, "{linear_solver:?}");
            assert!((objective - F_STAR).abs() < 1e-7, "{linear_solver:?}");
        }
    }
}

/// With the workspace's solver installed (`spine_kkt::install`) and `linear_solver = "pardiso"`,
/// Ipopt factorises with it (its counters move, MUMPS's default does not move them), it reaches the
/// optimum MUMPS reaches, and an unknown linear solver is a setup error.
#[test]
fn the_workspaces_linear_solver_is_used_when_asked_and_agrees_with_mumps() {
    spine_kkt::install().unwrap();
    let before = spine_kkt::pardiso::counters();
    let ours = solve(&mut Hs071::new(), &tight().string("linear_solver", "pardiso")).unwrap();
    let after = spine_kkt::pardiso::counters();
    assert!(after.factorizations > before.factorizations && after.solves > before.solves);
    let mumps = solve(&mut Hs071::new(), &tight()).unwrap();
    assert_eq!(ours.status, Status::SolveSucceeded);
    assert_eq!(mumps.status, Status::SolveSucceeded);
    for (a, b) in ours.x.iter().zip(&mumps.x) {
        assert!((a - b).abs() < 1e-8, "{:?} against {:?}", ours.x, mumps.x);
    }
    assert!(matches!(
        solve(&mut Hs071::new(), &tight().string("linear_solver", "ma27")),
        Err(SetupError::InvalidOption(_))
    ));
}

#[test]
fn hs071_limited_memory_reaches_the_same_optimum() {
    let mut problem = Hs071 { exact_hessian: false, ..Hs071::new() };
    let solution = solve(&mut problem, &tight()).unwrap();
    assert!(solution.status.is_converged(), "{}", solution.status);
    assert!((solution.objective - F_STAR).abs() < 1e-6);
    assert_eq!(solution.evaluations.hessian, 0);
}

#[test]
fn user_stop_is_reported_as_such() {
    let mut problem = Hs071 { stop_after: Some(2), ..Hs071::new() };
    let solution = solve(&mut problem, &tight()).unwrap();
    assert_eq!(solution.status, Status::UserRequestedStop);
    assert_eq!(solution.iterations, 2);
}

/// A run's time limit (`spine_stop`) stops Ipopt at its first iteration with status `time_limit`;
/// a limit the solve stays within changes nothing.
#[test]
fn a_passed_time_limit_stops_ipopt_and_is_reported_as_such() {
    let (solution, reached) =
        spine_stop::with_time_limit(Some(std::time::Duration::ZERO), || solve(&mut Hs071::new(), &tight()).unwrap());
    assert!(reached);
    assert_eq!(solution.status, Status::TimeLimit);
    assert_eq!(solution.status.name(), "time_limit");
    assert!(!solution.status.is_converged());
    assert_eq!(solution.iterations, 0);
    let (solution, reached) = spine_stop::with_time_limit(Some(std::time::Duration::from_secs(3600)), || {
        solve(&mut Hs071::new(), &tight()).unwrap()
    });
    assert!(!reached);
    assert_eq!(solution.status, Status::SolveSucceeded);
}

#[test]
fn iteration_limit_is_reported_as_such() {
    let solution = solve(&mut Hs071::new(), &tight().integer("max_iter", 3)).unwrap();
    assert_eq!(solution.status, Status::MaximumIterationsExceeded);
    assert!(!solution.status.is_converged());
}

#[test]
fn infeasible_constraints_end_with_the_infeasibility_status() {
    // x1 x2 x3 x4 ≥ 700 is impossible with 1 ≤ xi ≤ 5 and Σ xi² = 40 (the largest product is 100).
    let mut problem = Hs071 { lower_product: 700.0, ..Hs071::new() };
    let solution = solve(&mut problem, &tight()).unwrap();
    assert!(solution.status.is_infeasible(), "{}", solution.status);
}

#[test]
fn a_panic_in_a_callback_is_caught_and_resumed_after_ipopt_returns() {
    let result = std::panic::catch_unwind(|| {
        let mut problem = Hs071 { panic_in_objective_after: Some(3), ..Hs071::new() };
        solve(&mut problem, &tight())
    });
    let payload = result.expect_err("the panic must resume in Rust");
    let message = payload.downcast_ref::<&str>().copied().unwrap_or_default();
    assert_eq!(message, "deliberate panic in the objective");
    // Ipopt is still usable afterwards.
    let solution = solve(&mut Hs071::new(), &tight()).unwrap();
    assert_eq!(solution.status, Status::SolveSucceeded);
}

#[test]
fn unknown_options_and_bad_structures_are_setup_errors() {
    let err = solve(&mut Hs071::new(), &Options::new().number("no_such_option", 1.0)).unwrap_err();
    assert!(matches!(err, SetupError::InvalidOption(ref s) if s.contains("no_such_option")), "{err}");
    let err = solve(&mut Hs071::new(), &Options::new().string("tol", "text")).unwrap_err();
    assert!(matches!(err, SetupError::InvalidOption(_)));

    struct Upper(Hs071);
    impl Problem for Upper {
        fn num_variables(&self) -> usize {
            4
        }
        fn num_constraints(&self) -> usize {
            2
        }
        fn variable_bounds(&self, l: &mut [f64], u: &mut [f64]) {
            self.0.variable_bounds(l, u)
        }
        fn constraint_bounds(&self, l: &mut [f64], u: &mut [f64]) {
            self.0.constraint_bounds(l, u)
        }
        fn initial_point(&self, x: &mut [f64]) {
            self.0.initial_point(x)
        }
        fn objective(&mut self, x: &[f64], n: bool) -> Option<f64> {
            self.0.objective(x, n)
        }
        fn objective_gradient(&mut self, x: &[f64], n: bool, g: &mut [f64]) -> bool {
            self.0.objective_gradient(x, n, g)
        }
        fn constraints(&mut self, x: &[f64], n: bool, g: &mut [f64]) -> bool {
            self.0.constraints(x, n, g)
        }
        fn jacobian_structure(&self) -> Vec<(usize, usize)> {
            self.0.jacobian_structure()
        }
        fn jacobian_values(&mut self, x: &[f64], n: bool, v: &mut [f64]) -> bool {
            self.0.jacobian_values(x, n, v)
        }
        fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
            Some(vec![(0, 1)])
        }
        fn hessian_values(&mut self, _: &[f64], _: bool, _: f64, _: &[f64], _: bool, _: &mut [f64]) -> bool {
            true
        }
    }
    let err = solve(&mut Upper(Hs071::new()), &Options::new()).unwrap_err();
    assert!(matches!(err, SetupError::BadStructure(_)), "{err}");
}

#[test]
fn the_linked_ipopt_is_the_one_asked_for() {
    let version = spine_ipopt::IPOPT_VERSION;
    assert!(version.starts_with("3.11.") || version.starts_with("3.14."), "unexpected Ipopt {version}");
    // `just ipopt314 test` sets SPINE_EXPECT_IPOPT=3.14: the tests must really run on that backend.
    if let Ok(expected) = std::env::var("SPINE_EXPECT_IPOPT") {
        assert!(version.starts_with(&format!("{expected}.")), "built against Ipopt {version}, expected {expected}");
    }
    // And the library answers like that version: HS071 converges on either.
    let solution = solve(&mut Hs071::new(), &tight()).unwrap();
    assert_eq!(solution.status, Status::SolveSucceeded);
}
