//! The reduced-space ("nested") form of eq. (33), as the paper solves it: Ipopt sees only the
//! design; both equilibria are solved by continuation `θ0 → θ1 → θ2` at every new design, and the
//! gradients of `J` and of the end displacement come from the hand-derived adjoint
//! ([`crate::adjoint::adjoint_hand`]). The Hessian of the Lagrangian is either Ipopt's
//! limited-memory approximation or central differences of the exact adjoint gradients
//! ([`ReducedHessian`]): `2(2N + 1)` equilibrium re-solves (warm Newton from the current states)
//! per Hessian, a dense `(2N + 1)²/2` block, affordable up to a few hundred links.
//!
//! Variables (`n = 3N`): `θ0` (`0..N`), `k = K / C_K` (`N..2N+1`), interior node heights
//! `Y0_2..Y0_N` (`2N+1..3N`). Constraints (`m = 2N`): the `N` height steps (containing
//! `Φ(θ0) = 0`), the end displacement `X_{N+1}(θ2) = L_x + δ_d` (a dense row over `θ0`, `k`), and
//! the `N − 1` relative angles.
//!
//! A design whose continuation does not reach the full load (a fold, or a Newton failure) is an
//! evaluation error for Ipopt, which then shortens its step.

use crate::adjoint::{adjoint_hand, ReducedGradients};
use crate::assembly::{AnyGroup, Assembled, Group, Placed, Row};
use crate::numbers::Numbers;
use crate::problem::DesignProblem;
use spine_model::local::{Difference, HeightStep};
use spine_model::{Design, State};
use spine_solve::{solve_static, ContinuationOptions};

/// Index map of the reduced-space variables and constraints.
#[derive(Clone, Copy, Debug)]
pub struct ReducedLayout {
    pub n: usize,
}

impl ReducedLayout {
    pub fn height(&self, j: usize) -> Option<usize> {
        (j >= 1 && j < self.n).then(|| 2 * self.n + j)
    }
    pub fn num_variables(&self) -> usize {
        3 * self.n
    }
    pub fn height_row(&self, j: usize) -> usize {
        j
    }
    pub fn end_row(&self) -> usize {
        self.n
    }
    pub fn relative_row(&self, i: usize) -> usize {
        self.n + 1 + i
    }
    pub fn num_constraints(&self) -> usize {
        2 * self.n
    }
}

/// How the reduced space gets second derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ReducedHessian {
    /// Ipopt's L-BFGS approximation (`hessian_approximation = limited-memory`).
    LimitedMemory,
    /// Central differences of the adjoint gradients (step `1e-6 max(1, |x_k|)`), symmetrised.
    AdjointDifferences,
}

/// The equilibria and gradients at one design.
#[derive(Clone, Debug)]
pub struct Evaluation {
    pub x: Vec<f64>,
    pub passive: State,
    pub loaded: State,
    pub gradients: ReducedGradients,
}

/// Eq. (33) in the reduced space as an Ipopt problem.
pub struct ReducedSpaceNlp<'a> {
    pub problem: &'a DesignProblem,
    pub layout: ReducedLayout,
    pub continuation: ContinuationOptions,
    pub start: Vec<f64>,
    /// Equilibrium solves and adjoint gradients, one per distinct design Ipopt asked for.
    pub equilibrium_evaluations: usize,
    /// Designs at which the continuation failed (evaluation errors reported to Ipopt).
    pub failed_evaluations: usize,
    /// Called once per Ipopt iteration; return `false` to stop.
    pub on_iteration: Option<&'a mut dyn FnMut(&spine_ipopt::IterationInfo) -> bool>,
    pub hessian: ReducedHessian,
    linear: Assembled,
    last: Option<Evaluation>,
}

