//! The 7-link periodic case of Sec. 5.2.2: `cargo run --release -p spine-dynamics --example periodic -- L_x amplitude K period`.
use spine_dynamics::{periodic_response, DynamicProblem, Forcing, PeriodicSettings};
use spine_model::fixtures::{arch, uniform_loads};

fn main() {
    let args: Vec<f64> = std::env::args().skip(1).map(|a| a.parse().expect("numbers")).collect();
    let lx = args.first().copied().unwrap_or(1.0);
    let amp = args.get(1).copied().unwrap_or(0.4);
    let k = args.get(2).copied().unwrap_or(3000.0);
    let period = args.get(3).copied().unwrap_or(2.0);
    let n = 7;
    let (mut chain, mut design) = arch(n, lx, amp, k);
    design.stiffness[n] = k;
    chain.masses = vec![0.5; n];
    let mut passive = uniform_loads(n, -50.0, 0.0);
    for j in 1..=3 {
        passive.p_y[j] = -100.0;
    }
    let structure = spine_model::Structure { chain, passive, actuation: uniform_loads(n, 0.0, -4000.0) };
    let problem = DynamicProblem { structure, design, damping: vec![50.0; n + 1] };
    match periodic_response(&problem, Forcing::PulseTrain { period, duty: 0.5, delay: 0.0 }, None, &PeriodicSettings::default()) {
        Ok(r) => println!(
            "min {:.4e} m at {:.3} s, max {:.4e}, reach {:?}, return {:?}, settled {} after {} periods ({:.1e}), passive {:.4e}, loaded {:.4e}, {:.3} s, {} steps",
            r.min_end_displacement, r.time_of_minimum, r.max_end_displacement, r.reach_time, r.return_time, r.settled, r.periods_run,
            r.period_change, r.ends.passive_displacement, r.ends.loaded_displacement, r.time_seconds, r.stats.accepted_steps
        ),
        Err(e) => println!("error: {e}"),
    }
}
