//! Positive variables handed to Ipopt by their logarithm: `u = ln x`, so that a Newton step
//! changes such a variable by a bounded factor instead of a bounded amount.
//!
//! Why: eq. (33)'s objective and equilibria depend on a spring through its compliance, like
//! `a / k + b k` along a line through the optimum. Newton's method on `a / k` from above its
//! minimiser overshoots without bound (its curvature `2a / k³` vanishes as `k` grows: from a
//! stiff spring near its upper bound the step is `k / 2 · (1 − (k / k*)²)`), and Ipopt's line
//! search then cuts steps of 10³–10⁵ in `k` back to a few per cent, iteration after iteration
//! (docs/design.md, "Springs by their logarithm"). In `u = ln k` the same function is
//! `2√(ab) cosh(u − u*)`, whose Newton step is `−tanh(u − u*)`: at most one e-fold.
//!
//! Each logged variable is `u = s ln x` with `s = min(1, x_min)`: Newton's step is the same for
//! any constant `s`, and with `s ≤ x_min` the gradient `∂L/∂u = (x / s) ∂L/∂x` is never smaller
//! than in `x`, so Ipopt's stopping test is at least as strict (with `s` = 1 and springs `k < 1`,
//! as in the continuum study where `k ∈ [0.01, 1]`, it would be looser by `k`).
//!
//! [`LogVariables`] wraps any [`spine_ipopt::Problem`] and transforms the variables it names: the
//! bounds, the start point and start multipliers on the way in, first and second derivatives by
//! the chain rule (`∂/∂u = (x / s) ∂/∂x`; the Hessian of the Lagrangian gains the diagonal term
//! `(x / s²) ∂L/∂x`), and the solution back on the way out ([`LogVariables::solution_back`]), so
//! that everything after Ipopt sees the problem's own variables and multipliers
//! (`z_x = (s / x) z_u`).
//! A KKT point in `u` is a KKT point in `x` with those multipliers: the problem is the same, only
//! Ipopt's path to it differs.

use spine_ipopt::{IterationInfo, Problem, Solution};

/// `inner` with the variables `logged` (each with a positive lower bound) seen by their logarithm.
pub struct LogVariables<'p> {
    inner: &'p mut dyn Problem,
    /// Sorted indices of the transformed variables.
    logged: Vec<usize>,
    is_logged: Vec<bool>,
    /// `s` of each variable: a logged one is `u = s ln x` with `s = min(1, x_min)`, so that
    /// `∂L/∂u = (x / s) ∂L/∂x` is never smaller than `∂L/∂x` and Ipopt's stopping test in `u` is
    /// at least as strict as in `x` (1 for the others).
    scale: Vec<f64>,
    /// The inner Hessian's pattern, then the diagonals of logged variables it lacks.
    hessian: Option<Vec<(usize, usize)>>,
    /// Where each logged variable's diagonal entry is in `hessian`.
    diagonal_at: Vec<usize>,
    inner_hessian_len: usize,
    jacobian: Vec<(usize, usize)>,
    x: Vec<f64>,
    gradient: Vec<f64>,
    jacobian_values: Vec<f64>,
}

impl<'p> LogVariables<'p> {
    /// Wraps `inner`; `logged` are the variables to transform (each must have a lower bound > 0).
    pub fn new(inner: &'p mut dyn Problem, logged: &[usize]) -> Self {
        let n = inner.num_variables();
        let mut is_logged = vec![false; n];
        for &v in logged {
            is_logged[v] = true;
        }
        let logged: Vec<usize> = (0..n).filter(|&v| is_logged[v]).collect();
        let (mut lower, mut upper) = (vec![0.0; n], vec![0.0; n]);
        inner.variable_bounds(&mut lower, &mut upper);
        let scale: Vec<f64> = (0..n).map(|v| if is_logged[v] { lower[v].min(1.0) } else { 1.0 }).collect();
        let jacobian = inner.jacobian_structure();
        let mut diagonal_at = vec![usize::MAX; n];
        let inner_pattern = inner.hessian_structure();
        let inner_hessian_len = inner_pattern.as_ref().map_or(0, Vec::len);
        let hessian = inner_pattern.map(|mut pattern| {
            for (at, &(r, c)) in pattern.iter().enumerate() {
                if r == c && is_logged[r] {
                    diagonal_at[r] = at;
                }
            }
            for &v in &logged {
                if diagonal_at[v] == usize::MAX {
                    diagonal_at[v] = pattern.len();
                    pattern.push((v, v));
                }
            }
            pattern
        });
        let jacobian_len = jacobian.len();
        LogVariables {
            inner,
            logged,
            is_logged,
            scale,
            hessian,
            diagonal_at,
            inner_hessian_len,
            jacobian,
            x: vec![0.0; n],
            gradient: vec![0.0; n],
            jacobian_values: vec![0.0; jacobian_len],
        }
    }

