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
