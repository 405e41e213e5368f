//! Step response of an arch-shaped spine: `cargo run --release -p spine-dynamics --example step -- N C`.
use spine_dynamics::fixtures::arch_problem;
use spine_dynamics::{step_response, StepSettings};

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("numbers")).collect();
    let n = args.first().copied().unwrap_or(10.0) as usize;
    let c = args.get(1).copied().unwrap_or(50.0);
    let problem = arch_problem(n, c);
    let r = step_response(&problem, &StepSettings::default(), false).expect("stable ends");
    println!(
        "N = {n}, C = {c}: Δ∞ = {:.4e} m, T90 = {:?} s, τ(T90) = {:?}, fit τ = {:.3} (rms {:.2e}), settled {} ({:.1e}), drift {:?}, {:?}, {:.3} s",
        r.delta_inf, r.rise_time, r.tau_from_rise_time, r.fit.tau, r.fit.rms_error, r.settled, r.settle_error, r.drift, r.stats, r.time_seconds
    );
}
