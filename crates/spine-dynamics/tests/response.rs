//! The step response (the damping design of eq. (35) is tested in spine-dynamic-design).

use spine_dynamics::fixtures::arch_problem as problem;
use spine_dynamics::response::{fit_first_order, rise_time};
use spine_dynamics::{step_response, Forcing, StepSettings};

#[test]
fn step_response_settles_in_the_static_loaded_equilibrium_with_no_drift() {
    let settings = StepSettings { t_end: 3.0, ..Default::default() };
    let r = step_response(&problem(6, 30.0), &settings, false).unwrap();
    assert!(r.settled, "settle error {:.3e}", r.settle_error);
    assert!(r.final_state_gap < 1e-4, "θ(t_end) − θ2 = {:.3e} rad", r.final_state_gap);
    assert!(r.delta_inf < 0.0, "the axial push shortens the spine");
    assert!(r.drift.max_constraint <= 1e-9 && r.drift.max_constraint_rate <= 1e-9, "{:?}", r.drift);
    assert!(r.drift.max_constraint_dense <= 1e-9, "{:?}", r.drift);
    let t90 = r.rise_time.expect("rises");
    // T_90 is where the sampled response crosses 0.9 Δ∞.
    let before = r.samples.iter().rfind(|s| s.t < t90).unwrap();
    let after = r.samples.iter().find(|s| s.t > t90).unwrap();
    assert!(before.delta > 0.9 * r.delta_inf && after.delta <= 0.9 * r.delta_inf);
    assert!((r.tau_from_rise_time.unwrap() - 10f64.ln() / t90).abs() < 1e-12, "eq. (36) corrected: τ = ln 10 / T_90");
    assert!(r.fit.tau > 0.0 && r.fit.rms_error < 0.1);
}

/// `T_90` on the integration steps converges with the tolerance, where the root of the dense output
/// stalls at the interpolant's error: the scaled step case at N = 10 and 50, against rtol 1e-10.
#[test]
fn rise_time_on_the_steps_converges_with_the_tolerance() {
    use spine_dynamics::fixtures::peer_step_problem;
    use spine_dynamics::integrator::{integrate, EventFunction, Extras};
    use spine_dynamics::{Parameters, SpineOde};
    for n in [10, 50] {
        let p = peer_step_problem(n);
        let ends = p.static_ends(&Default::default()).unwrap();
        let d = p.dynamics(Forcing::Step);
        let at = |rtol: f64| {
            let mut settings = StepSettings { t_end: 1.0, ..Default::default() };
            (settings.integrator.rtol, settings.integrator.atol) = (rtol, rtol / 100.0);
            let (t90, _) = rise_time(&d, &ends, &settings, false);
            // The same run's root on the dense output alone.
            let ode = SpineOde { dynamics: &d, parameters: Parameters::None };
            let traj = integrate(&ode, 0.0, &ends.rest_state(), 1.0, &settings.integrator, Extras::default());
            let target = ends.x1 + 0.9 * (ends.x2 - ends.x1);
            let g = |y: &[f64]| d.end_x(&y[..n]) - target;
            let grad = |y: &[f64]| d.end_x_state_gradient(y);
            let dense = traj.first_root(0.0, &EventFunction::new(&g, &grad)).unwrap().t;
            (t90.unwrap(), dense)
        };
        let (reference, _) = at(1e-10);
        let errors: Vec<(f64, f64)> = [1e-5, 1e-6, 1e-7]
            .iter()
            .map(|&r| at(r))
            .map(|(s, d)| ((s - reference).abs(), (d - reference).abs()))
            .collect();
        for (k, &(on_steps, dense)) in errors.iter().enumerate() {
            let rtol = 1e-5 / 10f64.powi(k as i32);
            assert!(on_steps <= 3e-3 * rtol, "N = {n}, rtol {rtol:e}: T_90 off by {on_steps:.1e} s");
            assert!(on_steps <= dense, "N = {n}, rtol {rtol:e}: {on_steps:.1e} s on the steps, {dense:.1e} s dense");
        }
        // At rtol 1e-6 the dense root is at least ten times further off (its error does not
        // follow the tolerance).
        assert!(10.0 * errors[1].0 <= errors[1].1, "N = {n}: {:?}", errors[1]);
    }
}

