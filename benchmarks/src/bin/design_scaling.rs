//! `just bench-design`: eq. (33) on the scaled family of `../shared/PEERS.md` for growing N, full
//! space and (where affordable) reduced space: Ipopt status, iterations, wall time, time per
//! iteration and the optimum J. Each configuration runs `REPEATS` times and reports the fastest
//! (machines here are shared and noisy).
//!
//! Usage: `design_scaling [N ...]` (default 5 10 20 50 100 200 500 1000).

use spine_design::fixtures::{arch_start, scaled_family};
use spine_design::{solve_design, Formulation, SolverSettings};

const REPEATS: usize = 3;
/// Largest N for the reduced space: its finite-difference Hessian costs 2(2N + 1) equilibrium
/// solves per iteration and a dense (2N + 1)² block.
const REDUCED_MAX_N: usize = 100;

fn main() {
    let sizes: Vec<usize> = std::env::args().skip(1).map(|a| a.parse().expect("N must be a positive integer")).collect();
    let sizes = if sizes.is_empty() { vec![5, 10, 20, 50, 100, 200, 500, 1000] } else { sizes };
    println!("| N | formulation | status | iterations | wall time (s) | time per iteration (ms) | J (J) | clean |");
    println!("|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        let problem = scaled_family(n);
        let s = n as f64 / 10.0;
        let start = arch_start(n, 0.3, 1e3 * s * s);
        for formulation in [Formulation::Full, Formulation::Reduced] {
            if formulation == Formulation::Reduced && n > REDUCED_MAX_N {
                println!("| {n} | reduced | skipped (N > {REDUCED_MAX_N}) | | | | | |");
                continue;
            }
            let mut best: Option<(f64, spine_design::DesignResult)> = None;
            for _ in 0..REPEATS {
                let clock = std::time::Instant::now();
                let r = solve_design(&problem, &start, formulation, &SolverSettings::default(), &mut |_| true).expect("valid problem");
                let t = clock.elapsed().as_secs_f64();
                if best.as_ref().is_none_or(|(bt, _)| t < *bt) {
                    best = Some((t, r));
                }
            }
            let (t, r) = best.expect("at least one repeat");
            let per_iteration = 1e3 * r.solver.ipopt_seconds / r.solver.iterations.max(1) as f64;
            println!(
                "| {n} | {} | {} | {} | {t:.4} | {per_iteration:.3} | {:.9e} | {} |",
                formulation.name(),
                r.solver.status,
                r.solver.iterations,
                r.objective,
                if r.is_clean() { "yes" } else { "no" }
            );
        }
    }
}
