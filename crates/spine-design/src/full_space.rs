//! The simultaneous ("full-space") form of eq. (33): design and both equilibria are Ipopt's
//! variables, the equilibrium equations are constraints.
//!
//! Variables (`N` links, `n = 5N + 2`):
//!
//! | range | quantity | unit |
//! |---|---|---|
//! | `0..N` | `θ0` | rad |
//! | `N..2N+1` | `k = K / C_K` (eq. (34)) | N·m/rad ÷ C_K |
//! | `2N+1..3N+1`, `3N+1` | `θ1` or `u1 = θ1 − θ0`, `λ1` (passive equilibrium) | rad, N |
//! | `3N+2..4N+2`, `4N+2` | `θ2` or `u2 = θ2 − θ0`, `λ2` (passive + actuation) | rad, N |
//! | `4N+3..5N+2` | unloaded interior node heights `Y0_2..Y0_N` | m |
//!
//! Constraints (`m = 4N + 2`): the `N + 1` equilibrium equations at `θ1`, the same at `θ2`, the
//! `N` height steps `Y0_{j+1} − Y0_j − a_j tan θ0_j = 0` (with `Y0_1 = Y0_{N+1} = 0`, so they
//! contain `Φ(θ0) = 0`), the end displacement `X_{N+1}(θ2) = L_x + δ_d`, and the `N − 1` relative
//! angles `|θ0_i − θ0_{i+1}| ≤ π/6`. The node heights are lifted into variables so that every
//! row has O(1) entries except the three sums `Φ(θ1)`, `Φ(θ2)`, `X_{N+1}(θ2)`, which have O(N):
//! the Jacobian and the Hessian of the Lagrangian both have O(N) entries.
//!
//! The states are absolute angles or deflections from the unloaded shape ([`StateForm`]). The
//! springs act on `θ − θ0`, which formed from two angles of about 0.5 rad carries a round-off of
//! about 1e-16 rad; with `K` near 1e8 N·m/rad (the scaled family at N = 1000) that is 1e-8 N·m in
//! every joint residual and in the objective's gradient, and Ipopt could not go below it. With
//! deflections as variables it converges (docs/design.md, "Deflections as variables").

use crate::assembly::{group, AnyGroup, Assembled, Group, Placed, Row};
pub use crate::layout::{Layout, LoadState, StateForm};

use crate::numbers::{Criterion, Numbers, Resultants};
use crate::problem::DesignProblem;
use spine_model::local::{
    joint_slot, DeflectionJointResidual, Difference, HeightStep, JointResidual, LinkRise, LinkRun,
};
use spine_model::residual::slot;
use spine_model::{Design, State};

/// Builds the elements of eq. (33) in the full space, with the states in `states`' form.
pub fn assemble(problem: &DesignProblem, states: StateForm) -> Assembled {
    Assembled::new(groups(&Numbers::of(problem), states))
}

/// The groups of elements of eq. (33) with their constants taken from `numbers`: the problem's
/// numbers, or their rates along a parameter (each element's constants are copies of the numbers,
/// so the same map gives the elements' constant rates).
pub(crate) fn groups(numbers: &Numbers<f64>, states: StateForm) -> Vec<Box<dyn AnyGroup + Send + Sync>> {
    let n = numbers.spans.len();
    let probe = match &numbers.criterion {
        Criterion::Compliance { probe } => Some(probe),
        _ => None,
    };
    let layout = Layout { n, states, probe: probe.is_some(), budget: numbers.strain_energy_max.is_some() };
    let spans = &numbers.spans;
    let deflection = states == StateForm::Deflection;
    let mut load_states = vec![(LoadState::Passive, &numbers.passive), (LoadState::Loaded, &numbers.loaded)];
    load_states.extend(probe.map(|p| (LoadState::Probe, p)));
    let rises = load_states
        .iter()
        .flat_map(|(state, _)| {
            (0..n).map(move |i| Placed {
                element: LinkRise { span: spans[i], deflection },
                vars: [Some(layout.state_angle(*state, i)), Some(layout.theta0(i))],
                row: Row::Constraint(layout.constraint_row(*state)),
            })
        })
        .collect();
    let runs = (0..n)
        .map(|i| Placed {
            element: LinkRun { span: spans[i], deflection },
            vars: [Some(layout.state_angle(LoadState::Loaded, i)), Some(layout.theta0(i))],
            row: Row::Constraint(layout.end_row()),
        })
        .collect();
    let heights = (0..n)
        .map(|j| Placed {
            element: HeightStep { span: spans[j] },
            vars: [layout.height(j + 1), layout.height(j), Some(layout.theta0(j))],
            row: Row::Constraint(layout.height_row(j)),
        })
        .collect();
    let relatives = (0..n.saturating_sub(1))
        .map(|i| Placed {
            element: Difference,
            vars: [Some(layout.theta0(i)), Some(layout.theta0(i + 1))],
            row: Row::Constraint(layout.relative_row(i)),
        })
        .collect();
    let mut groups = vec![
        joints(&layout, numbers, &load_states),
        Box::new(Group::new(rises)),
        Box::new(Group::new(runs)),
        crate::criterion::objective(&layout, numbers),
        Box::new(Group::new(heights)),
        Box::new(Group::new(relatives)),
    ];
    if let Some(row) = layout.budget_row_if_any() {
        // The budget `U(θ1) ≤ U_max`: the paper's objective's elements on a row of their own (a
        // problem and its rates have the same budget, so the same groups).
        groups.push(crate::criterion::springs(&layout, numbers.stiffness_scale, Row::Constraint(row)));
    }
    groups
}

