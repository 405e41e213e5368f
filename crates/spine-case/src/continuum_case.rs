//! `"kind": "continuum"`: eq. (33) posed for one physical rod and solved for a ladder of `N`, to see
//! whether the optimal design has a limit as `N → ∞` (docs/continuum.md).

use crate::error::CaseError;
use crate::specs::Notes;
use serde::{Deserialize, Serialize};
use spine_continuum::design::RodDesign;
use spine_continuum::design_study::{validate_links, StudySettings};

/// `"kind": "continuum"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContinuumCase {
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    /// The rod and its design problem: loads per unit length, bounds on `EI`, a curvature bound
    /// and an `x`-dependent height bound (every field given).
    pub rod: RodDesign,
    /// The chain sizes `N`, increasing (2 … 100 000 links, at most 20 sizes); each is started
    /// from the previous optimum.
    pub links: Vec<usize>,
    #[serde(default)]
    pub solver: StudySettings,
}

/// A checked continuum case.
#[derive(Clone, Debug)]
pub struct ValidContinuum {
    pub rod: RodDesign,
    pub links: Vec<usize>,
    pub settings: StudySettings,
}

impl ContinuumCase {
    /// The study, checked; errors name `rod.FIELD`, `links[k]` or `solver.FIELD`.
    pub fn validate(&self) -> Result<ValidContinuum, CaseError> {
        self.rod.validate().map_err(|e| e.under("rod"))?;
        validate_links(&self.links).map_err(|e| e.under("links"))?;
        self.solver.validate().map_err(|e| e.under("solver"))?;
        Ok(ValidContinuum { rod: self.rod.clone(), links: self.links.clone(), settings: self.solver.clone() })
    }
}
