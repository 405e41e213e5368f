//! The last period's values of a fixed-horizon run and their spring gradients: by forward
//! sensitivities during the run, or by the discrete adjoint of the kept runs afterwards.

use crate::eom::Dynamics;
use crate::integrator::adjoint::{adjoint, Term};
use crate::integrator::Trajectory;
use crate::system::{Parameters, SpineOde};
use nalgebra::DMatrix;

/// `X_{N+1}(t) − L_x` at one time of the last simulated period (a local minimum, or the period's
/// end) with its gradient in the springs.
#[derive(Clone, Debug, PartialEq)]
pub struct EndValue {
    /// Absolute time, s, and the value, m.
    pub t: f64,
    pub value: f64,
    /// `d value / dK`, m per N·m/rad: `∇_y X · S(t)` (at an interior minimum `Ẋ = 0`, so the
    /// minimum's own shift in time does not enter, the envelope theorem; the period's end is a
    /// fixed time). Empty until [`LastPeriod::adjoint_gradients`] fills it when the run kept its
    /// steps for the adjoint.
    pub gradient: Vec<f64>,
}

/// How the springs' gradients of the last period's values are had (`S(0)`, `2N × (N + 1)`, is the
/// rates of the rest state `(θ1, 0)`).
#[derive(Clone, Debug)]
pub enum SpringGradients {
    /// Forward sensitivities from `S(0)` through every step (the reference path, and the one for
    /// TR-BDF2 runs).
    Forward(DMatrix<f64>),
    /// None during the run: every period's run is kept, and [`LastPeriod::adjoint_gradients`]
    /// gives the gradients of the values asked for by the discrete adjoint
    /// ([`crate::integrator::adjoint`]), at the cost of about one run per sweep whatever the
    /// number of springs.
    Adjoint,
}

/// The local minima of the last period, lowest first, and the value at the period's end, of a
/// fixed-horizon run (`simulate_periodic_springs`).
#[derive(Clone, Debug)]
pub struct LastPeriod {
    pub minima: Vec<EndValue>,
    pub end: EndValue,
    /// Every period's run, for the adjoint (empty with forward sensitivities).
    pub(super) runs: Vec<Trajectory>,
}

impl LastPeriod {
    /// Fills the spring gradients of `values` (taken from [`Self::minima`] and [`Self::end`]) by
    /// one adjoint sweep over the kept runs for the start sensitivities `s0`; `false` when the runs
    /// were not kept or are not Radau IIA runs.
    pub fn adjoint_gradients(&self, d: &Dynamics, values: &mut [&mut EndValue], s0: &DMatrix<f64>) -> bool {
        let ode = SpineOde { dynamics: d, parameters: Parameters::Springs };
        let outputs: Vec<Vec<Term>> = values
            .iter()
            .map(|v| {
                let run = self.runs.iter().find(|r| r.span().1 >= v.t).or(self.runs.last());
                let y = run.map_or_else(Vec::new, |r| r.value(v.t));
                vec![Term { t: v.t, weights: d.end_x_state_gradient(&y) }]
            })
            .collect();
        let runs: Vec<&Trajectory> = self.runs.iter().collect();
        let Some((gradients, _)) = (!runs.is_empty()).then(|| adjoint(&ode, &runs, &outputs)).flatten() else {
            return false;
        };
        for (v, g) in values.iter_mut().zip(gradients) {
            v.gradient = g.total(s0);
        }
        true
    }
}
