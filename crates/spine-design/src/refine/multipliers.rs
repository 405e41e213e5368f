//! Multipliers of a coarse optimum carried to the fine chain.

use super::mesh::{interpolate, midpoints, node_x};
use crate::full_space::Multipliers;
use crate::layout::{Layout, StateForm};
use crate::problem::DesignProblem;

/// The multipliers of a coarse solution carried to the fine chain, for Ipopt's warm start.
///
/// From the stationarity conditions of eq. (33) with a consistent coarsening (`K ∝ 1/h`, `J` a
/// Riemann sum): the multipliers of the equilibrium, height and end rows are fields of order one,
/// interpolated at the links (or copied for the single `Φ` and end rows); the multipliers of the
/// relative-angle rows and of the bounds on `θ0`, `k` and the heights scale like the span,
/// interpolated and multiplied by `h_fine / h_coarse`. A bound multiplier is kept only where the
/// fine variable sits on that bound (`x_fine` within `1e-7` of it), else it is zero and Ipopt's
/// `warm_start_mult_bound_push` sets it.
pub fn prolong_multipliers(
    coarse: &DesignProblem,
    fine: &DesignProblem,
    m: &Multipliers,
    x_fine: &[f64],
    lower: &[f64],
    upper: &[f64],
) -> Multipliers {
    let (mc, nf) = (coarse.n_links(), fine.n_links());
    // Row and bound indices only, which do not depend on how the states are variables.
    let (cl, fl) = (Layout::of(coarse, StateForm::Absolute), Layout::of(fine, StateForm::Absolute));
    let ratio = mc as f64 / nf as f64;
    let (cmid, fmid) = (midpoints(&coarse.structure.chain.spans), midpoints(&fine.structure.chain.spans));
    let (cx, fx) = (node_x(&coarse.structure.chain.spans), node_x(&fine.structure.chain.spans));
    let field = |values: Vec<f64>, at: &[f64], to: &[f64], scale: f64| -> Vec<f64> {
        interpolate(at, &values, to).into_iter().map(|v| v * scale).collect()
    };

    let mut constraints = vec![0.0; fl.num_constraints()];
    for &s in fl.load_states() {
        let joints = field((0..mc).map(|i| m.constraints[cl.equilibrium_row(s, i)]).collect(), &cmid, &fmid, 1.0);
        for (i, v) in joints.into_iter().enumerate() {
            constraints[fl.equilibrium_row(s, i)] = v;
        }
        constraints[fl.constraint_row(s)] = m.constraints[cl.constraint_row(s)];
    }
    for (j, v) in
        field((0..mc).map(|j| m.constraints[cl.height_row(j)]).collect(), &cmid, &fmid, 1.0).into_iter().enumerate()
    {
        constraints[fl.height_row(j)] = v;
    }
    constraints[fl.end_row()] = m.constraints[cl.end_row()];
    if mc >= 2 && nf >= 2 {
        let relative =
            field((0..mc - 1).map(|i| m.constraints[cl.relative_row(i)]).collect(), &cx[1..mc], &fx[1..nf], ratio);
        for (i, v) in relative.into_iter().enumerate() {
            constraints[fl.relative_row(i)] = v;
        }
    }

    let bound = |z: &[f64]| {
        let mut out = vec![0.0; fl.num_variables()];
        for (i, v) in field((0..mc).map(|i| z[cl.theta0(i)]).collect(), &cmid, &fmid, ratio).into_iter().enumerate() {
            out[fl.theta0(i)] = v;
        }
        for (j, v) in field((0..=mc).map(|j| z[cl.stiffness(j)]).collect(), &cx, &fx, ratio).into_iter().enumerate() {
            out[fl.stiffness(j)] = v;
        }
        if mc >= 2 && nf >= 2 {
            // Invariant: both layouts have a height variable for every interior node.
            let heights =
                field((1..mc).map(|j| z[cl.height(j).expect("interior")]).collect(), &cx[1..mc], &fx[1..nf], ratio);
            for (j, v) in heights.into_iter().enumerate() {
                out[fl.height(j + 1).expect("interior")] = v;
            }
        }
        out
    };
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-7 * (1.0 + b.abs());
    let mut z_lower = bound(&m.z_lower);
    let mut z_upper = bound(&m.z_upper);
    for k in 0..x_fine.len() {
        if !near(x_fine[k], lower[k]) {
            z_lower[k] = 0.0;
        }
        if !near(x_fine[k], upper[k]) {
            z_upper[k] = 0.0;
        }
    }
    Multipliers { constraints, z_lower, z_upper }
}
