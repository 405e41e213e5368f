//! `just bench-dynamics`: wall time to simulate 1 s of the step response (Sec. 5.2.1) for growing N,
//! with the integrator's work: accepted and rejected steps, right-hand-side evaluations (each one
//! solves the bordered mass-matrix system in O(N) by the articulated-body recursion), Jacobians
//! (2N dual-number passes each). The chain is `spine_dynamics::fixtures::arch_problem` with
//! 50 N·m·s/rad at every joint; default tolerances (`spine_dynamics::DEFAULT_RTOL` 1e-9,
//! `DEFAULT_ATOL` 1e-11). Each size runs `REPEATS` times and reports the fastest (shared, noisy
//! machines).
//!
//! Usage: `dynamics_scaling [N ...]` (default 5 10 20 50).
#![forbid(unsafe_code)]

use spine_dynamics::fixtures::arch_problem;
use spine_dynamics::{step_response, StepSettings};

const REPEATS: usize = 3;

fn main() {
    let sizes: Vec<usize> =
        std::env::args().skip(1).map(|a| a.parse().expect("N must be a positive integer")).collect();
    let sizes = if sizes.is_empty() { vec![5, 10, 20, 50] } else { sizes };
    println!("| N | wall time for 1 s (s) | accepted steps | rejected | f evaluations | Jacobians | Newton iterations | T_90 (s) | max abs(Phi) (m) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        let problem = arch_problem(n, 50.0);
        let settings = StepSettings { t_end: 1.0, samples: 11, ..Default::default() };
        let runs: Vec<_> =
            (0..REPEATS).map(|_| step_response(&problem, &settings, false).expect("stable ends")).collect();
        let r = runs.iter().min_by(|a, b| a.time_seconds.total_cmp(&b.time_seconds)).expect("runs");
        println!(
            "| {n} | {:.4} | {} | {} | {} | {} | {} | {} | {:.1e} |",
            r.time_seconds,
            r.stats.accepted_steps,
            r.stats.rejected_steps,
            r.stats.rhs_evaluations,
            r.stats.jacobian_evaluations,
            r.stats.newton_iterations,
            r.rise_time.map_or("—".into(), |t| format!("{t:.4}")),
            r.drift.max_constraint.max(r.drift.max_constraint_dense)
        );
    }
}
