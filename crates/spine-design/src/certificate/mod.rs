//! Second-order certificate of an eq. (33) optimum: is the first-order point Ipopt returned a
//! local minimum?
//!
//! At a KKT point `x*` with multipliers `λ*`, let `A` be the strictly active constraints (the
//! equalities, the equilibrium rows, the bounds whose multiplier is not negligible:
//! [`crate::optimality::active_set::ActiveSet`]) and `Z` an orthonormal basis of their null space on the free
//! variables. `H` is the Hessian of the Lagrangian. Then (Nocedal & Wright, Thms. 12.5–12.6):
//!
//! The second-order conditions are about the **critical cone**: directions `d` with `A d = 0` that
//! move each weakly active bound (multiplier and gap both negligible) only to its feasible side.
//! With `m` the smallest `dᵀHd` over the cone's unit directions:
//!
//! * `m > 0` ⇒ **strict local minimum** (second-order sufficiency);
//! * `m < 0` ⇒ **not a minimum**: the minimising `d` is a feasible direction (to second order) along
//!   which `J` decreases ([`NegativeCurvature`]);
//! * `m = 0` (below [`ZERO_CURVATURE`] of the spectrum's scale) ⇒ **weak minimum**: the necessary
//!   conditions hold, sufficiency is not proven (a flat valley, e.g. a spring whose two links
//!   deflect alike).
//!
//! Without weakly active bounds the cone is the null space `Z` of the active rows and `m` the
//! smallest eigenvalue of `ZᵀHZ`. With `w` of them, `m`'s minimiser is an eigenvector of `ZᵀHZ` on
//! the face where the bounds it moves are released and the others held, so the `2^w` faces are
//! searched (`w ≤` [`MAX_WEAK`]).
//!
//! The eigenvalues of `ZᵀHZ` are computed densely up to [`MAX_DENSE_FREE`] free variables (one
//! null-space basis shared by every face: `cone`); above,
//! the inertia of the reduced KKT matrix `[H_FF A_Fᵀ; A_F 0]` (one sparse `LDLᵀ`, the factorisation
//! of [`crate::optimality`] that [`crate::sensitivity`] uses too) decides: `free` positive and one negative eigenvalue per active row
//! is `ZᵀHZ ≻ 0` (Gould 1985) with the weak bounds released (sufficient); more negative ones than
//! independent rows with them held and `H` shifted by `ZERO_CURVATURE · scale` is a curvature
//! below the dense search's own zero on the cone (not a minimum). Unshifted, the inertia counted
//! round-off as negative curvature: the peers case at N = 500 (cold, 2 031 free variables) has
//! 115 negative eigenvalues of `ZᵀHZ`, the lowest −5.3e-5, which the dense search (tried there at
//! 4 s) calls zero. The inertia is reported at every size.
//!
//! [`crate::solve::settle`] turns a solver's run into a reported optimum: it certifies the run, re-solves it
//! tightly or leaves it along a direction of negative curvature when the certificate does not say
//! `strict_minimum`, and reports the minimum it reaches with the points it left.

mod cone;

use crate::full_space::Multipliers;
use crate::layout::Layout;
use crate::optimality::active_set::{ActiveSet, Bound, MAX_WEAK};
use crate::optimality::system::{with_weak, ActiveSystem, Matrices};
use crate::problem::DesignProblem;
use cone::cone_minimum;
use serde::{Deserialize, Serialize};

/// Most free variables for which `ZᵀHZ` is formed and its eigenvalues computed densely (`cone`:
/// 0.08 s for the whole certificate at 611 free variables and one face, the peers case at
/// N = 150); above, the inertia alone decides. The null space's basis costs `free² · rows`
/// (Householder, unblocked): 4.2 s at 2 031 free variables (N = 500).
pub const MAX_DENSE_FREE: usize = 600;