    /// The inner problem's point at `u`.
    fn inner_x(&mut self, u: &[f64]) {
        self.x.copy_from_slice(u);
        for &v in &self.logged {
            self.x[v] = (u[v] / self.scale[v]).exp();
        }
    }

    /// `dx/du = x / s` of variable `v` at the last point (1 if it is not logged).
    fn dx_du(&self, v: usize) -> f64 {
        if self.is_logged[v] {
            self.x[v] / self.scale[v]
        } else {
            1.0
        }
    }

    /// Ipopt's solution in `u` as a solution of the inner problem: `x = exp(u / s)`,
    /// `z_x = (s / x) z_u`.
    pub fn solution_back(&self, mut solution: Solution) -> Solution {
        for &v in &self.logged {
            let x = (solution.x[v] / self.scale[v]).exp();
            solution.x[v] = x;
            solution.z_lower[v] *= self.scale[v] / x;
            solution.z_upper[v] *= self.scale[v] / x;
        }
        solution
    }
}

/// `options` with Ipopt's `bound_relax_factor` shrunk so that Ipopt's relaxation of the bounds
/// in `u`, `bound_relax_factor · max(1, |u_bound|)`, moves no logged variable by more than
/// `bound_relax_factor` relative to its own bound: what the design check allows
/// ([`crate::violations::IPOPT_BOUND_RELAX_FACTOR`]). Without it a spring at `k = 10⁴` ended
/// 2.5e-8 relative beyond its bound (the scaled family at N = 20), ten times what the check allows.
pub fn relaxed_in_logs(problem: &LogVariables<'_>, options: &spine_ipopt::Options) -> spine_ipopt::Options {
    let n = problem.num_variables();
    let (mut lower, mut upper) = (vec![0.0; n], vec![0.0; n]);
    problem.variable_bounds(&mut lower, &mut upper);
    // Ipopt moves a bound `b` of `u = s ln x` by `f max(1, |b|)`, which is `f max(1, |b|) / s`
    // in `ln x`: the factor that keeps that within `f` is the smallest `s / max(1, |b|)`.
    let shrink = problem
        .logged
        .iter()
        .flat_map(|&v| [lower[v], upper[v]].map(|b| (v, b)))
        .filter(|(_, b)| b.is_finite())
        .fold(1.0f64, |m, (v, b)| m.min(problem.scale[v] / b.abs().max(1.0)));
    let relax = match options.get("bound_relax_factor") {
        Some(spine_ipopt::OptionValue::Num(x)) => *x,
        Some(spine_ipopt::OptionValue::Int(i)) => *i as f64,
        _ => crate::violations::IPOPT_BOUND_RELAX_FACTOR,
    };
    options.clone().number("bound_relax_factor", relax * shrink)
}

