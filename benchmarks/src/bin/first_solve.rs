//! Where the first solve of eq. (33) in a process spends the time a later one does not (issue 50,
//! item 4): the scaled family of `docs/PEERS.md` at N = 5 (its case file, tolerances and start),
//! solved `REPEATS` times in one process, with the one-time steps timed on their own first:
//! loading the linear solver ([`spine_kkt::install`]), and the first Ipopt run. Prints every
//! solve's wall time and the difference between the first and the fastest later one.
//!
//! Usage: `first_solve [N] [REPEATS]` (defaults 5 and 5). Run it as a fresh process each time:
//! the first solve of a process is what it measures.
#![forbid(unsafe_code)]

use spine_benchmarks::{cli, peers};
use spine_design::refine::{Refine, RefineMode};
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::Formulation;
use std::time::Instant;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// The first eq. (33) solve of a process against the repeated ones (the linear solver's loading).
#[derive(clap::Parser)]
struct Args {
    /// Links of the scaled family (at least 2).
    #[arg(default_value_t = 5, value_parser = cli::links)]
    n: usize,
    /// Solves after the first (at least 1).
    #[arg(default_value_t = 5, value_parser = cli::runs)]
    repeats: usize,
}

fn main() {
    let Args { n, repeats } = <Args as clap::Parser>::parse();
    let clock = Instant::now();
    let valid = peers::scaled_family_design(n);
    let mut settings = valid.settings.clone();
    settings.refine = peers::bench_ladder(n).map_or(Refine::Mode(RefineMode::Off), Refine::Ladder);
    let case_seconds = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let install = settings.linear_solver.ready();
    let install_seconds = clock.elapsed().as_secs_f64();
    println!(
        "case file parsed: {:.3} ms; linear solver loaded ({install:?}): {:.3} ms",
        case_seconds * 1e3,
        install_seconds * 1e3
    );
    let mut times = Vec::new();
    for k in 0..repeats {
        let clock = Instant::now();
        let r = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
            .solve(&valid.problem, &valid.start, &mut |_| true)
            .expect("a valid problem");
        let t = clock.elapsed().as_secs_f64();
        println!(
            "solve {k}: {:.3} ms, {} ({} iterations), J = {:.9e}",
            t * 1e3,
            r.solver.status,
            r.solver.iterations,
            r.objective
        );
        times.push(t);
    }
    let later = times[1..].iter().copied().fold(f64::INFINITY, f64::min);
    if later.is_finite() {
        println!("first − fastest later: {:.3} ms", (times[0] - later) * 1e3);
    }
}
