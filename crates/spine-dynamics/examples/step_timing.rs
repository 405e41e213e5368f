//! The scaled step case of `just bench-dynamics` at one size and tolerance, simulated `REPEATS`
//! times: the best wall time, the work counts (steps, evaluations, Newton iterations, Jacobians, factorisations), `T_90` and `Δ(1 s)` (for profiling a step
//! of the integrator, e.g. under `perf record`):
//! `cargo run --release -p spine-dynamics --example step_timing -- N RTOL REPEATS`.
use spine_dynamics::fixtures::peer_step_problem;
use spine_dynamics::response::simulate_step;
use spine_dynamics::{Forcing, Options, StepSettings};

fn main() {
    let arg = |k: usize, name: &str| {
        std::env::args().nth(k).unwrap_or_else(|| panic!("usage: step_timing N RTOL REPEATS ({name})"))
    };
    let n: usize = arg(1, "N").parse().expect("N: a number of links");
    let rtol: f64 = arg(2, "RTOL").parse().expect("RTOL: a tolerance");
    let repeats: usize = arg(3, "REPEATS").parse().expect("REPEATS: a count");
    let problem = peer_step_problem(n);
    let ends = problem.static_ends(&Default::default()).expect("stable ends");
    let d = problem.dynamics(Forcing::Step);
    // The harness's settings (benchmarks/src/bin/dynamics_scaling).
    let integrator = Options { rtol, atol: rtol / 100.0, max_steps: 10_000_000, ..Default::default() };
    let settings = StepSettings { t_end: 1.0, samples: 2, integrator, ..Default::default() };
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats.max(1) {
        let r = simulate_step(&d, ends.clone(), &settings, false);
        best = best.min(r.time_seconds);
        last = Some(r);
    }
    let r = last.expect("at least one run");
    let s = &r.stats;
    println!(
        "N = {n}, rtol {rtol:e}: best {:.3} ms, {} steps ({} rejected), {} evaluations, {} Newton iterations \
         ({} failed), {} Jacobians, {} factorisations, T_90 = {:?} s, Δ(1 s) = {:e} m",
        best * 1e3,
        s.accepted_steps,
        s.rejected_steps,
        s.rhs_evaluations,
        s.newton_iterations,
        s.newton_failures,
        s.jacobian_evaluations,
        s.factorizations,
        r.rise_time,
        r.final_delta
    );
}
