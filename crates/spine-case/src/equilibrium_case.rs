//! `"kind": "equilibrium"`: the passive and loaded equilibria of a given design.

use crate::error::CaseError;
use crate::specs::{check_options, ChainSpec, DesignSpec, LoadSpec, Notes};
use serde::{Deserialize, Serialize};
use spine_model::Structure;
use spine_solve::{ContinuationOptions, StaticProblem};

/// `"kind": "equilibrium"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EquilibriumCase {
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    pub chain: ChainSpec,
    pub design: DesignSpec,
    pub loads: LoadSpec,
    #[serde(default)]
    pub solver: ContinuationOptions,
}

/// A checked equilibrium case, ready for the solver.
#[derive(Clone, Debug)]
pub struct ValidEquilibrium {
    pub problem: StaticProblem,
    pub options: ContinuationOptions,
}

impl EquilibriumCase {
    /// The static problem and solver options, checked.
    pub fn validate(&self) -> Result<ValidEquilibrium, CaseError> {
        let mut chain = self.chain.validate()?;
        let design = match &self.design {
            DesignSpec::Given(d) => d.validate(&chain)?,
            DesignSpec::ToBeOptimised => {
                return Err(CaseError::invalid(
                    "design",
                    "an equilibrium case needs a given design {\"theta0\": [...], \"stiffness\": ...}; \"optimise\" is for design cases",
                ))
            }
        };
        let (passive, actuation) = self.loads.resolve(&mut chain)?;
        check_options(&self.solver)?;
        Ok(ValidEquilibrium {
            problem: StaticProblem { structure: Structure { chain, passive, actuation }, design },
            options: self.solver.clone(),
        })
    }
}
