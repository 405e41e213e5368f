//! Issue 18, item 4: at the integrator's default tolerances, the quantities the paper designs with
//! (T_90 of a step response, eq. (35); the reach and return times of a pulse train, eq. (37)) are
//! within 1e-6 relative of a run at tolerances a hundred times tighter (whose own error is below 1e-8).

use spine_dynamics::fixtures::arch_problem;
use spine_dynamics::{periodic_response, step_response, Forcing, Options, PeriodicSettings, StepSettings};
use spine_dynamics::{DEFAULT_ATOL, DEFAULT_RTOL};

fn tight() -> Options {
    Options { rtol: 1e-2 * DEFAULT_RTOL, atol: 1e-2 * DEFAULT_ATOL, ..Options::default() }
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn default_tolerances_give_the_rise_time_to_one_part_in_a_million() {
    for (n, damping) in [(5, 50.0), (10, 50.0)] {
        let p = arch_problem(n, damping);
        let default = StepSettings { t_end: 2.0, ..StepSettings::default() };
        let reference = StepSettings { integrator: tight(), ..default.clone() };
        let t90 = step_response(&p, &default, false).unwrap().rise_time.unwrap();
        let t90_ref = step_response(&p, &reference, false).unwrap().rise_time.unwrap();
        assert!(relative(t90, t90_ref) <= 1e-6, "N = {n}: T_90 {t90} vs {t90_ref} ({:.1e})", relative(t90, t90_ref));
    }
}

#[test]
fn default_tolerances_give_the_pulse_reach_and_return_times_to_one_part_in_a_million() {
    let p = arch_problem(7, 50.0);
    let forcing = Forcing::PulseTrain { period: 1.0, duty: 0.5, delay: 0.0 };
    let default = PeriodicSettings::default();
    let reference = PeriodicSettings { integrator: tight(), ..default.clone() };
    let a = periodic_response(&p, forcing.clone(), None, &default).unwrap();
    let b = periodic_response(&p, forcing, None, &reference).unwrap();
    for (what, x, y) in [("reach", a.reach_time, b.reach_time), ("return", a.return_time, b.return_time)] {
        let (x, y) = (x.unwrap(), y.unwrap());
        assert!(relative(x, y) <= 1e-6, "{what} time {x} vs {y} ({:.1e})", relative(x, y));
    }
}