impl<'a> ReducedSpaceNlp<'a> {
    pub fn new(
        problem: &'a DesignProblem,
        start: &Design,
        continuation: ContinuationOptions,
        hessian: ReducedHessian,
    ) -> Self {
        let n = problem.n_links();
        let layout = ReducedLayout { n };
        let heights: Vec<Placed<HeightStep, 3>> = (0..n)
            .map(|j| Placed {
                element: HeightStep { span: problem.structure.chain.spans[j] },
                vars: [layout.height(j + 1), layout.height(j), Some(j)],
                row: Row::Constraint(layout.height_row(j)),
            })
            .collect();
        let relatives: Vec<Placed<Difference, 2>> = (0..n.saturating_sub(1))
            .map(|i| Placed {
                element: Difference,
                vars: [Some(i), Some(i + 1)],
                row: Row::Constraint(layout.relative_row(i)),
            })
            .collect();
        let groups: Vec<Box<dyn AnyGroup + Send + Sync>> =
            vec![Box::new(Group::new(heights)), Box::new(Group::new(relatives))];
        let mut x0 = vec![0.0; layout.num_variables()];
        x0[..n].copy_from_slice(&start.theta0);
        for j in 0..=n {
            x0[n + j] = start.stiffness[j] / problem.stiffness_scale;
        }
        let y = problem.node_heights(&start.theta0);
        for j in 1..n {
            x0[layout.height(j).unwrap()] = y[j];
        }
        ReducedSpaceNlp {
            problem,
            layout,
            continuation,
            start: x0,
            equilibrium_evaluations: 0,
            failed_evaluations: 0,
            on_iteration: None,
            hessian,
            linear: Assembled::new(groups),
            last: None,
        }
    }

    /// The design in physical units.
    pub fn design(&self, x: &[f64]) -> Design {
        let n = self.layout.n;
        Design {
            theta0: x[..n].to_vec(),
            stiffness: x[n..2 * n + 1].iter().map(|k| k * self.problem.stiffness_scale).collect(),
        }
    }

    /// Solves both equilibria and the adjoint gradients at `x` (cached by `x`).
    pub fn evaluate(&mut self, x: &[f64]) -> Option<&Evaluation> {
        if self.last.as_ref().is_none_or(|e| e.x.as_slice() != x) {
            self.last = None;
            self.equilibrium_evaluations += 1;
            let design = self.design(x);
            let solution = solve_static(&self.problem.static_problem(&design), &self.continuation);
            let reached =
                solution.passive.load_factor == 1.0 && solution.loaded.as_ref().is_some_and(|l| l.load_factor == 1.0);
            if !reached {
                self.failed_evaluations += 1;
                return None;
            }
            let passive = solution.passive.state;
            // Invariant: `reached` above holds only with a loaded equilibrium.
            let loaded = solution.loaded.expect("reached").state;
            let Ok(gradients) = adjoint_hand(self.problem, &design, &passive, &loaded) else {
                self.failed_evaluations += 1;
                return None;
            };
            self.last = Some(Evaluation { x: x.to_vec(), passive, loaded, gradients });
        }
        self.last.as_ref()
    }

    /// `σ ∇J + λ_end ∇X` in the optimiser's variables (`θ0`, `k`) at a design near the last
    /// evaluation, with both equilibria re-solved by Newton from the last states.
    fn weighted_gradient(&self, x: &[f64], sigma: f64, lambda_end: f64) -> Option<Vec<f64>> {
        let last = self.last.as_ref()?;
        let design = self.design(x);
        let (passive, loaded) =
            self.problem.equilibria_near(&design, &last.passive, &last.loaded, &self.continuation)?;
        let g = adjoint_hand(self.problem, &design, &passive, &loaded).ok()?;
        let weighted = g.energy_gradient.iter().zip(&g.end_x_gradient).map(|(j, x)| sigma * j + lambda_end * x);
        let mut out = vec![0.0; 2 * self.layout.n + 1];
        to_optimiser_variables(self.layout.n, self.problem.stiffness_scale, weighted, &mut out);
        Some(out)
    }
}

/// A gradient with respect to `(θ0, K)` (`N` then `N + 1` entries) written into `out` as one with
/// respect to the optimiser's `(θ0, k)`, `k = K / C_K` (eq. (34)): the `K` entries times `C_K`.
fn to_optimiser_variables(n: usize, stiffness_scale: f64, design_gradient: impl Iterator<Item = f64>, out: &mut [f64]) {
    for (k, (o, g)) in out.iter_mut().zip(design_gradient).enumerate() {
        *o = if k < n { g } else { stiffness_scale * g };
    }
}