/// Most dense work for the critical cone's search, in units of `free³` per face (`2^w` faces for
/// `w` weakly active bounds): four faces at [`MAX_DENSE_FREE`]. Above, the inertia decides.
/// Measured: the rod of `spine_continuum::design` at `N = 100` (450 free variables, 8 weak bounds)
/// took 24 s in 256 dense eigensolves of the free variables' size before this budget. The faces
/// now cost an eigensolve of the null space's size each (`cone`), so the budget is generous;
/// it is kept so that the same points are certified densely as before.
pub const MAX_DENSE_WORK: f64 = 4.0 * (MAX_DENSE_FREE * MAX_DENSE_FREE * MAX_DENSE_FREE) as f64;

/// A bound at zero gap is weakly active for the certificate when its multiplier is below this
/// fraction of the terms it balances: a multiplier above protects the bound to first order
/// (moving off it raises `J` by `z·gap`), however small beside the sensitivities' threshold
/// ([`crate::optimality::active_set::WEAK_MULTIPLIER`], which asks whether a derivative may
/// switch sides).
pub const CERTIFICATE_WEAK_MULTIPLIER: f64 = 1e-7;

/// A curvature below this fraction of the Hessian's scale (its largest entry on the free
/// variables) counts as zero: at Ipopt's default tolerance the multipliers, and with them `H`, are
/// accurate to about 1e-8 relative, and a bound whose gap is not yet resolved leaves a nearly flat
/// direction (J is nearly linear in a stiffness at its bound).
pub const ZERO_CURVATURE: f64 = 1e-8;

/// What the certificate proves about a first-order point of eq. (33).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MinimumStatus {
    /// Second-order sufficiency holds: positive curvature on the null space of the active
    /// constraints.
    StrictMinimum,
    /// No negative curvature on the critical face, but a zero eigenvalue (a flat valley, e.g. a
    /// spring whose links deflect alike) or a negative one only off the face of the weakly
    /// active bounds: a minimum to second order, not a proven strict one.
    WeakMinimum,
    /// Negative curvature on the critical face: a saddle or a maximum along a feasible direction.
    NotAMinimum,
}

impl MinimumStatus {
    /// The name written in results (`strict_minimum`, `weak_minimum`, `not_a_minimum`).
    pub fn name(self) -> &'static str {
        match self {
            Self::StrictMinimum => "strict_minimum",
            Self::WeakMinimum => "weak_minimum",
            Self::NotAMinimum => "not_a_minimum",
        }
    }
}

impl std::fmt::Display for MinimumStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The second-order certificate of one point, with the numbers that show it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    pub status: MinimumStatus,
    /// Variables fixed by a strictly active bound, free variables, strictly active rows (the
    /// equalities included), weakly active bounds.
    pub fixed_variables: usize,
    pub free_variables: usize,
    pub active_rows: usize,
    pub weakly_active: usize,
    /// Dimension of the null space of the independent active rows on the free variables (0: the
    /// active constraints fix the point, a vertex; with strict complementarity a strict minimum).
    pub null_space_dimension: usize,
    /// Inertia `[positive, negative, zero]` of the reduced KKT matrix `[H_FF A_Fᵀ; A_F 0]`
    /// (weakly active bounds free); a strict minimum has `[free, active_rows, 0]` (`None` where
    /// the factorisation failed).
    pub reduced_kkt_inertia: Option<[usize; 3]>,
    /// The smallest curvature `dᵀHd` over unit directions `d` of the critical cone (the null space
    /// of the active rows, moving each weakly active bound only to its feasible side), in the
    /// NLP's variables (`θ` in rad, `K/C_K`, `λ` in N, heights in m), and the largest magnitude
    /// of an entry of `H` on the free variables (the scale [`ZERO_CURVATURE`] is taken of). The
    /// curvature is `None` above [`MAX_DENSE_FREE`] free variables, [`MAX_WEAK`]
    /// weak bounds or [`MAX_DENSE_WORK`] (the inertia decides there, against the same threshold),
    /// and for a vertex (no direction); the scale is given at every size.
    pub smallest_curvature: Option<f64>,
    pub curvature_scale: Option<f64>,
    /// `J` at the point certified, J, and whether that point is the run's own (`run`) or the
    /// run re-solved tightly from it (`polished`, `J` within 1e-6 relative).
    pub objective: f64,
    pub point: CertifiedPoint,
}

