//! Eq. (36)'s first-order model of the step response, fitted to a run ([`fit_first_order`]), and
//! its own reading of the rise. Eq. (36) writes the response as `δx(t) = δ_d (1 − e^{−τt})`,
//! with `δ_d` the end displacement of eq. (33), which is measured from the unloaded shape `θ0`
//! (where `X_{N+1} = L_x`). The step response ([`crate::response`]) measures `Δ(t)` from the rest
//! state `θ1`, where the motion starts, and its `T_90` is the first `t` with `Δ(t) = 0.9 Δ∞`.
//! This reading: the first `t` with `X_{N+1}(t) − L_x = f (X_{N+1}(θ2) − L_x)` (`f` the rise
//! fraction, 0.9); zero when the rest state is already past it. The two agree when the passive
//! load does not move the end (`θ1 = θ0`).

use crate::end_x::EndX;
use crate::eom::Dynamics;
use crate::integrator::{Options, Trajectory};
use crate::system::{Parameters, SpineOde};
use serde::Serialize;

/// The rise of the end displacement measured from `θ0`, as eq. (36) measures `δ_d`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RiseFromUnloaded {
    /// `X_{N+1}(θ2) − L_x`, m: the loaded state's `δ_d`.
    pub delta_d: f64,
    /// The travel from `θ1` this reading asks for over the rest-state reading's `f Δ∞`: above 1
    /// where the passive load moves the end away from `θ2`, below 1 where it moves it ahead.
    pub threshold_ratio: f64,
    /// First `t` with `X_{N+1}(t) − L_x = f δ_d`, s (`None` when not reached in the run).
    pub rise_time: Option<f64>,
    /// `−ln(1 − f) / rise_time`, 1/s (`None` at a zero or missing rise time).
    pub tau: Option<f64>,
}

/// The reading on the step response `traj` (from rest at `θ1`, integrated with `options`) of the
/// chain `d`, whose end is at `x1 = X_{N+1}(θ1)` at rest and settles at `x2 = X_{N+1}(θ2)`, with
/// `L_x = length_x`, for the rise fraction `fraction`.
pub(crate) fn rise_from_unloaded(
    d: &Dynamics,
    (x1, x2, length_x): (f64, f64, f64),
    options: &Options,
    fraction: f64,
    traj: &Trajectory,
) -> RiseFromUnloaded {
    let delta_d = x2 - length_x;
    let travel = length_x + fraction * delta_d - x1;
    let threshold_ratio = travel / (fraction * (x2 - x1));
    let rise_time = if travel * (x2 - x1) <= 0.0 {
        // The rest state is already at or past the threshold.
        Some(0.0)
    } else {
        let end = EndX::new(SpineOde { dynamics: d, parameters: Parameters::None }, options, length_x);
        end.crossing(traj, 0.0, fraction * delta_d)
    };
    let tau = rise_time.filter(|&t| t > 0.0).map(|t| -(1.0 - fraction).ln() / t);
    RiseFromUnloaded { delta_d, threshold_ratio, rise_time, tau }
}

/// The first-order model `Δ∞ (1 − e^{−τ t})` fitted to the samples by least squares in `τ`.
#[derive(Clone, Debug, Serialize)]
pub struct FirstOrderFit {
    /// Fitted rate `τ`, 1/s.
    pub tau: f64,
    /// RMS and largest residual of the fit, as fractions of `|Δ∞|`.
    pub rms_error: f64,
    pub max_error: f64,
}

/// Least-squares `τ` for `Δ(t) ≈ Δ∞ (1 − e^{−τ t})`: a log-spaced scan then golden-section refinement.
pub fn fit_first_order(times: &[f64], delta: &[f64], delta_inf: f64) -> FirstOrderFit {
    let t_max = times.iter().cloned().fold(0.0, f64::max);
    let cost = |ln_tau: f64| -> f64 {
        let tau = ln_tau.exp();
        times.iter().zip(delta).map(|(&t, &d)| (d - delta_inf * (1.0 - (-tau * t).exp())).powi(2)).sum()
    };
    let (lo, hi) = ((1e-3 / t_max).ln(), (1e5 / t_max).ln());
    let grid = 400;
    // Invariant: the grid holds `grid + 1 = 401` points.
    let best = (0..=grid)
        .map(|k| lo + (hi - lo) * k as f64 / grid as f64)
        .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
        .expect("a non-empty grid");
    let step = (hi - lo) / grid as f64;
    let (mut a, mut b) = (best - step, best + step);
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..100 {
        let (c, d) = (b - phi * (b - a), a + phi * (b - a));
        if cost(c) < cost(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let tau = (0.5 * (a + b)).exp();
    let residuals: Vec<f64> = times
        .iter()
        .zip(delta)
        .map(|(&t, &d)| (d - delta_inf * (1.0 - (-tau * t).exp())).abs() / delta_inf.abs())
        .collect();
    let rms_error = (residuals.iter().map(|r| r * r).sum::<f64>() / residuals.len() as f64).sqrt();
    FirstOrderFit { tau, rms_error, max_error: residuals.iter().cloned().fold(0.0, f64::max) }
}
