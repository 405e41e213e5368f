//! The exact two-link design of Sec. 3, found with the general `N`-link code.
//!
//! For a given spring `K` and end displacement `δ`, the design angle `θ0` solves eqs. (8) and (9).
//! Here it is found by a bracketed root search in `θ0` whose every evaluation runs the general
//! equilibrium solver on the chain `N = 2`, `K = [0, K, 0]`, spans `a = L cos θ0` (so the link length
//! stays `L`, as in the paper's Sec. 3), `P_Y` at the middle node and `P_X` at the slider.

mod optimum;

pub use optimum::{optimum, optimum_within, OptimumPlace, TwoLinkOptimum};

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
    /// those bounds), then, with [`OptimisationSpec::theta0_limit`], again with that limit for each
    /// upper bound whose optimum lies beyond it (within it, the optimum is the same point).
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
    /// Sec. 5's bounds as a limit on `|θ0|`, rad (`min(θ0_max, asin(Y_max / L))`), when given.
    pub theta0_limit: Option<f64>,
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
        let mut optima: Vec<_> =
            o.upper_bounds.iter().map(|&upper| optimum(tl, o.delta, (o.lower_bound, upper), opts)).collect();
        if let Some(limit) = o.theta0_limit {
            for (k, &upper) in o.upper_bounds.iter().enumerate() {
                if optima[k].as_ref().is_none_or(|f| f.theta0.abs() > limit) {
                    optima.push(optimum_within(tl, o.delta, (o.lower_bound, upper), Some(limit), opts));
                }
            }
        }
        optima
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
    /// Eqs. (27)–(30) at the system's design against the exact gradient (erratum E10).
    pub gradients: Option<SmallDeflectionGradients>,
}

/// Eqs. (27)–(30) at one design, with the multipliers that make the exact gradient stationary in
/// both angles: as printed, exact (forward AD through eq. (26)), and the term (27), (28) leave
/// out; `(∂ℒ/∂K1, ∂ℒ/∂K2, ∂ℒ/∂θ0,1, ∂ℒ/∂θ0,2)`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SmallDeflectionGradients {
    pub multipliers: [f64; 2],
    pub printed: [f64; 4],
    pub exact: [f64; 4],
    pub missing: [f64; 2],
    /// The size of the terms that cancel in the angle components: `max |∂J/∂θ0,i|`.
    pub angle_scale: f64,
}

impl SmallDeflectionGradients {
    /// The gradients of `system` (`None` where eq. (26) or the multipliers' system is singular).
    pub fn of(system: &SmallDeflection) -> Option<Self> {
        let multipliers = system.angle_stationary_multipliers()?;
        Some(Self {
            multipliers,
            printed: system.gradient_eqs_27_30(multipliers)?,
            exact: system.lagrangian_gradient(0.0, multipliers)?,
            missing: system.missing_stiffness_terms()?,
            angle_scale: system.lagrangian_gradient(0.0, [0.0, 0.0])?[2..].iter().fold(0.0, |m, g| m.max(g.abs())),
        })
    }

    /// The largest relative gap between `printed` (with `missing` added to (27), (28) when
    /// `corrected`) and `exact`: relative to `|exact|` for the springs, to [`Self::angle_scale`]
    /// for the angles (where `exact` is zero).
    pub fn gap(&self, corrected: bool) -> f64 {
        (0..4)
            .map(|i| {
                let add = if corrected && i < 2 { self.missing[i] } else { 0.0 };
                let scale = if i < 2 { self.exact[i].abs() } else { self.angle_scale }.max(f64::MIN_POSITIVE);
                ((self.printed[i] + add) - self.exact[i]).abs() / scale
            })
            .fold(0.0, f64::max)
    }
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
        gradients: SmallDeflectionGradients::of(system),
        rows,
    }
}
