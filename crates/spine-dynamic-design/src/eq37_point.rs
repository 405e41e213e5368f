//! Eq. (37)'s functions at one design with their exact derivatives in the springs: the strain
//! energy `U(θ1(K); K)` and its gradient (direct method), and the two lowest local minima of the
//! end displacement over the last period with their gradients (the discrete adjoint of the
//! plain run, when asked for, or forward sensitivities). [`crate::periodic_gradient`] explains
//! the formulation.

use crate::periodic_settings::{PeriodicDesignSettings, Sensitivities};
use nalgebra::DMatrix;
use spine_dynamics::forcing::Forcing;
use spine_dynamics::periodic::{simulate_periodic_springs, EndValue, LastPeriod, PeriodicResponse, SpringGradients};
use spine_dynamics::response::{DynamicProblem, StaticEnds};
use spine_dynamics::Dynamics;
use spine_model::jacobian::{design_column_of_stiffness, design_jacobian, residual_and_state_jacobian};
use spine_model::State;
use spine_solve::linalg::BorderedLu;

/// One design with eq. (37)'s functions and their exact derivatives in `K` (the constraint's by
/// the discrete adjoint once [`Self::constraint_gradients`] asks for them).
#[derive(Clone, Debug)]
pub struct Eq37Point {
    /// `U(θ1)`, J, and `dU/dK`, J per N·m/rad.
    pub energy: f64,
    pub energy_gradient: Vec<f64>,
    /// The lowest local minimum of `X_{N+1} − L_x` over the last period and the next one (or the
    /// period's end), m, with their gradients in `K` (empty while [`Self::pending`]).
    pub minima: [EndValue; 2],
    pub response: PeriodicResponse,
    /// What the adjoint sweep needs until it has run: the equations of motion, the kept runs and
    /// `S(0)`.
    pending: Option<Box<(Dynamics, LastPeriod, DMatrix<f64>)>>,
}

impl Eq37Point {
    /// Whether the constraint gradients are still to be computed.
    pub fn pending(&self) -> bool {
        self.pending.is_some()
    }

    /// Fills the gradients of both minima if they are not there yet: one adjoint sweep for each,
    /// side by side on rayon's pool (two cores: about the time of one sweep; the same numbers
    /// whatever the pool's size); `false` when a sweep fails (singular Newton matrices). A failed
    /// point stays pending, so that it never passes for one with gradients.
    pub fn constraint_gradients(&mut self) -> bool {
        let Some(pending) = &self.pending else { return true };
        let (d, last, s0) = &**pending;
        let [first, second] = &mut self.minima;
        let sweep = |m: &mut EndValue| last.adjoint_gradients(d, &mut [m], s0);
        let (a, b) = rayon::join(|| sweep(first), || sweep(second));
        if a && b {
            self.pending = None;
        }
        a && b
    }
}

/// `dθ1/dK` (the rest state's sensitivities `S(0)`, `2N × (N + 1)`) and `dU/dK` from the
/// equilibrium `R(θ1, λ1; K) = 0`: one factorisation, a solve per spring (module docs).
fn rest_sensitivities(p: &DynamicProblem, ends: &StaticEnds) -> Option<(DMatrix<f64>, Vec<f64>)> {
    let spans = &p.structure.chain.spans;
    let stiffness = &p.design.stiffness;
    let n = spans.len();
    let loads = p.structure.passive_loads();
    let state = State { theta: ends.theta1.clone(), lambda: ends.lambda1 };
    // dθ1/dK: A [dθ; dλ] = −∂R/∂K_j, one solve per spring.
    let (_, a) = residual_and_state_jacobian(spans, &p.design, &loads, &state);
    let lu = BorderedLu::factor(&a).ok()?;
    let mut rhs = vec![vec![0.0; n + 1]; stiffness.len()];
    let first_spring = design_column_of_stiffness(n, 0);
    for &(r, c, v) in &design_jacobian(spans, &p.design, &loads, &state).entries {
        if let Some(j) = c.checked_sub(first_spring) {
            rhs[j][r] -= v;
        }
    }
    let mut s0 = DMatrix::zeros(2 * n, stiffness.len());
    let deflection: Vec<f64> = ends.theta1.iter().zip(&p.design.theta0).map(|(t, t0)| t - t0).collect();
    let moments = spine_dynamics::eom::joint_moments(stiffness, &deflection);
    let relative = |j: usize| {
        let at = |i: isize| if i < 0 || i as usize >= n { 0.0 } else { deflection[i as usize] };
        at(j as isize) - at(j as isize - 1)
    };
    let mut energy_gradient = vec![0.0; stiffness.len()];
    for (j, b) in rhs.iter().enumerate() {
        let dtheta = lu.solve(b);
        for i in 0..n {
            s0[(i, j)] = dtheta[i];
        }
        energy_gradient[j] = 0.5 * relative(j).powi(2) + (0..n).map(|i| moments[i] * dtheta[i]).sum::<f64>();
    }
    Some((s0, energy_gradient))
}

/// Eq. (37)'s objective and constraint functions at `stiffness` over `periods` forcing periods,
/// with the objective's gradient and, by `settings.gradient.sensitivities`, the constraint's
/// (forward) or what its adjoint needs ([`Eq37Point::constraint_gradients`]); `None` where the
/// design has no stable equilibria or its simulation fails.
pub fn eq37_values(
    problem: &DynamicProblem,
    forcing: &Forcing,
    stiffness: &[f64],
    delta_d: f64,
    settings: &PeriodicDesignSettings,
    periods: usize,
) -> Option<Eq37Point> {
    let p = problem.with_stiffness(stiffness);
    let ends = p.static_ends(&settings.response.continuation).ok()?;
    let (s0, energy_gradient) = rest_sensitivities(&p, &ends)?;
    let energy = spine_model::energy::strain_energy(&ends.theta1, &p.design.theta0, stiffness);
    let d = p.dynamics(forcing.clone());
    let adjoint = sensitivities_used(settings) == Sensitivities::Adjoint;
    let gradients = if adjoint { SpringGradients::Adjoint } else { SpringGradients::Forward(s0.clone()) };
    let length_x = p.structure.chain.length_x();
    let (response, last) =
        simulate_periodic_springs(&d, ends, length_x, Some(delta_d), &settings.response, gradients, periods);
    let mut last = last?;
    // One minimum in the period: the second constraint is the period's end (inactive).
    let second = if last.minima.len() > 1 { last.minima.swap_remove(1) } else { last.end.clone() };
    let first = last.minima.swap_remove(0);
    let pending = adjoint.then(|| Box::new((d, last, s0)));
    Some(Eq37Point { energy, energy_gradient, minima: [first, second], response, pending })
}

/// [`eq37_values`] with the constraint gradients computed.
pub fn eq37_point(
    problem: &DynamicProblem,
    forcing: &Forcing,
    stiffness: &[f64],
    delta_d: f64,
    settings: &PeriodicDesignSettings,
    periods: usize,
) -> Option<Eq37Point> {
    let mut point = eq37_values(problem, forcing, stiffness, delta_d, settings, periods)?;
    point.constraint_gradients().then_some(point)
}

/// The sensitivities a run uses: the adjoint needs Radau IIA's stored steps (module docs of
/// [`Sensitivities`]).
pub fn sensitivities_used(settings: &PeriodicDesignSettings) -> Sensitivities {
    settings.gradient.sensitivities.for_method(settings.response.integrator.method)
}