/// Which point a certificate was computed at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CertifiedPoint {
    /// The solver's own solution and multipliers.
    Run,
    /// The solution re-solved from itself with `tol` 1e-12 ([`crate::solve::polish::polish`]).
    Polished,
}

/// A direction of negative curvature in the full-space variables (layout order), unit length,
/// oriented into the feasible side of every weakly active bound it moves.
pub struct NegativeCurvature {
    pub direction: Vec<f64>,
    pub curvature: f64,
}

/// The largest magnitude of an entry of `H` on the variables `fixed` leaves free: the scale
/// [`ZERO_CURVATURE`] is taken of, by the dense search and the inertia alike.
fn hessian_scale(n: usize, fixed: &[Bound], matrices: &Matrices) -> f64 {
    let mut free = vec![true; n];
    fixed.iter().for_each(|b| free[b.index] = false);
    let entries = matrices.hessian_pattern.iter().zip(&matrices.hessian);
    entries.filter(|((a, b), _)| free[*a] && free[*b]).fold(0.0f64, |m, (_, v)| m.max(v.abs()))
}

/// Whether `ZᵀHZ` has an eigenvalue below `threshold` (< 0) on the critical cone's smallest face,
/// every weakly active bound held (its directions are in the cone): by the inertia of the
/// reduced KKT matrix with `H − threshold·I`, whose eigenvalues on the null space are those of
/// `ZᵀHZ` shifted (`Z` orthonormal): more negative ones than independent active rows (Gould
/// 1985). `None` where the factorisation fails.
fn curvature_below(matrices: &Matrices, layout: Layout, set: &ActiveSet, threshold: f64) -> Option<bool> {
    let n = layout.num_variables();
    let mut shifted = Matrices {
        hessian_pattern: matrices.hessian_pattern.clone(),
        hessian: matrices.hessian.clone(),
        jacobian_pattern: matrices.jacobian_pattern.clone(),
        jacobian: matrices.jacobian.clone(),
    };
    shifted.hessian_pattern.extend((0..n).map(|i| (i, i)));
    shifted.hessian.extend(std::iter::repeat_n(-threshold, n));
    let (fixed, rows) = with_weak(set, &set.weak_variables, &set.weak_rows);
    let held = ActiveSystem::new(&shifted, layout, fixed, rows);
    held.kkt.as_ref().map(|k| k.inertia.negative > k.rows.len())
}

