//! How far a design result is from satisfying eq. (33): each part of the problem recomputed from
//! the reported design and states, and what Ipopt's tolerances allow.

use crate::problem::DesignProblem;
use crate::settings::{ExtraOption, SolverSettings};
use serde::Serialize;
use spine_model::kinematics::end_constraint;
use spine_model::Design;

/// How far the result is from satisfying eq. (33), each part in its own unit.
#[derive(Clone, Debug, Serialize)]
pub struct Violations {
    /// Largest of all below (mixed units: N·m, m, rad, N·m/rad).
    pub max: f64,
    pub passive_equilibrium: f64,
    pub loaded_equilibrium: f64,
    /// `|Φ(θ0)|`, m.
    pub unloaded_end_height: f64,
    /// `|X_{N+1}(θ2) − L_x − δ_d|`, m.
    pub end_displacement: f64,
    /// Bound excess of `θ0`, relative angles (rad), node heights (m), stiffness (N·m/rad).
    pub theta0_bounds: f64,
    pub relative_angle_bounds: f64,
    pub height_bounds: f64,
    pub stiffness_bounds: f64,
}

impl Violations {
    /// Measures every part from `design`, the equilibrium residuals of `θ1` and `θ2` (N·m) and the
    /// end displacement `X_{N+1}(θ2) − L_x` (m).
    pub(crate) fn measure(problem: &DesignProblem, design: &Design, residuals: (f64, f64), end: f64) -> Self {
        let spans = &problem.structure.chain.spans;
        let b = &problem.bounds;
        let heights = problem.node_heights(&design.theta0);
        let n = design.theta0.len();
        let v = Violations {
            max: 0.0,
            passive_equilibrium: residuals.0,
            loaded_equilibrium: residuals.1,
            unloaded_end_height: end_constraint(spans, &design.theta0, &design.theta0).abs(),
            end_displacement: (end - problem.delta_d).abs(),
            theta0_bounds: design.theta0.iter().map(|t| excess(*t, -b.theta0_max, b.theta0_max)).fold(0.0, f64::max),
            relative_angle_bounds: design
                .theta0
                .windows(2)
                .map(|w| excess(w[0] - w[1], -b.relative_angle_max, b.relative_angle_max))
                .fold(0.0, f64::max),
            height_bounds: heights[1..n]
                .iter()
                .zip(b.height_floors(spans))
                .map(|(y, floor)| excess(*y, floor, b.height_max))
                .fold(0.0, f64::max),
            stiffness_bounds: design
                .stiffness
                .iter()
                .enumerate()
                .map(|(j, k)| excess(*k, b.stiffness_min[j], b.stiffness_max[j]))
                .fold(0.0, f64::max),
        };
        let max = [
            v.passive_equilibrium,
            v.loaded_equilibrium,
            v.unloaded_end_height,
            v.end_displacement,
            v.theta0_bounds,
            v.relative_angle_bounds,
            v.height_bounds,
            v.stiffness_bounds,
        ]
        .into_iter()
        .fold(0.0, f64::max);
        Violations { max, ..v }
    }