/// Joint row `i` of one load state: what both forms of its element need.
struct JointRow {
    state: LoadState,
    i: usize,
    prev: Option<usize>,
    next: Option<usize>,
    span: f64,
    vertical: f64,
    axial: f64,
}

/// The joint rows of both load states (`N` per state): eq. (5)'s residual on absolute angles or
/// on deflections. The two forms differ only in their element and its slots.
fn joints(
    layout: &Layout,
    numbers: &Numbers<f64>,
    load_states: &[(LoadState, &Resultants<f64>)],
) -> Box<dyn AnyGroup + Send + Sync> {
    let n = layout.n;
    let spans = &numbers.spans;
    let stiffness_scale = numbers.stiffness_scale;
    let rows = load_states.iter().flat_map(|(state, loads)| {
        (0..n).map(move |i| JointRow {
            state: *state,
            i,
            prev: (i > 0).then(|| i - 1),
            next: (i + 1 < n).then_some(i + 1),
            span: spans[i],
            vertical: loads.vertical[i],
            axial: loads.axial[i],
        })
    });
    let angle = |r: &JointRow, link: Option<usize>| link.map(|k| layout.state_angle(r.state, k));
    let place = |r: &JointRow| Row::Constraint(layout.equilibrium_row(r.state, r.i));
    match layout.states {
        StateForm::Absolute => group(rows.map(|r| {
            let mut vars = [None; slot::COUNT];
            vars[slot::THETA_PREV] = angle(&r, r.prev);
            vars[slot::THETA] = angle(&r, Some(r.i));
            vars[slot::THETA_NEXT] = angle(&r, r.next);
            vars[slot::LAMBDA] = Some(layout.lambda(r.state));
            vars[slot::THETA0_PREV] = r.prev.map(|p| layout.theta0(p));
            vars[slot::THETA0] = Some(layout.theta0(r.i));
            vars[slot::THETA0_NEXT] = r.next.map(|q| layout.theta0(q));
            vars[slot::STIFFNESS_LEFT] = Some(layout.stiffness(r.i));
            vars[slot::STIFFNESS_RIGHT] = Some(layout.stiffness(r.i + 1));
            let element = JointResidual { span: r.span, vertical: r.vertical, axial: r.axial, stiffness_scale };
            Placed { element, vars, row: place(&r) }
        })),
        StateForm::Deflection => group(rows.map(|r| {
            let mut vars = [None; joint_slot::COUNT];
            vars[joint_slot::U_PREV] = angle(&r, r.prev);
            vars[joint_slot::U] = angle(&r, Some(r.i));
            vars[joint_slot::U_NEXT] = angle(&r, r.next);
            vars[joint_slot::LAMBDA] = Some(layout.lambda(r.state));
            vars[joint_slot::THETA0] = Some(layout.theta0(r.i));
            vars[joint_slot::STIFFNESS_LEFT] = Some(layout.stiffness(r.i));
            vars[joint_slot::STIFFNESS_RIGHT] = Some(layout.stiffness(r.i + 1));
            let element =
                DeflectionJointResidual { span: r.span, vertical: r.vertical, axial: r.axial, stiffness_scale };
            Placed { element, vars, row: place(&r) }
        })),
    }
}

/// Eq. (33) in the full space as an Ipopt problem, with exact sparse first and second
/// derivatives from the elements.
pub struct FullSpaceNlp<'a> {
    pub problem: &'a DesignProblem,
    pub layout: Layout,
    pub assembled: Assembled,
    pub start: Vec<f64>,
    /// Called once per Ipopt iteration (progress, logging); return `false` to stop.
    pub on_iteration: Option<&'a mut dyn FnMut(&spine_ipopt::IterationInfo) -> bool>,
    /// Start multipliers, used with Ipopt's `warm_start_init_point = yes` (mesh sequencing).
    pub multipliers: Option<Multipliers>,
    /// `x`, `f` and `g` at the last point: Ipopt asks for both at the same point.
    values: Option<(Vec<f64>, f64, Vec<f64>)>,
    /// `x`, `∇f` and the Jacobian values at the last point: Ipopt asks for both at the same point.
    first_derivatives: Option<(Vec<f64>, Vec<f64>, Vec<f64>)>,
}