impl spine_ipopt::Problem for ReducedSpaceNlp<'_> {
    fn num_variables(&self) -> usize {
        self.layout.num_variables()
    }
    fn num_constraints(&self) -> usize {
        self.layout.num_constraints()
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        Numbers::of(self.problem).variable_bounds(lower, upper, |j| self.layout.height(j));
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        Numbers::of(self.problem).constraint_bounds(
            lower,
            upper,
            self.layout.end_row(),
            |i| self.layout.relative_row(i),
            None,
        );
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&self.start);
    }
    fn objective(&mut self, x: &[f64], _new_x: bool) -> Option<f64> {
        self.evaluate(x).map(|e| e.gradients.energy)
    }
    fn objective_gradient(&mut self, x: &[f64], _new_x: bool, gradient: &mut [f64]) -> bool {
        let (n, ck) = (self.layout.n, self.problem.stiffness_scale);
        let Some(e) = self.evaluate(x) else { return false };
        gradient.fill(0.0);
        to_optimiser_variables(n, ck, e.gradients.energy_gradient.iter().copied(), gradient);
        true
    }
    fn constraints(&mut self, x: &[f64], _new_x: bool, g: &mut [f64]) -> bool {
        self.linear.values(x, g);
        let row = self.layout.end_row();
        let Some(e) = self.evaluate(x) else { return false };
        g[row] = e.gradients.end_x;
        true
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        let mut structure = self.linear.patterns.jacobian.clone();
        structure.extend((0..2 * self.layout.n + 1).map(|k| (self.layout.end_row(), k)));
        structure
    }
    fn jacobian_values(&mut self, x: &[f64], _new_x: bool, values: &mut [f64]) -> bool {
        let linear_len = self.linear.patterns.jacobian.len();
        let mut unused = vec![0.0; x.len()];
        self.linear.first_derivatives(x, &mut unused, &mut values[..linear_len]);
        let (n, ck) = (self.layout.n, self.problem.stiffness_scale);
        let Some(e) = self.evaluate(x) else { return false };
        to_optimiser_variables(n, ck, e.gradients.end_x_gradient.iter().copied(), &mut values[linear_len..]);
        true
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        let d = 2 * self.layout.n + 1;
        (self.hessian == ReducedHessian::AdjointDifferences)
            .then(|| (0..d).flat_map(|r| (0..=r).map(move |c| (r, c))).collect())
    }
    fn hessian_values(&mut self, x: &[f64], _: bool, sigma: f64, lambda: &[f64], _: bool, values: &mut [f64]) -> bool {
        let d = 2 * self.layout.n + 1;
        if self.evaluate(x).is_none() {
            return false;
        }
        let lambda_end = lambda[self.layout.end_row()];
        let mut columns = Vec::with_capacity(d);
        for k in 0..d {
            let h = 1e-6 * x[k].abs().max(1.0);
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[k] += h;
            xm[k] -= h;
            let (Some(gp), Some(gm)) =
                (self.weighted_gradient(&xp, sigma, lambda_end), self.weighted_gradient(&xm, sigma, lambda_end))
            else {
                return false;
            };
            columns.push(gp.iter().zip(&gm).map(|(a, b)| (a - b) / (2.0 * h)).collect::<Vec<f64>>());
        }
        // The height steps' own second derivatives (−a_j λ_j d²tan θ0_j/dθ0_j²) sit on the θ0 diagonal.
        let mut linear = vec![0.0; self.linear.patterns.hessian.len()];
        self.linear.hessian(x, 0.0, lambda, &mut linear);
        let mut position = 0;
        for r in 0..d {
            for c in 0..=r {
                values[position] = 0.5 * (columns[c][r] + columns[r][c]);
                position += 1;
            }
        }
        for (&(r, c), v) in self.linear.patterns.hessian.iter().zip(&linear) {
            values[r * (r + 1) / 2 + c] += v;
        }
        values.iter().all(|v| v.is_finite())
    }
    fn intermediate(&mut self, info: &spine_ipopt::IterationInfo) -> bool {
        self.on_iteration.as_mut().is_none_or(|f| f(info))
    }
}