impl Problem for LogVariables<'_> {
    fn num_variables(&self) -> usize {
        self.inner.num_variables()
    }
    fn num_constraints(&self) -> usize {
        self.inner.num_constraints()
    }
    fn variable_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        self.inner.variable_bounds(lower, upper);
        for &v in &self.logged {
            debug_assert!(lower[v] > 0.0, "a logged variable needs a positive lower bound");
            lower[v] = self.scale[v] * lower[v].ln();
            upper[v] =
                if upper[v].is_finite() && upper[v] < 1e19 { self.scale[v] * upper[v].ln() } else { f64::INFINITY };
        }
    }
    fn constraint_bounds(&self, lower: &mut [f64], upper: &mut [f64]) {
        self.inner.constraint_bounds(lower, upper);
    }
    fn initial_point(&self, x: &mut [f64]) {
        self.inner.initial_point(x);
        for &v in &self.logged {
            x[v] = self.scale[v] * x[v].max(f64::MIN_POSITIVE).ln();
        }
    }
    fn initial_multipliers(&self, z_lower: &mut [f64], z_upper: &mut [f64], lambda: &mut [f64]) -> bool {
        if !self.inner.initial_multipliers(z_lower, z_upper, lambda) {
            return false;
        }
        let mut x = vec![0.0; self.num_variables()];
        self.inner.initial_point(&mut x);
        for &v in &self.logged {
            z_lower[v] *= x[v] / self.scale[v];
            z_upper[v] *= x[v] / self.scale[v];
        }
        true
    }
    fn objective(&mut self, u: &[f64], new_x: bool) -> Option<f64> {
        self.inner_x(u);
        self.inner.objective(&self.x, new_x)
    }
    fn objective_gradient(&mut self, u: &[f64], new_x: bool, gradient: &mut [f64]) -> bool {
        self.inner_x(u);
        let ok = self.inner.objective_gradient(&self.x, new_x, gradient);
        for &v in &self.logged {
            gradient[v] *= self.dx_du(v);
        }
        ok
    }
    fn constraints(&mut self, u: &[f64], new_x: bool, g: &mut [f64]) -> bool {
        self.inner_x(u);
        self.inner.constraints(&self.x, new_x, g)
    }
    fn jacobian_structure(&self) -> Vec<(usize, usize)> {
        self.jacobian.clone()
    }
    fn jacobian_values(&mut self, u: &[f64], new_x: bool, values: &mut [f64]) -> bool {
        self.inner_x(u);
        let ok = self.inner.jacobian_values(&self.x, new_x, values);
        for (value, &(_, c)) in values.iter_mut().zip(&self.jacobian) {
            *value *= self.dx_du(c);
        }
        ok
    }
    fn hessian_structure(&self) -> Option<Vec<(usize, usize)>> {
        self.hessian.clone()
    }
    fn hessian_values(
        &mut self,
        u: &[f64],
        new_x: bool,
        sigma: f64,
        lambda: &[f64],
        new_lambda: bool,
        values: &mut [f64],
    ) -> bool {
        self.inner_x(u);
        let Some(pattern) = self.hessian.as_ref() else { return false };
        let split = self.inner_hessian_len;
        let mut ok = self.inner.hessian_values(&self.x, new_x, sigma, lambda, new_lambda, &mut values[..split]);
        values[split..].iter_mut().for_each(|v| *v = 0.0);
        for (value, &(r, c)) in values[..split].iter_mut().zip(pattern) {
            let scale = self.dx_du(r) * self.dx_du(c);
            *value *= scale;
        }
        // The chain rule's second term, `(x / s²) ∂L/∂x` on the diagonal of each logged variable,
        // with `∂L/∂x = σ ∇f + Jᵀλ` gathered in `gradient` (the inner problem caches both at `x`).
        ok &= self.inner.objective_gradient(&self.x, false, &mut self.gradient);
        ok &= self.inner.jacobian_values(&self.x, false, &mut self.jacobian_values);
        for &v in &self.logged {
            self.gradient[v] *= sigma;
        }
        for (value, &(r, c)) in self.jacobian_values.iter().zip(&self.jacobian) {
            if self.is_logged[c] {
                self.gradient[c] += lambda[r] * value;
            }
        }
        for &v in &self.logged {
            values[self.diagonal_at[v]] += self.x[v] / (self.scale[v] * self.scale[v]) * self.gradient[v];
        }
        ok
    }
    fn intermediate(&mut self, info: &IterationInfo) -> bool {
        self.inner.intermediate(info)
    }
}

#[cfg(test)]
mod tests {
    use super::LogVariables;
    use crate::fixtures::{arch_start, scaled_family};
    use crate::full_space::FullSpaceNlp;
    use crate::layout::StateForm;
    use spine_ipopt::Problem;

    /// `σ∇f + Jᵀλ` of `p` at `u`.
    fn lagrangian_gradient(p: &mut dyn Problem, u: &[f64], sigma: f64, lambda: &[f64]) -> Vec<f64> {
        let mut grad = vec![0.0; u.len()];
        assert!(p.objective_gradient(u, true, &mut grad));
        grad.iter_mut().for_each(|g| *g *= sigma);
        let pattern = p.jacobian_structure();
        let mut values = vec![0.0; pattern.len()];
        assert!(p.jacobian_values(u, false, &mut values));
        for (&(r, c), v) in pattern.iter().zip(&values) {
            grad[c] += lambda[r] * v;
        }
        grad
    }

