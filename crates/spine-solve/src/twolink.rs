//! The exact two-link design of Sec. 3, found with the general `N`-link code.
//!
//! For a given spring `K` and end displacement `δ`, the design angle `θ0` solves eqs. (8) and (9).
//! Here it is found by a bracketed root search in `θ0` whose every evaluation runs the general
//! equilibrium solver on the chain `N = 2`, `K = [0, K, 0]`, spans `a = L cos θ0` (so the link length
//! stays `L`, as in the paper's Sec. 3), `P_Y` at the middle node and `P_X` at the slider.

use crate::equilibrium::{solve_static, StaticSolution};
use crate::options::ContinuationOptions;
use crate::problem::StaticProblem;
use spine_model::twolink::{SmallDeflection, TwoLink};
use spine_model::{Chain, Design, NodalLoads, Structure};

/// The general chain and loads that realise the Sec. 3 problem for design angle `theta0`.
pub fn general_problem(tl: &TwoLink, stiffness: f64, theta0: f64) -> StaticProblem {
    let span = tl.length * theta0.cos();
    let chain = Chain { spans: vec![span; 2], masses: vec![0.0; 2], gravity: 0.0 };
    let design = Design { theta0: vec![theta0, -theta0], stiffness: vec![0.0, stiffness, 0.0] };
    let passive = NodalLoads { p_x: vec![0.0; 3], p_y: vec![0.0, tl.p_y, 0.0] };
    let actuation = NodalLoads { p_x: vec![0.0, 0.0, tl.p_x], p_y: vec![0.0; 3] };
    StaticProblem { structure: Structure { chain, passive, actuation }, design }
}

/// Solves the general problem for design angle `theta0`.
pub fn general_solution(tl: &TwoLink, stiffness: f64, theta0: f64, opts: &ContinuationOptions) -> StaticSolution {
    solve_static(&general_problem(tl, stiffness, theta0), opts)
}

/// The exact `θ0` for `(K, δ)`, or `None` when no sign change of `δ(θ0) − δ` is found between the
/// zero-moment angle `θ*` and `π/2` (where the link would stand upright). Returns the first root
/// above `θ*` (the branch of eq. (10)), converged to `|Δθ0| ≤ 1e-14`.
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
        let b = start + (std::f64::consts::FRAC_PI_2 - 1e-6 - start) * (k as f64 / steps as f64).powi(2);
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

/// One row of the two-link study: closed forms beside the exact design for one `δ`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StudyRow {
    /// Prescribed end displacement, m.
    pub delta: f64,
    /// Exact `θ0` (rad) from the general solver, `None` if no root was found.
    pub theta0_exact: Option<f64>,
    /// Eq. (10) as printed, rad.
    pub theta0_eq10_printed: f64,
    /// Eq. (10) on the right branch, rad.
    pub theta0_eq10: f64,
    /// Eq. (10) consistent with eq. (11) to first order, rad.
    pub theta0_first_order: f64,
    /// Eq. (11) evaluated at the exact `θ0`, N·m/rad (compare with the given `K`).
    pub stiffness_eq11: Option<f64>,
    /// `θ1` at the exact design, rad.
    pub theta1: Option<f64>,
    /// `R` as printed in eq. (17) and corrected, at the exact design.
    pub ratio_eq17_printed: Option<f64>,
    pub ratio: Option<f64>,
}

/// Least-squares slopes of `log error` against `log |δ|` over the three smallest `|δ|` of the study
/// (the asymptotic regime): the observed orders of the closed forms.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StudyOrders {
    pub eq10: Option<f64>,
    pub first_order: Option<f64>,
    pub eq11_relative: Option<f64>,
}

/// The closed forms of Sec. 3 beside the exact solution for each `δ`, with observed error orders;
/// eq. (12) solved for each upper stiffness bound; eq. (26) against the exact small deflections.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Study {
    pub zero_moment_angle: f64,
    pub rows: Vec<StudyRow>,
    pub orders: StudyOrders,
    /// Eq. (12) for each upper bound of [`OptimisationSpec::upper_bounds`] (`None`: no design in
    /// those bounds).
    pub optima: Vec<Option<TwoLinkOptimum>>,
    pub small_deflection: Option<SmallDeflectionStudy>,
}

/// What a Sec. 3 study computes.
#[derive(Clone, Debug, PartialEq)]
pub struct StudySpec {
    /// The spring `K` of the closed-form table, N·m/rad.
    pub stiffness: f64,
    /// End displacements of the closed-form table, m.
    pub deltas: Vec<f64>,
    pub optimisation: Option<OptimisationSpec>,
    pub small_deflection: Option<SmallDeflectionSpec>,
}

