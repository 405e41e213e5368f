//! `"kind": "twolink"`: the two-link analysis of Sec. 3.

use crate::error::CaseError;
use crate::per_item::check_finite;
use crate::specs::{check_options, positive, Notes};
use serde::{Deserialize, Serialize};
use spine_model::twolink::{SmallDeflection, TwoLink};
use spine_solve::twolink::{OptimisationSpec, SmallDeflectionSpec, StudySpec};
use spine_solve::ContinuationOptions;

/// `"kind": "twolink"`: Sec. 3.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TwoLinkCase {
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    /// Link length `L`, m (> 0).
    pub length: f64,
    /// Middle spring `K`, N·m/rad (> 0).
    pub stiffness: f64,
    /// Transverse force at the middle node, N (≠ 0).
    pub p_y: f64,
    /// Axial force at the slider, N (≠ 0).
    pub p_x: f64,
    /// End displacements `δ` to tabulate, m (each ≠ 0, `|δ| < 2L`).
    pub deltas: Vec<f64>,
    /// Eq. (12) solved at one `δ` for each upper stiffness bound.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub optimisation: Option<TwoLinkOptimisation>,
    /// The small-deflection system of eqs. (25), (26) against the exact equilibria.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub small_deflection: Option<TwoLinkSmallDeflection>,
    #[serde(default)]
    pub solver: ContinuationOptions,
}

/// `optimisation` of a two-link case: eq. (12), `min 2K(θ1 − θ0)²` subject to eq. (9) at `delta`,
/// `lower_bound ≤ K ≤ upper` for each of `upper_bounds` (the paper gives two readings of its upper
/// bound, 10⁴ in its list and 1000 in its text).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TwoLinkOptimisation {
    /// End displacement, m (≠ 0, `|δ| < 2L`).
    pub delta: f64,
    /// N·m/rad (> 0).
    pub lower_bound: f64,
    /// N·m/rad, each > `lower_bound`; at least one.
    pub upper_bounds: Vec<f64>,
    /// Sec. 5's bounds on the N-link problem, carried over: each upper bound whose optimum leans
    /// beyond them is solved again within them (optional).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sec5_bounds: Option<TwoLinkSec5Bounds>,
}

/// Sec. 5's bounds for the two-link problem: `|θ0| ≤ theta0_max` (rad, in (0, π/2)) and the middle
/// node's height `L sin θ0 ≤ height_max` (m, > 0), one limit on `|θ0|` together.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TwoLinkSec5Bounds {
    pub theta0_max: f64,
    pub height_max: f64,
}

/// `small_deflection` of a two-link case: links `lengths` (m), the first at design angle
/// `theta0_1` (rad; the second's follows from `L1 sin θ0,1 + L2 sin θ0,2 = 0`), springs
/// `stiffness = [K1, K2]` (N·m/rad, no `K3`), the case's `p_y` at the middle node and `p_x` at the
/// slider, each multiplied by every one of `scales`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TwoLinkSmallDeflection {
    pub lengths: [f64; 2],
    pub theta0_1: f64,
    pub stiffness: [f64; 2],
    /// Load scales, each in (0, 1]; at least two (an order is fitted over the three smallest).
    pub scales: Vec<f64>,
}

/// A checked two-link case.
#[derive(Clone, Debug)]
pub struct ValidTwoLink {
    pub twolink: TwoLink,
    pub spec: StudySpec,
    pub options: ContinuationOptions,
}

impl TwoLinkCase {
    /// The two-link problem, checked.
    pub fn validate(&self) -> Result<ValidTwoLink, CaseError> {
        let length = positive("length", self.length, "m")?;
        let stiffness = positive("stiffness", self.stiffness, "N·m/rad")?;
        for (field, v) in [("p_y", self.p_y), ("p_x", self.p_x)] {
            if !v.is_finite() || v == 0.0 {
                return Err(CaseError::invalid(field, format!("must be a finite, nonzero force (N), got {v}")));
            }
        }
        if self.deltas.is_empty() {
            return Err(CaseError::invalid("deltas", "give at least one end displacement (m)"));
        }
        check_finite("deltas", &self.deltas)?;
        if let Some(i) = self.deltas.iter().position(|d| *d == 0.0 || d.abs() >= 2.0 * length) {
            return Err(CaseError::invalid(
                format!("deltas[{i}]"),
                format!("must be nonzero with |δ| < 2L = {} m, got {}", 2.0 * length, self.deltas[i]),
            ));
        }
        check_options(&self.solver)?;
        let optimisation = self.optimisation.as_ref().map(|o| o.validate(length)).transpose()?;
        let small_deflection = self.small_deflection.as_ref().map(|s| s.validate(self.p_y, self.p_x)).transpose()?;
        Ok(ValidTwoLink {
            twolink: TwoLink { length, p_y: self.p_y, p_x: self.p_x },
            spec: StudySpec { stiffness, deltas: self.deltas.clone(), optimisation, small_deflection },
            options: self.solver.clone(),
        })
    }
}