    /// The largest violation of eq. (33)'s constraint rows: the equilibria (N·m), the unloaded end
    /// height and the end displacement (m), the relative angles (rad) and the node heights (m),
    /// without the bounds on `θ0` and `K` themselves. This is what Ipopt reports as the
    /// constraint violation of an NLP whose variables carry those bounds (CasADi's peer script's
    /// measure), so the two compare like with like; [`Violations::max`] adds the variable bounds,
    /// whose excess in `K` is in N·m/rad (3e-9 relative to `K_max` = 1e8 N·m/rad reads 0.33).
    pub fn constraint_rows(&self) -> f64 {
        [
            self.passive_equilibrium,
            self.loaded_equilibrium,
            self.unloaded_end_height,
            self.end_displacement,
            self.relative_angle_bounds,
            self.height_bounds,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }

    /// What an inequality's bound `at` allows beyond it: the constraint tolerance plus Ipopt's
    /// relaxation of bounds (`bound_relax_factor · max(|at|, 1)`).
    pub fn inequality_allowance(settings: &SolverSettings, at: f64) -> f64 {
        settings.constraint_tolerance + bound_relax_factor(settings) * at.abs().max(1.0)
    }

    /// Each part of eq. (33) with its violation and what is allowed: the equalities (equilibria,
    /// unloaded end height, end displacement) `constraint_tolerance`, Ipopt's `constr_viol_tol`;
    /// the bounds that plus Ipopt's relaxation of every bound, `bound_relax_factor · max(1, |b|)`
    /// in the variable's own scale (for `K`, the scaled `k = K / C_K` of eq. (34)), which Ipopt
    /// applies to the problem it solves and which `honor_original_bounds = no` keeps.
    pub fn parts(&self, problem: &DesignProblem, settings: &SolverSettings) -> [(&'static str, f64, f64); 8] {
        let tol = settings.constraint_tolerance;
        let relax = bound_relax_factor(settings);
        let b = &problem.bounds;
        let c_k = problem.stiffness_scale;
        let k_max = b.stiffness_max.iter().fold(0.0f64, |m, k| m.max(k.abs()));
        let angle = tol + relax * b.theta0_max.abs().max(1.0);
        let relative = tol + relax * b.relative_angle_max.abs().max(1.0);
        let height = tol + relax * b.height_min.abs().max(b.height_max.abs()).max(1.0);
        let stiffness = tol * c_k + relax * k_max.max(c_k);
        [
            ("passive_equilibrium", self.passive_equilibrium, tol),
            ("loaded_equilibrium", self.loaded_equilibrium, tol),
            ("unloaded_end_height", self.unloaded_end_height, tol),
            ("end_displacement", self.end_displacement, tol),
            ("theta0_bounds", self.theta0_bounds, angle),
            ("relative_angle_bounds", self.relative_angle_bounds, relative),
            ("height_bounds", self.height_bounds, height),
            ("stiffness_bounds", self.stiffness_bounds, stiffness),
        ]
    }
}

/// Ipopt's default `bound_relax_factor`.
pub const IPOPT_BOUND_RELAX_FACTOR: f64 = 1e-8;

fn excess(value: f64, lo: f64, hi: f64) -> f64 {
    (lo - value).max(value - hi).max(0.0)
}

/// Ipopt's `bound_relax_factor` of a run: the case's, or Ipopt's default.
fn bound_relax_factor(settings: &SolverSettings) -> f64 {
    match settings.ipopt_options.get("bound_relax_factor") {
        Some(ExtraOption::Num(x)) => *x,
        Some(ExtraOption::Int(i)) => *i as f64,
        _ => IPOPT_BOUND_RELAX_FACTOR,
    }
}

#[cfg(test)]
mod tests {
    use super::Violations;

    fn zero() -> Violations {
        Violations {
            max: 0.0,
            passive_equilibrium: 0.0,
            loaded_equilibrium: 0.0,
            unloaded_end_height: 0.0,
            end_displacement: 0.0,
            theta0_bounds: 0.0,
            relative_angle_bounds: 0.0,
            height_bounds: 0.0,
            stiffness_bounds: 0.0,
        }
    }

    #[test]
    fn the_constraint_rows_leave_out_the_variables_own_bounds() {
        let bounds_only = Violations { max: 0.33, stiffness_bounds: 0.33, theta0_bounds: 1e-9, ..zero() };
        assert_eq!(bounds_only.constraint_rows(), 0.0);
        let rows: [fn(&mut Violations) -> &mut f64; 6] = [
            |v| &mut v.passive_equilibrium,
            |v| &mut v.loaded_equilibrium,
            |v| &mut v.unloaded_end_height,
            |v| &mut v.end_displacement,
            |v| &mut v.relative_angle_bounds,
            |v| &mut v.height_bounds,
        ];
        for (k, part) in rows.iter().enumerate() {
            let mut v = Violations { stiffness_bounds: 0.33, ..zero() };
            *part(&mut v) = 1e-7 * (k + 1) as f64;
            assert_eq!(v.constraint_rows(), 1e-7 * (k + 1) as f64, "row part {k}");
        }
    }
}
