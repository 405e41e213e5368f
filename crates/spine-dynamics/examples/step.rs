//! Step response of an arch-shaped spine: `cargo run --release -p spine-dynamics --example step -- N C`.
use spine_dynamics::{step_response, DynamicProblem, StepSettings};
use spine_model::fixtures::{arch, uniform_loads};

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("numbers")).collect();
    let n = args.first().copied().unwrap_or(10.0) as usize;
    let c = args.get(1).copied().unwrap_or(50.0);
    let (mut chain, design) = arch(n, 1.0, 0.4, 1000.0);
    chain.masses = vec![0.5; n];
    let problem = DynamicProblem {
        chain,
        design,
        damping: vec![c; n + 1],
        passive: uniform_loads(n, -5.0, 0.0),
        actuation: uniform_loads(n, 0.0, -400.0),
    };
    let r = step_response(&problem, &StepSettings::default(), false).expect("stable ends");
    println!(
        "N = {n}, C = {c}: Δ∞ = {:.4e} m, T90 = {:?} s, τ(T90) = {:?}, fit τ = {:.3} (rms {:.2e}), settled {} ({:.1e}), drift {:?}, {:?}, {:.3} s",
        r.delta_inf, r.rise_time, r.tau_from_rise_time, r.fit.tau, r.fit.rms_error, r.settled, r.settle_error, r.drift, r.stats, r.time_seconds
    );
}