impl TwoLinkOptimisation {
    fn validate(&self, length: f64) -> Result<OptimisationSpec, CaseError> {
        if !self.delta.is_finite() || self.delta == 0.0 || self.delta.abs() >= 2.0 * length {
            return Err(CaseError::invalid(
                "optimisation.delta",
                format!("must be nonzero with |δ| < 2L = {} m, got {}", 2.0 * length, self.delta),
            ));
        }
        let lower = positive("optimisation.lower_bound", self.lower_bound, "N·m/rad")?;
        if self.upper_bounds.is_empty() {
            return Err(CaseError::invalid(
                "optimisation.upper_bounds",
                "give at least one upper stiffness bound (N·m/rad)",
            ));
        }
        if let Some(i) = self.upper_bounds.iter().position(|u| !(u.is_finite() && *u > lower)) {
            return Err(CaseError::invalid(
                format!("optimisation.upper_bounds[{i}]"),
                format!("must be finite and > lower_bound = {lower} N·m/rad, got {}", self.upper_bounds[i]),
            ));
        }
        let theta0_limit = match &self.sec5_bounds {
            None => None,
            Some(b) => {
                if !(b.theta0_max > 0.0 && b.theta0_max < std::f64::consts::FRAC_PI_2) {
                    return Err(CaseError::invalid(
                        "optimisation.sec5_bounds.theta0_max",
                        format!("must be in (0, π/2) rad, got {}", b.theta0_max),
                    ));
                }
                let height = positive("optimisation.sec5_bounds.height_max", b.height_max, "m")?;
                Some(b.theta0_max.min((height / length).min(1.0).asin()))
            }
        };
        Ok(OptimisationSpec {
            delta: self.delta,
            lower_bound: lower,
            upper_bounds: self.upper_bounds.clone(),
            theta0_limit,
        })
    }
}

impl TwoLinkSmallDeflection {
    fn validate(&self, p_y: f64, p_x: f64) -> Result<SmallDeflectionSpec, CaseError> {
        let l1 = positive("small_deflection.lengths[0]", self.lengths[0], "m")?;
        let l2 = positive("small_deflection.lengths[1]", self.lengths[1], "m")?;
        let t1 = self.theta0_1;
        if !t1.is_finite() || t1.abs() >= std::f64::consts::FRAC_PI_2 || (l1 * t1.sin()).abs() >= l2 {
            return Err(CaseError::invalid(
                "small_deflection.theta0_1",
                format!("must be finite with |θ0,1| < π/2 and |L1 sin θ0,1| < L2 (so the second link closes the chain), got {t1}"),
            ));
        }
        check_finite("small_deflection.stiffness", &self.stiffness)?;
        let [k1, k2] = self.stiffness;
        if k1 < 0.0 || k2 <= 0.0 {
            return Err(CaseError::invalid(
                "small_deflection.stiffness",
                format!("must be [K1 ≥ 0, K2 > 0] N·m/rad, got [{k1}, {k2}]"),
            ));
        }
        if self.scales.len() < 2 {
            return Err(CaseError::invalid("small_deflection.scales", "give at least two load scales in (0, 1]"));
        }
        if let Some(i) = self.scales.iter().position(|s| !(s.is_finite() && *s > 0.0 && *s <= 1.0)) {
            return Err(CaseError::invalid(
                format!("small_deflection.scales[{i}]"),
                format!("must be in (0, 1], got {}", self.scales[i]),
            ));
        }
        let system = SmallDeflection {
            lengths: [l1, l2],
            theta0: [t1, -(l1 * t1.sin() / l2).asin()],
            stiffness: [k1, k2],
            p_y2: p_y,
            p_x3: p_x,
        };
        Ok(SmallDeflectionSpec { system, scales: self.scales.clone() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn optimisation(bounds: Option<TwoLinkSec5Bounds>) -> TwoLinkOptimisation {
        TwoLinkOptimisation { delta: -0.02, lower_bound: 100.0, upper_bounds: vec![1e4], sec5_bounds: bounds }
    }

    #[test]
    fn sec5_bounds_become_one_angle_limit_and_bad_ones_name_their_field() {
        let spec = |b| optimisation(Some(b)).validate(0.5);
        // The height bound is the tighter one here: asin(0.2 / 0.5).
        let limit = spec(TwoLinkSec5Bounds { theta0_max: 0.6, height_max: 0.2 }).unwrap().theta0_limit.unwrap();
        assert!((limit - 0.4f64.asin()).abs() < 1e-15, "{limit}");
        let limit = spec(TwoLinkSec5Bounds { theta0_max: 0.3, height_max: 0.25 }).unwrap().theta0_limit.unwrap();
        assert_eq!(limit, 0.3);
        assert_eq!(optimisation(None).validate(0.5).unwrap().theta0_limit, None);
        let err = spec(TwoLinkSec5Bounds { theta0_max: 2.0, height_max: 0.25 }).unwrap_err().to_string();
        assert!(err.contains("optimisation.sec5_bounds.theta0_max") && err.contains("(0, π/2)"), "{err}");
        let err = spec(TwoLinkSec5Bounds { theta0_max: 0.5, height_max: -1.0 }).unwrap_err().to_string();
        assert!(err.contains("optimisation.sec5_bounds.height_max"), "{err}");
    }
}
