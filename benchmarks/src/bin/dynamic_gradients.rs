//! `just bench-gradients`: the cost of eq. (37)'s constraint gradients by the discrete adjoint
//! against forward sensitivities and against a plain simulation, for the periodic fixture
//! chain of N links (`spine_dynamics::fixtures::periodic_problem`) under pulses.
//!
//! Usage: `dynamic_gradients [N ...]` (default 7 20 50). Each timing is the fastest of `REPEATS`.
#![forbid(unsafe_code)]

use spine_dynamic_design::periodic_gradient::{eq37_point, eq37_values};
use spine_dynamic_design::periodic_settings::Sensitivities;
use spine_dynamic_design::PeriodicDesignSettings;
use spine_dynamics::fixtures::periodic_problem;
use spine_dynamics::Forcing;
use std::time::Instant;

const REPEATS: usize = 3;

fn fastest<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..REPEATS {
        let clock = Instant::now();
        let r = f();
        best = best.min(clock.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    // `--sweeps-only`: the adjoint sweeps alone, 20 times (for a profiler).
    let sweeps_only = args.iter().any(|a| a == "--sweeps-only");
    let mut sizes: Vec<usize> = args.iter().filter(|a| !a.starts_with("--")).map(|a| a.parse().expect("N")).collect();
    if sizes.is_empty() {
        sizes = vec![7, 20, 50];
    }
    println!("| N | springs | steps | plain run (s) | adjoint sweep (s) | plain + adjoint / plain | forward run (s) | forward / plain | forward / (plain + adjoint) | max gradient difference |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for n in sizes {
        let p = periodic_problem(n);
        let forcing = Forcing::PulseTrain { period: 0.4, duty: 0.5, delay: 0.0 };
        let settings = PeriodicDesignSettings::default();
        let mut forward_settings = settings.clone();
        forward_settings.gradient.sensitivities = Sensitivities::Forward;
        let k = p.design.stiffness.clone();
        let periods = 3;
        let (plain, point) = fastest(|| eq37_values(&p, &forcing, &k, -0.01, &settings, periods).expect("a run"));
        if sweeps_only {
            for _ in 0..20 {
                assert!(point.clone().constraint_gradients());
            }
            continue;
        }
        let (sweep, adjoint) = fastest(|| {
            let mut q = point.clone();
            assert!(q.constraint_gradients());
            q
        });
        let (forward_time, forward) =
            fastest(|| eq37_point(&p, &forcing, &k, -0.01, &forward_settings, periods).expect("a run"));
        let scale = forward.minima[0].gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
        let difference = adjoint
            .minima
            .iter()
            .zip(&forward.minima)
            .flat_map(|(a, f)| a.gradient.iter().zip(&f.gradient).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max)
            / scale;
        println!(
            "| {n} | {} | {} | {plain:.4} | {sweep:.4} | {:.2} | {forward_time:.4} | {:.1} | {:.1} | {difference:.1e} |",
            k.len(),
            point.response.stats.accepted_steps,
            (plain + sweep) / plain,
            forward_time / plain,
            forward_time / (plain + sweep),
        );
    }
}
