//! The two-link optimisation of eq. (12): minimise `U(θ1)` over `K` within its bounds, with `θ0`
//! the exact design angle of each `K` (eqs. (8), (9)).

use super::*;

/// Where the optimum of eq. (12) lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OptimumPlace {
    /// Between the bounds, where `dJ/dK` along the constraint vanishes.
    Interior,
    /// At the lower stiffness bound.
    LowerBound,
    /// At the upper stiffness bound.
    UpperBound,
    /// At the largest (or smallest) `K` for which a stable design still meets `δ`: beyond it no
    /// `θ0` gives a stable `θ2` with end displacement `δ`, so `J` has an infimum there, not a
    /// minimum inside the bounds.
    StabilityEdge,
    /// At the largest `K` whose design keeps `|θ0|` within a limit (Sec. 5's angle and height
    /// bounds): `J` still falls along the constraint, and the bound stops it.
    AngleBound,
}

impl OptimumPlace {
    /// As a report says it.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Interior => "interior",
            Self::LowerBound => "at the lower bound",
            Self::UpperBound => "at the upper bound",
            Self::StabilityEdge => "at the stability edge",
            Self::AngleBound => "at the angle bound",
        }
    }
}

/// Eq. (12) solved: `min_{θ0, K} 2K(θ1 − θ0)²` subject to `cos θ2 = cos θ0 + δ/2L` and
/// `K_min ≤ K ≤ K_max`, with the Lagrange conditions (18)–(20) evaluated at the optimum.
#[derive(Clone, Debug, serde::Serialize)]
pub struct TwoLinkOptimum {
    pub delta: f64,
    /// `(K_min, K_max)`, N·m/rad.
    pub bounds: (f64, f64),
    /// The limit on `|θ0|`, rad, when the problem has one (Sec. 5's bounds, [`optimum_within`]).
    pub theta0_limit: Option<f64>,
    pub place: OptimumPlace,
    pub stiffness: f64,
    pub theta0: f64,
    pub theta1: f64,
    pub theta2: f64,
    /// `J = 2K(θ1 − θ0)²`, J.
    pub objective: f64,
    /// `λ1` making eq. (20) zero, J.
    pub lambda: f64,
    /// Eq. (19) with that `λ1`: `dJ/dK` along the constraint, J·rad/(N·m).
    pub dl_dk: f64,
    /// Eq. (20) with that `λ1`, J/rad: zero to round-off (the `λ1` is chosen so).
    pub dl_dtheta0: f64,
    /// The same by central differences of `J(K, θ0(K))` along the constraint (the exact `θ0(K)`
    /// of [`exact_theta0`]), `None` at a stability edge (one side has no design).
    pub dl_dk_central_difference: Option<f64>,
    /// Eqs. (13), (14) at the optimum: the objective's own partials, J·rad/(N·m) and J/rad.
    pub dj_dk: f64,
    pub dj_dtheta0: f64,
    /// Evaluations of `J(K)` (each a root search of the general `N = 2` solver).
    pub evaluations: usize,
}

/// `J(K)` along the constraint: `(θ0, θ1, θ2, J)` of the exact design for `(K, δ)`, none where
/// that design's `|θ0|` exceeds `limit`.
fn along_constraint(
    tl: &TwoLink,
    stiffness: f64,
    delta: f64,
    limit: Option<f64>,
    opts: &ContinuationOptions,
) -> Option<(f64, f64, f64, f64)> {
    let theta0 = exact_theta0(tl, stiffness, delta, opts).filter(|t| limit.is_none_or(|l| t.abs() <= l))?;
    let sol = general_solution(tl, stiffness, theta0, opts);
    let theta1 = sol.passive.status.is_stable().then(|| sol.passive.state.theta[0])?;
    let theta2 = sol.loaded.filter(|l| l.status.is_stable()).map(|l| l.state.theta[0])?;
    Some((theta0, theta1, theta2, tl.strain_energy(theta1, theta0, stiffness)))
}

/// Solves eq. (12) in its one remaining freedom: for each `K` the constraint fixes `θ0`
/// ([`exact_theta0`]), so `J` is minimised over `log K` in the bounds — a scan of 41 points, then
/// golden sections around the best (interior), or bisection of the stability edge when the best
/// point's neighbour has no design. `None` when no `K` in the bounds has a design.
pub fn optimum(tl: &TwoLink, delta: f64, bounds: (f64, f64), opts: &ContinuationOptions) -> Option<TwoLinkOptimum> {
    optimum_within(tl, delta, bounds, None, opts)
}