#[test]
fn first_order_fit_recovers_an_exact_exponential() {
    let times: Vec<f64> = (0..500).map(|k| k as f64 * 0.002).collect();
    let delta: Vec<f64> = times.iter().map(|t| -0.03 * (1.0 - (-11.5 * t).exp())).collect();
    let fit = fit_first_order(&times, &delta, -0.03);
    assert!((fit.tau - 11.5).abs() < 1e-6, "τ = {}", fit.tau);
    assert!(fit.rms_error < 1e-9);
}

#[test]
fn rise_time_gradient_equals_central_differences() {
    let p = problem(4, 20.0);
    let ends = p.static_ends(&Default::default()).unwrap();
    let d = p.dynamics(Forcing::Step);
    let mut settings = StepSettings::default();
    settings.integrator.rtol = 1e-10;
    settings.integrator.atol = 1e-12;
    let (t90, grad) = rise_time(&d, &ends, &settings, true);
    let (t90, grad) = (t90.unwrap(), grad.unwrap());
    for k in 0..5 {
        let fd = spine_model::finite_difference::central(d.damping[k], 1e-3, |c| {
            let mut dk = d.clone();
            dk.damping[k] = c;
            rise_time(&dk, &ends, &settings, false).0.unwrap()
        });
        assert!(
            (fd - grad[k]).abs() <= 1e-5 * grad.iter().map(|g| g.abs()).fold(0.0, f64::max),
            "dT90/dC{k}: {} vs FD {fd}",
            grad[k]
        );
    }
    assert!(grad.iter().all(|g| *g > 0.0), "more damping, slower rise: {grad:?} (T90 = {t90})");
}

/// Eq. (36)'s reading of the rise, the end displacement measured from θ0: with a passive load it
/// is the first crossing of `f δ_d` by `X(t) − L_x` on the samples; without one (θ1 = θ0) it is the
/// rest-state `T_90`.
#[test]
fn the_rise_from_the_unloaded_shape_is_eq_36s_reading() {
    let settings = StepSettings { t_end: 1.0, ..Default::default() };
    let r = step_response(&problem(6, 30.0), &settings, false).unwrap();
    let u = &r.from_unloaded;
    assert!((u.delta_d - r.ends.loaded_displacement).abs() < 1e-15);
    let target = 0.9 * u.delta_d;
    let t = u.rise_time.expect("reached");
    assert!(r.ends.passive_displacement != 0.0 && (u.threshold_ratio - 1.0).abs() > 1e-3, "{}", u.threshold_ratio);
    let before = r.samples.iter().rfind(|s| s.t < t).unwrap();
    let after = r.samples.iter().find(|s| s.t > t).unwrap();
    assert!(before.end_displacement > target && after.end_displacement <= target, "{before:?} {after:?} {target}");
    assert!((u.tau.unwrap() - 10f64.ln() / t).abs() < 1e-12);
    // The travel it asks for from θ1, against the rest-state reading's 0.9 Δ∞.
    let travel = 0.9 * u.delta_d - r.ends.passive_displacement;
    assert!((u.threshold_ratio - travel / (0.9 * r.delta_inf)).abs() < 1e-12);
    // No passive load and no weight: θ1 = θ0, and the two readings are one.
    let mut p = problem(6, 30.0);
    p.structure.passive = spine_model::NodalLoads::zero(6);
    p.structure.chain.gravity = 0.0;
    let r = step_response(&p, &settings, false).unwrap();
    assert!(r.ends.passive_displacement.abs() < 1e-14, "{}", r.ends.passive_displacement);
    let (a, b) = (r.rise_time.unwrap(), r.from_unloaded.rise_time.unwrap());
    assert!((a - b).abs() <= 1e-9 * a, "{a} vs {b}");
    assert!((r.from_unloaded.threshold_ratio - 1.0).abs() < 1e-9);
}
