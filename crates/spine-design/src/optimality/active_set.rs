//! Which bounds hold at an optimum, read from the primal-dual solution: a bound is active when
//! its multiplier exceeds its gap (at Ipopt's solution their product is the final barrier
//! parameter, so one of the two is small and the other is not), and weakly active (degenerate)
//! when both are negligible: the multiplier below [`WEAK_MULTIPLIER`] of the terms it balances in
//! its stationarity row (`|∂f/∂x_i| + Σ_r |J_ri λ_r|`; for a row, of the largest row multiplier)
//! and the gap below [`WEAK_GAP`] of `max(1, |bound|)`, or the gap below that and the multiplier
//! not larger than the gap (a bound in a flat valley: both at noise level). An interior-point solution resolves this
//! only to about `√μ` of the final barrier parameter: after the polishing solve (`tol` 1e-12) a
//! bound placed exactly at a free spring's optimum keeps a multiplier of 5e-4 of its terms, the
//! smallest strictly active stiffness bound of design5 3e-3.

use super::point::Evaluation;
use crate::full_space::Multipliers;
use serde::Serialize;

/// A multiplier below this fraction of the terms it balances, with a gap below [`WEAK_GAP`]
/// (module docs), makes a bound weakly active: strict complementarity fails there.
pub const WEAK_MULTIPLIER: f64 = 1e-3;
/// A gap below this of `max(1, |bound|)` counts as zero.
pub const WEAK_GAP: f64 = 1e-6;

/// At most this many weakly active bounds are enumerated (2^k systems): by the sensitivities for
/// one-sided derivatives, by the certificate for the faces of the critical cone.
pub const MAX_WEAK: usize = 8;

/// One side of a bound on a variable or a constraint row (`lower`, `upper`, `both` in JSON).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    Lower,
    Upper,
    /// An equality (a fixed variable or an equality row).
    Both,
}

impl std::fmt::Display for Side {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Lower => "lower",
            Self::Upper => "upper",
            Self::Both => "equality",
        })
    }
}

/// A bound that holds or nearly holds at the optimum.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bound {
    /// Variable index (layout order) or constraint row.
    pub index: usize,
    pub side: Side,
    /// Its multiplier's magnitude and its gap.
    pub multiplier: f64,
    pub gap: f64,
}

/// The active set at an optimum: bounds on variables and constraint rows, each active or weakly
/// active.
#[derive(Clone, Debug, Default)]
pub struct ActiveSet {
    pub variables: Vec<Bound>,
    pub rows: Vec<Bound>,
    /// Weakly active bounds (module docs), not in the two lists.
    pub weak_variables: Vec<Bound>,
    pub weak_rows: Vec<Bound>,
    /// The smallest multiplier of an active inequality bound and the smallest gap of an inactive
    /// one (`INFINITY` where there is none).
    pub smallest_active_multiplier: f64,
    pub smallest_inactive_gap: f64,
}

/// One inequality with its bounds, value, the magnitudes of its two multipliers and the scale of
/// what its multiplier balances.
struct Inequality {
    index: usize,
    value: f64,
    lower: f64,
    upper: f64,
    z_lower: f64,
    z_upper: f64,
    scale: f64,
    /// The multiplier, as a fraction of `scale`, below which a bound at zero gap is weak.
    weak: f64,
}

/// Classifies one inequality: active (`true`), weakly active (`false`) or inactive (`None`).
fn classify(q: Inequality) -> Option<(Bound, bool)> {
    if q.lower == q.upper {
        let bound = Bound { index: q.index, side: Side::Both, multiplier: (q.z_lower - q.z_upper).abs(), gap: 0.0 };
        return Some((bound, true));
    }
    let (gap_l, gap_u) = ((q.value - q.lower).max(0.0), (q.upper - q.value).max(0.0));
    let lower_side = gap_u.is_infinite() || (gap_l.is_finite() && gap_l * q.z_upper <= gap_u * q.z_lower);
    let (side, multiplier, gap, at) =
        if lower_side { (Side::Lower, q.z_lower, gap_l, q.lower) } else { (Side::Upper, q.z_upper, gap_u, q.upper) };
    if !gap.is_finite() {
        return None;
    }
    let bound = Bound { index: q.index, side, multiplier, gap };
    // A gap at zero with a multiplier that is negligible, or not even larger than that gap, is
    // degenerate: the second case is a bound in a flat valley (a spring whose links deflect alike,
    // whose stationarity terms are themselves near zero), which the relative test cannot see.
    let zero_gap = gap <= WEAK_GAP * at.abs().max(1.0);
    if zero_gap && (multiplier <= q.weak * q.scale || multiplier <= gap) {
        Some((bound, false))
    } else {
        (multiplier > gap).then_some((bound, true))
    }
}