impl<'a> FullSpaceNlp<'a> {
    /// The NLP from a start design and start states (for example equilibria solved at the start
    /// design); node heights start at the design's own heights.
    pub fn new(problem: &'a DesignProblem, states: StateForm, start: &Design, passive: &State, loaded: &State) -> Self {
        let layout = Layout::of(problem, states);
        let heights = problem.node_heights(&start.theta0);
        let mut x = layout.pack(start, problem.stiffness_scale, passive, loaded, &heights);
        if layout.probe {
            // θ3 from the start design by continuation, else the unloaded shape (Ipopt solves it).
            let continuation = spine_solve::ContinuationOptions::default();
            let probe = problem.probe_state(start, &continuation).unwrap_or_else(|| State::unloaded(start));
            layout.pack_probe(&mut x, &probe);
        }
        let start = x;
        FullSpaceNlp {
            problem,
            layout,
            assembled: assemble(problem, states),
            start,
            on_iteration: None,
            multipliers: None,
            values: None,
            first_derivatives: None,
        }
    }
}

impl FullSpaceNlp<'_> {
    /// `f` and `g` at `x`, computed once per point (cached by `x`, like the first derivatives).
    fn values_at(&mut self, x: &[f64]) -> (f64, &[f64]) {
        if self.values.as_ref().is_none_or(|(at, _, _)| at.as_slice() != x) {
            let mut g = vec![0.0; self.layout.num_constraints()];
            let f = self.assembled.values(x, &mut g);
            self.values = Some((x.to_vec(), f, g));
        }
        // Invariant: the cache was filled for `x` just above.
        let (_, f, g) = self.values.as_ref().expect("computed above");
        (*f, g)
    }

    /// `∇f` and the Jacobian at `x`, computed once per point (the cache is keyed by `x` itself,
    /// not by Ipopt's `new_x` flag, which refers to the last call of any evaluation).
    fn first_derivatives_at(&mut self, x: &[f64]) -> (&[f64], &[f64]) {
        if self.first_derivatives.as_ref().is_none_or(|(at, _, _)| at.as_slice() != x) {
            let mut gradient = vec![0.0; x.len()];
            let mut jacobian = vec![0.0; self.assembled.patterns.jacobian.len()];
            self.assembled.first_derivatives(x, &mut gradient, &mut jacobian);
            self.first_derivatives = Some((x.to_vec(), gradient, jacobian));
        }
        // Invariant: the cache was filled for `x` just above.
        let (_, g, j) = self.first_derivatives.as_ref().expect("computed above");
        (g, j)
    }
}

impl spine_ipopt::Problem for FullSpaceNlp<'_> {
    fn num_variables(&self) -> usize {
        self.layout.num_variables()
    }
    fn num_constraints(&self) -> usize {
        self.layout.num_constraints()
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let bounds = Numbers::of(self.problem).full_space_bounds(&self.layout);
        lower.copy_from_slice(&bounds.lower);
        upper.copy_from_slice(&bounds.upper);
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        let bounds = Numbers::of(self.problem).full_space_bounds(&self.layout);
        lower.copy_from_slice(&bounds.row_lower);
        upper.copy_from_slice(&bounds.row_upper);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.start);
    }
    fn initial_multipliers(&self, z_lower: &mut [f64], z_upper: &mut [f64], lambda: &mut [f64]) -> bool {
        let Some(m) = &self.multipliers else { return false };
        z_lower.copy_from_slice(&m.z_lower);
        z_upper.copy_from_slice(&m.z_upper);
        lambda.copy_from_slice(&m.constraints);
        true
    }
    fn objective(&mut self, x: &[f64], _new_x: bool) -> Option<f64> {
        let (f, _) = self.values_at(x);
        f.is_finite().then_some(f)
    }
    fn objective_gradient(&mut self, x: &[f64], _new_x: bool, gradient: &mut [f64]) -> bool {
        let (grad, _) = self.first_derivatives_at(x);
        gradient.copy_from_slice(grad);
        gradient.iter().all(|v| v.is_finite())
    }
    fn constraints(&mut self, x: &[f64], _new_x: bool, g: &mut [f64]) -> bool {
        g.copy_from_slice(self.values_at(x).1);
        g.iter().all(|v| v.is_finite())
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        self.assembled.patterns.jacobian.clone()
    }
    fn jacobian_values(&mut self, x: &[f64], _new_x: bool, values: &mut [f64]) -> bool {
        let (_, jac) = self.first_derivatives_at(x);
        values.copy_from_slice(jac);
        values.iter().all(|v| v.is_finite())
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        Some(self.assembled.patterns.hessian.clone())
    }
    fn hessian_values(
        &mut self,
        x: &[f64],
        _new_x: bool,
        sigma: f64,
        lambda: &[f64],
        _new_lambda: bool,
        values: &mut [f64],
    ) -> bool {
        self.assembled.hessian(x, sigma, lambda, values);
        values.iter().all(|v| v.is_finite())
    }
    fn intermediate(&mut self, info: &spine_ipopt::IterationInfo) -> bool {
        self.on_iteration.as_mut().is_none_or(|f| f(info))
    }
}

/// Multipliers of a full-space solution (Ipopt's sign convention), in the layout's order.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Multipliers {
    pub constraints: Vec<f64>,
    pub z_lower: Vec<f64>,
    pub z_upper: Vec<f64>,
}