/// Eq. (12) at `delta` with `lower_bound ≤ K ≤ upper` for each of `upper_bounds` (N·m/rad).
#[derive(Clone, Debug, PartialEq)]
pub struct OptimisationSpec {
    pub delta: f64,
    pub lower_bound: f64,
    pub upper_bounds: Vec<f64>,
}

/// Eq. (26) for `system` with its loads scaled by each of `scales`.
#[derive(Clone, Debug, PartialEq)]
pub struct SmallDeflectionSpec {
    pub system: SmallDeflection,
    pub scales: Vec<f64>,
}

/// Runs the two-link study of `spec`.
pub fn study(tl: &TwoLink, spec: &StudySpec, opts: &ContinuationOptions) -> Study {
    let stiffness = spec.stiffness;
    let optima = spec.optimisation.as_ref().map_or_else(Vec::new, |o| {
        o.upper_bounds.iter().map(|&upper| optimum(tl, o.delta, (o.lower_bound, upper), opts)).collect()
    });
    let small_deflection = spec.small_deflection.as_ref().map(|s| small_deflection_study(&s.system, &s.scales, opts));
    let rows: Vec<StudyRow> = spec
        .deltas
        .iter()
        .map(|&delta| {
            let exact = exact_theta0(tl, stiffness, delta, opts);
            let theta1 = exact.and_then(|t0| {
                let sol = general_solution(tl, stiffness, t0, opts);
                sol.passive.status.is_stable().then(|| sol.passive.state.theta[0])
            });
            let pair = exact.zip(theta1);
            StudyRow {
                delta,
                theta0_exact: exact,
                theta0_eq10_printed: tl.theta0_eq10_printed(stiffness, delta),
                theta0_eq10: tl.theta0_eq10(stiffness, delta),
                theta0_first_order: tl.theta0_first_order(stiffness, delta),
                stiffness_eq11: exact.map(|t0| tl.stiffness_eq11(t0, delta)),
                theta1,
                ratio_eq17_printed: pair.map(|(t0, t1)| TwoLink::ratio_eq17_printed(t1, t0, stiffness)),
                ratio: pair.map(|(t0, t1)| TwoLink::ratio(t1, t0, stiffness)),
            }
        })
        .collect();
    let fit = |err: &dyn Fn(&StudyRow) -> Option<f64>| observed_order(&rows, |r| r.delta.abs(), err);
    let orders = StudyOrders {
        eq10: fit(&|r| r.theta0_exact.map(|t| (r.theta0_eq10 - t).abs())),
        first_order: fit(&|r| r.theta0_exact.map(|t| (r.theta0_first_order - t).abs())),
        eq11_relative: fit(&|r| r.stiffness_eq11.map(|k| (k - stiffness).abs() / stiffness)),
    };
    Study { zero_moment_angle: tl.zero_moment_angle(), rows, orders, optima, small_deflection }
}

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
}

impl OptimumPlace {
    /// As a report says it.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Interior => "interior",
            Self::LowerBound => "at the lower bound",
            Self::UpperBound => "at the upper bound",
            Self::StabilityEdge => "at the stability edge",
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
    /// The same by central differences of `J(K, θ0(K))` along the constraint (the exact `θ0(K)`
    /// of [`exact_theta0`]), `None` at a stability edge (one side has no design).
    pub dl_dk_central_difference: Option<f64>,
    /// Eqs. (13), (14) at the optimum: the objective's own partials, J·rad/(N·m) and J/rad.
    pub dj_dk: f64,
    pub dj_dtheta0: f64,
    /// Evaluations of `J(K)` (each a root search of the general `N = 2` solver).
    pub evaluations: usize,
}

/// `J(K)` along the constraint: `(θ0, θ1, θ2, J)` of the exact design for `(K, δ)`.
fn along_constraint(
    tl: &TwoLink,
    stiffness: f64,
    delta: f64,
    opts: &ContinuationOptions,
) -> Option<(f64, f64, f64, f64)> {
    let theta0 = exact_theta0(tl, stiffness, delta, opts)?;
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
    let mut evaluations = 0usize;
    let mut j = |k: f64| {
        evaluations += 1;
        along_constraint(tl, k, delta, opts).map(|v| v.3)
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
        (inside.exp(), OptimumPlace::StabilityEdge)
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
    let (theta0, theta1, theta2, objective) = along_constraint(tl, stiffness, delta, opts)?;
    let lambda = tl.multiplier_eq20(theta0, stiffness, theta1, theta2);
    let (dl_dk, _) = tl.lagrangian_gradient(theta0, stiffness, theta1, theta2, lambda);
    let (dj_dk, dj_dtheta0) = tl.lagrangian_gradient(theta0, stiffness, theta1, theta2, 0.0);
    let h = 1e-4 * stiffness;
    let dl_dk_central_difference = along_constraint(tl, stiffness + h, delta, opts)
        .zip(along_constraint(tl, stiffness - h, delta, opts))
        .map(|(p, m)| (p.3 - m.3) / (2.0 * h));
    Some(TwoLinkOptimum {
        delta,
        bounds,
        place,
        stiffness,
        theta0,
        theta1,
        theta2,
        objective,
        lambda,
        dl_dk,
        dl_dk_central_difference,
        dj_dk,
        dj_dtheta0,
        evaluations: evaluations + 3,
    })
}

/// One load scale of the eq. (26) check: the small-deflection `Δθ` against the exact one.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SmallDeflectionRow {
    /// Both loads multiplied by this.
    pub scale: f64,
    /// Exact `θ2 − θ0` (both loads), rad, `None` when the general solver found no stable state.
    pub exact: Option<[f64; 2]>,
    /// Relative error `‖Δθ(26) − Δθ‖ / ‖Δθ‖` of eq. (26) corrected and as printed.
    pub error: Option<f64>,
    pub error_printed: Option<f64>,
}

