//! The exact two-link design of Sec. 3, found with the general `N`-link code.
//!
//! For a given spring `K` and end displacement `δ`, the design angle `θ0` solves eqs. (8) and (9).
//! Here it is found by a bracketed root search in `θ0` whose every evaluation runs the general
//! equilibrium solver on the chain `N = 2`, `K = [0, K, 0]`, spans `a = L cos θ0` (so the link length
//! stays `L`, as in the paper's Sec. 3), `P_Y` at the middle node and `P_X` at the slider.

use crate::equilibrium::{solve_static, ContinuationOptions, StaticProblem, StaticSolution};
use spine_model::twolink::TwoLink;
use spine_model::{Chain, Design, NodalLoads};

/// The general chain and loads that realise the Sec. 3 problem for design angle `theta0`.
pub fn general_problem(tl: &TwoLink, stiffness: f64, theta0: f64) -> StaticProblem {
    let span = tl.length * theta0.cos();
    let chain = Chain { spans: vec![span; 2], masses: vec![0.0; 2], gravity: 0.0 };
    let design = Design { theta0: vec![theta0, -theta0], stiffness: vec![0.0, stiffness, 0.0] };
    let passive = NodalLoads { p_x: vec![0.0; 3], p_y: vec![0.0, tl.p_y, 0.0] };
    let actuation = NodalLoads { p_x: vec![0.0, 0.0, tl.p_x], p_y: vec![0.0; 3] };
    StaticProblem { chain, design, passive, actuation }
}

/// Solves the general problem for design angle `theta0`.
pub fn general_solution(tl: &TwoLink, stiffness: f64, theta0: f64, opts: &ContinuationOptions) -> StaticSolution {
    solve_static(&general_problem(tl, stiffness, theta0), opts)
}

/// The exact `θ0` for `(K, δ)`, or `None` when no sign change of `δ(θ0) − δ` is found between the
/// zero-moment angle `θ*` and `θ* + 1` rad. Returns the first root above `θ*` (the branch of
/// eq. (10)), converged to `|Δθ0| ≤ 1e-14`.
pub fn exact_theta0(tl: &TwoLink, stiffness: f64, delta: f64, opts: &ContinuationOptions) -> Option<f64> {
    let f = |t0: f64| -> Option<f64> {
        let sol = general_solution(tl, stiffness, t0, opts);
        sol.loaded.filter(|l| l.status.is_stable())?;
        sol.end_displacement.map(|d| d - delta)
    };
    let start = tl.zero_moment_angle();
    let mut a = start + 1e-9;
    let mut fa = f(a)?;
    let steps = 400;
    let mut bracket = None;
    for k in 1..=steps {
        let b = start + 1.0 * (k as f64 / steps as f64).powi(2);
        let fb = f(b)?;
        if fa * fb <= 0.0 {
            bracket = Some((a, fa, b, fb));
            break;
        }
        a = b;
        fa = fb;
    }
    let (mut a, mut fa, mut b, mut fb) = bracket?;
    // Illinois regula falsi: `(a, b)` always brackets the root, `b` is the newest point.
    for _ in 0..200 {
        let c = (a * fb - b * fa) / (fb - fa);
        let fc = f(c)?;
        if fc == 0.0 {
            return Some(c);
        }
        if fc * fb < 0.0 {
            a = b;
            fa = fb;
        } else {
            fa *= 0.5;
        }
        b = c;
        fb = fc;
        if (b - a).abs() <= 1e-14 {
            break;
        }
    }
    Some(b)
}