/// The certificate of a full-space point `x` (layout order) with Ipopt's `multipliers`, and the
/// direction of the smallest curvature where the status is `not_a_minimum` (negative) or
/// `weak_minimum` (zero within tolerance).
pub fn certify(
    problem: &DesignProblem,
    layout: Layout,
    x: &[f64],
    multipliers: &Multipliers,
    point: CertifiedPoint,
) -> (Certificate, Option<NegativeCurvature>) {
    let (at, matrices) = Matrices::at(problem, layout, x, &multipliers.constraints);
    let set = ActiveSet::identify_with(x, &at, &matrices.jacobian_pattern, multipliers, CERTIFICATE_WEAK_MULTIPLIER);
    let n = layout.num_variables();
    let weak = set.weak_variables.len() + set.weak_rows.len();
    // The inertia with the weakly active bounds free (a superset of the critical cone).
    let system = ActiveSystem::new(&matrices, layout, set.variables.clone(), set.rows.clone());
    let inertia = system.kkt.as_ref().map(|k| [k.inertia.positive, k.inertia.negative, k.inertia.zero]);
    let free = (n - set.variables.len()) as f64;
    let affordable = weak <= MAX_WEAK && (1u64 << weak) as f64 * free.powi(3) <= MAX_DENSE_WORK;
    let cone = affordable.then(|| cone_minimum(n, &set, &matrices)).flatten();
    let (status, negative, smallest, scale) = match cone {
        Some((minimum, scale, direction)) => {
            let zero = ZERO_CURVATURE * scale.max(f64::MIN_POSITIVE);
            let status = if minimum > zero {
                MinimumStatus::StrictMinimum
            } else if minimum < -zero {
                MinimumStatus::NotAMinimum
            } else {
                MinimumStatus::WeakMinimum
            };
            // The direction of the smallest curvature: negative (not a minimum), or zero within
            // tolerance (a weak minimum, probed along it: higher-order terms may descend).
            let negative = direction
                .filter(|_| status != MinimumStatus::StrictMinimum)
                .map(|direction| NegativeCurvature { direction, curvature: minimum });
            (status, negative, minimum.is_finite().then_some(minimum), Some(scale))
        }
        None => {
            // Too large (or too many weak bounds) for the dense search: the inertia decides. With
            // the weakly active bounds free, `ZᵀHZ ≻ 0` proves a strict minimum; with them held
            // (the cone's smallest face), a curvature below `−ZERO_CURVATURE · scale` proves it is
            // not one (`curvature_below`), the dense search's own threshold.
            let scale = hessian_scale(n, &set.variables, &matrices);
            let status = if system.certified().is_some() {
                MinimumStatus::StrictMinimum
            } else if curvature_below(&matrices, layout, &set, -ZERO_CURVATURE * scale) == Some(true) {
                MinimumStatus::NotAMinimum
            } else {
                MinimumStatus::WeakMinimum
            };
            (status, None, None, Some(scale))
        }
    };
    let independent_rows = set.rows.len() - system.dependent.len();
    let certificate = Certificate {
        status,
        fixed_variables: set.variables.len(),
        free_variables: n - set.variables.len(),
        active_rows: set.rows.len(),
        null_space_dimension: (n - set.variables.len()).saturating_sub(independent_rows),
        weakly_active: weak,
        reduced_kkt_inertia: inertia,
        smallest_curvature: smallest,
        curvature_scale: scale,
        objective: at.objective,
        point,
    };
    (certificate, negative)
}

/// The scaled family of `n` links solved from its arch start with the default settings: a
/// solver's run for the certificate's tests.
#[cfg(test)]
pub(crate) fn solved_scaled_family(n: usize) -> (DesignProblem, crate::solver_run::SolverRun) {
    use crate::fixtures::{arch_start, scaled_family};
    let problem = scaled_family(n);
    let s = n as f64 / 10.0;
    let start = arch_start(n, 0.3, 1e3 * s * s);
    let settings = crate::settings::SolverSettings::default();
    let formulation = crate::settings::Formulation::Full;
    let run = crate::solve::run::run_solver(&problem, &start, formulation, &settings, &mut |_| true).expect("solves");
    (problem, run)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shifted inertia against the dense search on the face with every weak bound held, at a
    /// solved point with a null space: an eigenvalue below the threshold is found exactly when
    /// the dense minimum is below it.
    #[test]
    fn the_shifted_inertia_finds_the_dense_minimum_of_the_held_face() {
        let (problem, run) = solved_scaled_family(20);
        let (layout, x) = run.point(&problem).expect("a full-space point");
        let multipliers = run.multipliers.as_ref().expect("multipliers");
        let (at, matrices) = Matrices::at(&problem, layout, &x, &multipliers.constraints);
        let set =
            ActiveSet::identify_with(&x, &at, &matrices.jacobian_pattern, multipliers, CERTIFICATE_WEAK_MULTIPLIER);
        let (variables, rows) = with_weak(&set, &set.weak_variables, &set.weak_rows);
        let held = ActiveSet { variables, rows, weak_variables: Vec::new(), weak_rows: Vec::new(), ..set.clone() };
        let n = layout.num_variables();
        let (minimum, scale, _) = cone_minimum(n, &held, &matrices).expect("small enough");
        assert!(minimum.is_finite() && scale > 0.0, "a face with directions: {minimum}, {scale}");
        for (offset, below) in [(1e-6, true), (-1e-6, false), (1e-3, true), (-1e-3, false)] {
            let threshold = minimum + offset * scale;
            assert_eq!(curvature_below(&matrices, layout, &set, threshold), Some(below), "{minimum} {offset}");
        }
    }
}
