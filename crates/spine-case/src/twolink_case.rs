//! `"kind": "twolink"`: the two-link analysis of Sec. 3.

use crate::per_item::check_finite;
use crate::specs::{check_options, positive, Notes};
use crate::CaseError;
use serde::{Deserialize, Serialize};
use spine_model::twolink::TwoLink;
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
    #[serde(default)]
    pub solver: ContinuationOptions,
}

/// A checked two-link case.
#[derive(Clone, Debug)]
pub struct ValidTwoLink {
    pub twolink: TwoLink,
    pub stiffness: f64,
    pub deltas: Vec<f64>,
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
        Ok(ValidTwoLink {
            twolink: TwoLink { length, p_y: self.p_y, p_x: self.p_x },
            stiffness,
            deltas: self.deltas.clone(),
            options: self.solver.clone(),
        })
    }
}
