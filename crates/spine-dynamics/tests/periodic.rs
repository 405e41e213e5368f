//! The periodic response (the design of eq. (37) is tested in spine-dynamic-design).

use spine_dynamics::{periodic_response, DynamicProblem, Forcing, PeriodicSettings};

fn problem(n: usize) -> DynamicProblem {
    spine_dynamics::fixtures::periodic_problem(n)
}

#[test]
fn slow_pulses_swing_between_the_two_static_states() {
    let forcing = Forcing::PulseTrain { period: 1.0, duty: 0.5, delay: 0.0 };
    let p = problem(4);
    let loaded = p.static_ends(&Default::default()).unwrap().loaded_displacement;
    let r = periodic_response(&p, forcing, Some(0.5 * loaded), &PeriodicSettings::default()).unwrap();
    assert!(r.settled, "period change {:.2e}", r.period_change);
    let (on, off) = (r.ends.loaded_displacement, r.ends.passive_displacement);
    assert!(
        (r.min_end_displacement - on).abs() < 1e-4 * on.abs(),
        "min {} vs X(θ2) − L_x = {on}",
        r.min_end_displacement
    );
    assert!(
        (r.max_end_displacement - off).abs() < 1e-3 * on.abs(),
        "max {} vs X(θ1) − L_x = {off}",
        r.max_end_displacement
    );
    let (reach, back) = (r.reach_time.unwrap(), r.return_time.unwrap());
    assert!(reach > 0.0 && reach < 0.5 && back > 0.0 && back < 0.5, "reach {reach} s, return {back} s");
    let hit = r.time_to_target.unwrap();
    assert!(hit > 0.0 && hit < reach, "half the loaded displacement is passed before 90 % of the swing ({hit} s)");
    assert!(r.drift.max_constraint < 1e-9 && r.drift.max_constraint_dense < 1e-9);
}

#[test]
fn sinusoidal_force_gives_a_settled_periodic_motion() {
    let forcing = Forcing::Sinusoid { angular_frequency: 20.0 };
    let r = periodic_response(&problem(3), forcing, None, &PeriodicSettings::default()).unwrap();
    assert!(r.settled);
    assert!(
        r.min_end_displacement < r.ends.passive_displacement
            && r.min_end_displacement > 1.5 * r.ends.loaded_displacement
    );
}