    /// The wrapper's gradient, Jacobian and Hessian of the Lagrangian against central differences
    /// of its own values and first derivatives, at an arch start of the scaled family (N = 6, the
    /// springs spread over their range so that `x ∂L/∂x` varies).
    #[test]
    fn derivatives_in_log_springs_match_central_differences() {
        // k in [100, 10⁴] (s = 1) and, with C_K 10⁴ times larger, in [0.01, 1] (s = 0.01).
        for ck in [1.0, 1e4] {
            derivatives_match(ck);
        }
    }

    fn derivatives_match(ck: f64) {
        let n = 6;
        let mut problem = scaled_family(n);
        problem.stiffness_scale *= ck;
        let mut start = arch_start(n, 0.3, 1e3 * 0.36);
        for (j, k) in start.stiffness.iter_mut().enumerate() {
            *k *= 0.5 + 0.4 * j as f64;
        }
        let states = crate::problem::start_states(&problem, &start, &Default::default(), &mut Vec::new());
        let mut inner = FullSpaceNlp::new(&problem, StateForm::Deflection, &start, &states.0, &states.1);
        let logged: Vec<usize> = (0..=n).map(|j| inner.layout.stiffness(j)).collect();
        let mut p = LogVariables::new(&mut inner, &logged);
        let (nv, m) = (p.num_variables(), p.num_constraints());
        let mut u = vec![0.0; nv];
        p.initial_point(&mut u);
        let lambda: Vec<f64> = (0..m).map(|r| 0.3 + 0.1 * (r % 7) as f64).collect();
        let sigma = 0.7;
        let scale = |v: usize| if logged.contains(&v) { 1e-6 } else { 1e-6 * u[v].abs().max(1e-2) };

        // Gradient and Jacobian: columns by central differences of f and g.
        let g0 = lagrangian_gradient(&mut p, &u, sigma, &lambda);
        for v in 0..nv {
            let h = scale(v);
            let (mut up, mut down) = (u.clone(), u.clone());
            up[v] += h;
            down[v] -= h;
            let (fu, fd) = (p.objective(&up, true).unwrap(), p.objective(&down, true).unwrap());
            let (mut gu, mut gd) = (vec![0.0; m], vec![0.0; m]);
            assert!(p.constraints(&up, true, &mut gu) && p.constraints(&down, true, &mut gd));
            let fd_l = sigma * (fu - fd) / (2.0 * h)
                + lambda.iter().zip(gu.iter().zip(&gd)).map(|(l, (a, b))| l * (a - b) / (2.0 * h)).sum::<f64>();
            let tol = 1e-6 * g0[v].abs().max(1.0) + 1e-6 * g0.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            assert!((fd_l - g0[v]).abs() <= tol, "∂L/∂u[{v}]: {} by AD, {fd_l} by differences", g0[v]);
        }

        // Hessian of the Lagrangian: columns by central differences of the Lagrangian's gradient.
        let pattern = p.hessian_structure().expect("exact Hessian");
        let mut values = vec![0.0; pattern.len()];
        assert!(p.hessian_values(&u, true, sigma, &lambda, true, &mut values));
        let mut dense = vec![vec![0.0; nv]; nv];
        for (&(r, c), v) in pattern.iter().zip(&values) {
            dense[r][c] += v;
            if r != c {
                dense[c][r] += v;
            }
        }
        let largest = dense.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs()));
        for v in 0..nv {
            let h = scale(v);
            let (mut up, mut down) = (u.clone(), u.clone());
            up[v] += h;
            down[v] -= h;
            let (gu, gd) =
                (lagrangian_gradient(&mut p, &up, sigma, &lambda), lagrangian_gradient(&mut p, &down, sigma, &lambda));
            for r in 0..nv {
                let fd = (gu[r] - gd[r]) / (2.0 * h);
                assert!(
                    (fd - dense[r][v]).abs() <= 1e-5 * largest,
                    "∂²L/∂u[{r}]∂u[{v}]: {} exact, {fd} by differences (largest entry {largest})",
                    dense[r][v]
                );
            }
        }
    }
}