/// Eq. (26) against the exact equilibria as the loads shrink, with the observed orders
/// (slopes of `log error` against `log scale` over the three smallest scales): 1 for a first-order
/// small-deflection model, 0 for one that does not converge.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SmallDeflectionStudy {
    pub system: SmallDeflection,
    pub rows: Vec<SmallDeflectionRow>,
    pub order: Option<f64>,
    pub order_printed: Option<f64>,
}

/// The observed order of an error: the slope of `ln error` against `ln size` over the three rows
/// of smallest `size` (the asymptotic regime; rows without a positive error are left out).
fn observed_order<R>(rows: &[R], size: impl Fn(&R) -> f64, error: &dyn Fn(&R) -> Option<f64>) -> Option<f64> {
    let mut smallest: Vec<&R> = rows.iter().collect();
    smallest.sort_by(|a, b| size(a).total_cmp(&size(b)));
    let points: Vec<(f64, f64)> = smallest.into_iter().take(3).filter_map(|r| error(r).map(|e| (size(r), e))).collect();
    slope(&points)
}

/// Least-squares slope of `ln y` against `ln x`.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0).map(|p| (p.0.ln(), p.1.ln())).collect();
    if pts.len() < 2 {
        return None;
    }
    let m = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / m, pts.iter().map(|p| p.1).sum::<f64>() / m);
    let num: f64 = pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = pts.iter().map(|(x, _)| (x - mx) * (x - mx)).sum();
    (den > 0.0).then(|| num / den)
}

/// Eq. (26) for `system` with both loads scaled by each of `scales`, against the general `N = 2`
/// solver (spans `L_i cos θ0,i`, springs `[K1, K2, 0]`).
pub fn small_deflection_study(
    system: &SmallDeflection,
    scales: &[f64],
    opts: &ContinuationOptions,
) -> SmallDeflectionStudy {
    let rows: Vec<SmallDeflectionRow> = scales
        .iter()
        .map(|&scale| {
            let scaled = SmallDeflection { p_y2: system.p_y2 * scale, p_x3: system.p_x3 * scale, ..*system };
            let spans = [0, 1].map(|i| system.lengths[i] * system.theta0[i].cos());
            let problem = StaticProblem {
                structure: Structure {
                    chain: Chain { spans: spans.to_vec(), masses: vec![0.0; 2], gravity: 0.0 },
                    passive: NodalLoads { p_x: vec![0.0; 3], p_y: vec![0.0, scaled.p_y2, 0.0] },
                    actuation: NodalLoads { p_x: vec![0.0, 0.0, scaled.p_x3], p_y: vec![0.0; 3] },
                },
                design: Design {
                    theta0: system.theta0.to_vec(),
                    stiffness: vec![system.stiffness[0], system.stiffness[1], 0.0],
                },
            };
            let sol = solve_static(&problem, opts);
            let exact = sol
                .loaded
                .filter(|l| l.status.is_stable())
                .map(|l| [l.state.theta[0] - system.theta0[0], l.state.theta[1] - system.theta0[1]]);
            let error = |printed: bool| {
                let (model, _) = scaled.delta_theta(printed)?;
                let e = exact?;
                Some((model[0] - e[0]).hypot(model[1] - e[1]) / e[0].hypot(e[1]))
            };
            SmallDeflectionRow { scale, exact, error: error(false), error_printed: error(true) }
        })
        .collect();
    let order = |pick: &dyn Fn(&SmallDeflectionRow) -> Option<f64>| observed_order(&rows, |r| r.scale, pick);
    SmallDeflectionStudy {
        system: *system,
        order: order(&|r| r.error),
        order_printed: order(&|r| r.error_printed),
        rows,
    }
}