impl ActiveSet {
    /// Reads the active set from the point's bounds and Ipopt's multipliers (`z_lower`, `z_upper`
    /// for the variables; the sign of `λ` for the rows: positive at an upper bound).
    pub(crate) fn identify(x: &[f64], at: &Evaluation, pattern: &[(usize, usize)], multipliers: &Multipliers) -> Self {
        Self::identify_with(x, at, pattern, multipliers, WEAK_MULTIPLIER)
    }

    /// [`ActiveSet::identify`] with `weak` in place of [`WEAK_MULTIPLIER`].
    pub(crate) fn identify_with(
        x: &[f64],
        at: &Evaluation,
        pattern: &[(usize, usize)],
        multipliers: &Multipliers,
        weak: f64,
    ) -> Self {
        let lambda = &multipliers.constraints;
        let mut terms: Vec<f64> = at.gradient.iter().map(|g| g.abs()).collect();
        for (&(r, c), &j) in pattern.iter().zip(&at.jacobian) {
            terms[c] += (j * lambda[r]).abs();
        }
        let largest_lambda = lambda.iter().fold(0.0f64, |m, l| m.max(l.abs()));
        let mut set = ActiveSet {
            smallest_active_multiplier: f64::INFINITY,
            smallest_inactive_gap: f64::INFINITY,
            ..Default::default()
        };
        for i in 0..x.len() {
            let (value, lower, upper) = (x[i], at.lower[i], at.upper[i]);
            let (z_lower, z_upper) = (multipliers.z_lower[i].abs(), multipliers.z_upper[i].abs());
            let found = classify(Inequality { index: i, value, lower, upper, z_lower, z_upper, scale: terms[i], weak });
            set.record(found, true, value, lower, upper);
        }
        for r in 0..at.constraints.len() {
            let (value, lower, upper) = (at.constraints[r], at.row_lower[r], at.row_upper[r]);
            let (z_lower, z_upper) = (lambda[r].min(0.0).abs(), lambda[r].max(0.0));
            let found =
                classify(Inequality { index: r, value, lower, upper, z_lower, z_upper, scale: largest_lambda, weak });
            set.record(found, false, value, lower, upper);
        }
        set
    }

    fn record(&mut self, found: Option<(Bound, bool)>, variable: bool, value: f64, lower: f64, upper: f64) {
        match found {
            Some((bound, true)) => {
                if bound.side != Side::Both {
                    self.smallest_active_multiplier = self.smallest_active_multiplier.min(bound.multiplier);
                }
                if variable {
                    self.variables.push(bound)
                } else {
                    self.rows.push(bound)
                }
            }
            Some((bound, false)) => {
                if variable {
                    self.weak_variables.push(bound)
                } else {
                    self.weak_rows.push(bound)
                }
            }
            None => {
                let gap = (value - lower).min(upper - value);
                if gap.is_finite() {
                    self.smallest_inactive_gap = self.smallest_inactive_gap.min(gap);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn upper(value: f64, z_upper: f64, scale: f64) -> Option<(Bound, bool)> {
        classify(Inequality {
            index: 0,
            value,
            lower: 1.0,
            upper: 100.0,
            z_lower: 0.0,
            z_upper,
            scale,
            weak: WEAK_MULTIPLIER,
        })
    }

    #[test]
    fn strictly_weakly_and_not_active() {
        // A multiplier well above its gap and its terms: active.
        assert_eq!(upper(100.0 - 1e-9, 1e-2, 1.0).map(|(_, strict)| strict), Some(true));
        // Both negligible against the terms: weakly active.
        assert_eq!(upper(100.0 - 1e-9, 1e-8, 1.0).map(|(_, strict)| strict), Some(false));
        // A spring in a flat valley (Fig. 5's case at −1 N per node): the terms are themselves
        // near zero, the gap 6.3e-7 (zero at this bound's scale) and the multiplier 5.6e-8, below
        // the gap: weakly active, not inactive (its tangent would leave the box).
        assert_eq!(upper(100.0 - 6.3e-7, 5.6e-8, 1e-9).map(|(_, strict)| strict), Some(false));
        // A real gap: inactive whatever the multiplier's noise.
        assert!(upper(90.0, 1e-12, 1e-9).is_none());
    }
}
