//! The end's X displacement `X_{N+1} − L_x` on a trajectory of one ODE: its value and the first
//! time it reaches a level (an event on the steps). Shared by the periodic response's reach,
//! return and target times and by eq. (36)'s reading of the step response's rise.

use crate::eom::Dynamics;
use crate::integrator::{first_event, EventFunction, Options, Trajectory};
use crate::system::SpineOde;

pub(crate) struct EndX<'a> {
    pub d: &'a Dynamics,
    pub ode: SpineOde<'a>,
    options: &'a Options,
    pub length_x: f64,
    lipschitz: Vec<f64>,
}

impl<'a> EndX<'a> {
    /// The end of `ode`'s chain with `L_x = length_x`, its events located with `options`.
    pub fn new(ode: SpineOde<'a>, options: &'a Options, length_x: f64) -> Self {
        let d = ode.dynamics;
        Self { d, ode, options, length_x, lipschitz: d.end_x_lipschitz() }
    }

    /// `X_{N+1} − L_x` at the state `y`, m.
    pub fn at(&self, y: &[f64]) -> f64 {
        self.d.end_x(&y[..self.d.n_links()]) - self.length_x
    }

    /// The first time after `after` that the end's X displacement reaches `level`.
    pub fn crossing(&self, traj: &Trajectory, after: f64, level: f64) -> Option<f64> {
        let g = |y: &[f64]| self.at(y) - level;
        let grad = |y: &[f64]| self.d.end_x_state_gradient(y);
        let event = EventFunction::new(&g, &grad).with_lipschitz(&self.lipschitz);
        first_event(&self.ode, self.options, traj, after, &event).map(|e| e.t)
    }
}
