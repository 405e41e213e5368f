//! Eq. (36)'s own reading of the rise. Eq. (36) writes the response as
//! `δx(t) = δ_d (1 − e^{−τt})`, with `δ_d` the end displacement of eq. (33), which is measured from
//! the unloaded shape `θ0` (where `X_{N+1} = L_x`). The step response ([`crate::response`])
//! measures `Δ(t)` from the rest state `θ1`, where the motion starts, and its `T_90` is the first
//! `t` with `Δ(t) = 0.9 Δ∞`. This reading: the first `t` with
//! `X_{N+1}(t) − L_x = f (X_{N+1}(θ2) − L_x)` (`f` the rise fraction, 0.9); zero when the rest
//! state is already past it. The two agree when the passive load does not move the end
//! (`θ1 = θ0`).

use crate::eom::Dynamics;
use crate::integrator::{first_event, EventFunction, Options, Trajectory};
use crate::response::StaticEnds;
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
/// chain `d` between `ends`, for the rise fraction `fraction`.
pub(crate) fn rise_from_unloaded(
    d: &Dynamics,
    ends: &StaticEnds,
    options: &Options,
    fraction: f64,
    traj: &Trajectory,
) -> RiseFromUnloaded {
    let n = d.n_links();
    let length_x = ends.x1 - ends.passive_displacement;
    let delta_d = ends.x2 - length_x;
    let target = length_x + fraction * delta_d;
    let travel = target - ends.x1;
    let threshold_ratio = travel / (fraction * (ends.x2 - ends.x1));
    let rise_time = if travel * (ends.x2 - ends.x1) <= 0.0 {
        // The rest state is already at or past the threshold.
        Some(0.0)
    } else {
        let ode = SpineOde { dynamics: d, parameters: Parameters::None };
        let g = |y: &[f64]| d.end_x(&y[..n]) - target;
        let grad = |y: &[f64]| d.end_x_state_gradient(y);
        let lipschitz = d.end_x_lipschitz();
        let function = EventFunction::new(&g, &grad).with_lipschitz(&lipschitz);
        first_event(&ode, options, traj, 0.0, &function).map(|e| e.t)
    };
    let tau = rise_time.filter(|&t| t > 0.0).map(|t| -(1.0 - fraction).ln() / t);
    RiseFromUnloaded { delta_d, threshold_ratio, rise_time, tau }
}
