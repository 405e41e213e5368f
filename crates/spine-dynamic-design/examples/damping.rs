//! Eq. (35) on an arch-shaped spine: `cargo run --release -p spine-dynamic-design --example damping -- N T_d`.
use spine_dynamic_design::{design_damping, DampingSettings};
use spine_dynamics::fixtures::arch_problem;

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("numbers")).collect();
    let n = args.first().copied().unwrap_or(5.0) as usize;
    let target = args.get(1).copied().unwrap_or(0.2);
    let problem = arch_problem(n, 10.0);
    let r = design_damping(&problem, target, &DampingSettings::default()).expect("stable ends");
    println!(
        "{} ({} it, {} sims, {:.2} s): C0 = {:?}, C = {:.3?}, T90 = {:?} (err {:?}), J = {:.4e}",
        r.status,
        r.iterations,
        r.simulations,
        r.time_seconds,
        r.uniform_start,
        r.damping,
        r.rise_time,
        r.rise_time_error,
        r.objective
    );
}