/// [`optimum`] with the design angle also bounded, `|θ0| ≤ theta0_limit` (rad): Sec. 5's bounds on
/// the N-link problem, `|θ0| ≤ θ0_max` and the middle node's height `L sin θ0 ≤ Y_max`, as one
/// limit. Where the limit stops the descent the optimum is [`OptimumPlace::AngleBound`].
pub fn optimum_within(
    tl: &TwoLink,
    delta: f64,
    bounds: (f64, f64),
    theta0_limit: Option<f64>,
    opts: &ContinuationOptions,
) -> Option<TwoLinkOptimum> {
    let mut evaluations = 0usize;
    let mut j = |k: f64| {
        evaluations += 1;
        along_constraint(tl, k, delta, theta0_limit, opts).map(|v| v.3)
    };
    let (lo, hi) = (bounds.0.ln(), bounds.1.ln());
    const SCAN: usize = 41;
    let grid: Vec<f64> = (0..SCAN).map(|i| lo + (hi - lo) * i as f64 / (SCAN - 1) as f64).collect();
    let values: Vec<Option<f64>> = grid.iter().map(|&g| j(g.exp())).collect();
    let best = (0..SCAN)
        .filter(|&i| values[i].is_some())
        .min_by(|&a, &b| values[a].unwrap_or(f64::INFINITY).total_cmp(&values[b].unwrap_or(f64::INFINITY)))?;
    let feasible = |i: usize| values.get(i).is_some_and(Option::is_some);
    let (stiffness, place) = if best + 1 < SCAN && !feasible(best + 1) || best > 0 && !feasible(best - 1) {
        // The design ends between `best` and its neighbour: bisect the edge to 1e-10 in log K.
        let (mut inside, mut outside) = if best + 1 < SCAN && !feasible(best + 1) {
            (grid[best], grid[best + 1])
        } else {
            (grid[best], grid[best - 1])
        };
        while (outside - inside).abs() > 1e-10 {
            let mid = 0.5 * (inside + outside);
            if j(mid.exp()).is_some() {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        // Which side ended it: the angle limit (the design beyond exists but leans too far) or
        // stability (none beyond).
        let beyond = exact_theta0(tl, outside.exp(), delta, opts);
        let place = match (theta0_limit, beyond) {
            (Some(l), Some(t)) if t.abs() > l => OptimumPlace::AngleBound,
            _ => OptimumPlace::StabilityEdge,
        };
        (inside.exp(), place)
    } else if best == 0 {
        (bounds.0, OptimumPlace::LowerBound)
    } else if best == SCAN - 1 {
        (bounds.1, OptimumPlace::UpperBound)
    } else {
        // Golden sections on [grid[best − 1], grid[best + 1]] to 1e-10 in log K.
        let ratio = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (grid[best - 1], grid[best + 1]);
        let mut c = b - ratio * (b - a);
        let mut d = a + ratio * (b - a);
        let (mut fc, mut fd) = (j(c.exp()).unwrap_or(f64::INFINITY), j(d.exp()).unwrap_or(f64::INFINITY));
        while b - a > 1e-10 {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - ratio * (b - a);
                fc = j(c.exp()).unwrap_or(f64::INFINITY);
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + ratio * (b - a);
                fd = j(d.exp()).unwrap_or(f64::INFINITY);
            }
        }
        ((0.5 * (a + b)).exp(), OptimumPlace::Interior)
    };
    let (theta0, theta1, theta2, objective) = along_constraint(tl, stiffness, delta, theta0_limit, opts)?;
    let lambda = tl.multiplier_eq20(theta0, stiffness, theta1, theta2);
    let (dl_dk, dl_dtheta0) = tl.lagrangian_gradient(theta0, stiffness, theta1, theta2, lambda);
    let (dj_dk, dj_dtheta0) = tl.lagrangian_gradient(theta0, stiffness, theta1, theta2, 0.0);
    let h = 1e-4 * stiffness;
    let dl_dk_central_difference = along_constraint(tl, stiffness + h, delta, theta0_limit, opts)
        .zip(along_constraint(tl, stiffness - h, delta, theta0_limit, opts))
        .map(|(p, m)| (p.3 - m.3) / (2.0 * h));
    Some(TwoLinkOptimum {
        delta,
        bounds,
        theta0_limit,
        place,
        stiffness,
        theta0,
        theta1,
        theta2,
        objective,
        lambda,
        dl_dk,
        dl_dtheta0,
        dl_dk_central_difference,
        dj_dk,
        dj_dtheta0,
        evaluations: evaluations + 3,
    })
}
