//! Events on the steps themselves: a root of `g(y(t))` located on the dense output moved onto the
//! solution of an integration step.
//!
//! Radau IIA's dense output (the collocation polynomial) is of order 3, its step ends of order 5:
//! at loose tolerances a root of the interpolant is off by its interpolation error divided by the
//! slope of `g`, which can be a hundred times the error of the solution at the step points (step
//! case, N = 100, rtol 1e-6: `T_90` off by 1.4e-7 s on the interpolant while `Δ(1 s)` is within
//! 6e-10 of the reference). [`first_event`] takes Newton steps on the event time with `y(t)`
//! from a step that ends at `t`.

use super::{integrate, Event, EventFunction, Extras, OdeSystem, Options, Outcome, Trajectory};

/// Most Newton steps on the event time (two reach round-off from a dense root).
const NEWTON_STEPS: usize = 3;

/// The first time after `after` where the event function `g(y(t))` changes sign, on the
/// integration steps.
///
/// [`Trajectory::first_root`] locates it on the dense output of `traj` (a run of `sys` with
/// `opts`). Then Newton on `g(y(t)) = 0` moves it onto the steps: each `y(t)` integrated (the
/// run's options, a first step that covers the way) from the accepted step point before the event,
/// `ġ = ∇g · f`. The event's `y` is the state at the last Newton iterate, `dt/dp = −(∇g · S) / ġ`
/// with `S` the dense output's at the refined time. The dense root stays when an iterate leaves
/// the event's step or an integration does not complete.
pub fn first_event(
    sys: &dyn OdeSystem,
    opts: &Options,
    traj: &Trajectory,
    after: f64,
    function: &EventFunction<'_>,
) -> Option<Event> {
    let (g, grad) = (function.g, function.grad);
    let event = traj.first_root(after, function)?;
    let Some(step) = traj.interval_at(event.t).filter(|iv| iv.t0 < event.t) else {
        return Some(event);
    };
    let piece = step.piece();
    let mut t = event.t;
    let mut last: Option<(Vec<f64>, Vec<f64>, f64)> = None;
    for _ in 0..NEWTON_STEPS {
        let options = Options { initial_step: Some(t - step.t0), ..opts.clone() };
        let run = integrate(sys, step.t0, &step.y0, t, &options, Extras::default());
        if run.outcome != Outcome::Completed {
            return Some(event);
        }
        let at = run.end().to_vec();
        let dg = grad(&at);
        let mut f = vec![0.0; at.len()];
        sys.rhs_into(t, piece, &at, &mut f);
        let rate: f64 = dg.iter().zip(f).map(|(a, b)| a * b).sum();
        let next = t - g(&at) / rate;
        last = Some((at, dg, rate));
        if !(next > step.t0 && next <= step.t1) {
            return Some(event);
        }
        let moved = (next - t).abs();
        t = next;
        if moved <= 4.0 * f64::EPSILON * t.abs() {
            break;
        }
    }
    let Some((y, dg, rate)) = last else { return Some(event) };
    let t_sensitivity = step
        .sensitivity(t)
        .map(|s| (0..s.ncols()).map(|p| -(0..s.nrows()).map(|i| dg[i] * s[(i, p)]).sum::<f64>() / rate).collect());
    Some(Event { t, y, t_sensitivity })
}
