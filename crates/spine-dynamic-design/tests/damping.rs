//! Eq. (35): the damping design meets its rise time at a KKT point.

use spine_dynamic_design::{design_damping, DampingSettings};
use spine_dynamics::fixtures::arch_problem as problem;
use spine_dynamics::response::rise_time;
use spine_dynamics::Forcing;

#[test]
fn damping_design_meets_the_rise_time_and_is_a_kkt_point() {
    let p = problem(4, 20.0);
    let target = 0.1;
    let r = design_damping(&p, target, &DampingSettings::default()).unwrap();
    assert!(r.converged, "{}", r.status);
    assert!(r.rise_time_error.unwrap() < 5e-3, "T90 = {:?}", r.rise_time);
    let c0 = r.uniform_start.unwrap();
    assert!(r.objective < 0.5 * 5.0 * c0 * c0, "redistribution lowers ½ΣC² below the uniform start");
    // Stationarity: C_i = μ dT90/dC_i for every damper off its bounds.
    let ends = p.static_ends(&Default::default()).unwrap();
    let mut d = p.dynamics(Forcing::Step);
    d.damping = r.damping.clone();
    let (_, grad) = rise_time(&d, &ends, &DampingSettings::default().step, true);
    let grad = grad.unwrap();
    let free: Vec<usize> = (0..5).filter(|&i| r.damping[i] > 1.0 + 1e-3 && r.damping[i] < 1e3 - 1e-3).collect();
    assert!(free.len() >= 2, "{:?}", r.damping);
    let mu: Vec<f64> = free.iter().map(|&i| r.damping[i] / grad[i]).collect();
    for m in &mu {
        assert!((m - mu[0]).abs() < 1e-3 * mu[0].abs(), "C_i / (dT/dC_i) = {mu:?}");
    }
}

/// The paper's "trial and error" on the lower limit: where the design at the stated limit turns
/// back, the search raises the limit until it does not, and the reported design is over-damped and
/// still meets its rise time; its limit is the smallest over-damped one tried, and a limit just
/// below it (the largest failing one tried) is not over-damped.
#[test]
fn the_lower_limit_is_raised_until_the_design_is_overdamped() {
    // The 10-link arch for T_d = 0.5 s turns back at C_min = 1 (by 12 % of the swing).
    let (p, target) = (problem(10, 20.0), 0.5);
    let plain = design_damping(&p, target, &DampingSettings::default()).unwrap();
    assert!(plain.converged && !plain.response.overdamping.is_overdamped(), "{:?}", plain.response.overdamping);
    let settings = DampingSettings { overdamped: true, ..DampingSettings::default() };
    let r = design_damping(&p, target, &settings).unwrap();
    let search = r.lower_limit.as_ref().expect("the search is recorded");
    let used = search.used.expect("an over-damped limit below the uniform start");
    assert!(used > 1.0 && r.damping.iter().all(|&c| c >= used - 1e-6), "{search:?} {:?}", r.damping);
    assert!(r.response.overdamping.is_overdamped(), "{:?}", r.response.overdamping);
    assert!(r.converged && r.rise_time_error.unwrap() < 5e-3, "T90 = {:?}", r.rise_time);
    assert_eq!(search.trials[0], (1.0, false));
    let failing = search.trials.iter().filter(|t| !t.1).map(|t| t.0).fold(0.0, f64::max);
    assert!(failing < used && used / failing < 1.03, "bracket to 2 %: {:?}", search.trials);
    assert!(r.simulations > plain.simulations, "every trial's simulations are counted");
    // Without the setting, nothing changes.
    assert!(plain.lower_limit.is_none());
}
