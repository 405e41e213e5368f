//! Why a sensitivity result is not clean (exit code 3): typed reasons in `result.json`.

use super::NoSensitivity;
use crate::design::DesignCaseResult;
use serde::Serialize;
use spine_design::sensitivity::SensitivityReport;

/// Why a sensitivity result is not clean (in `result.json`: `{"reason": "no_derivative", …}`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum NotClean {
    /// The optimum is not clean: its status, warnings and certificate say why.
    Optimum { status: spine_ipopt::Status },
    /// No sensitivities were computed, and why.
    NoSensitivities { why: NoSensitivity },
    /// A parameter has neither a two-sided derivative nor both one-sided ones, and why.
    NoDerivative { parameter: String, why: String },
}

impl NotClean {
    /// The reasons a result with this optimum and these sensitivities is not clean (none: clean).
    pub(super) fn of(
        design: &DesignCaseResult,
        report: Option<&SensitivityReport>,
        no_sensitivity: Option<&NoSensitivity>,
    ) -> Vec<Self> {
        let mut reasons = Vec::new();
        if !design.result.is_clean() {
            reasons.push(Self::Optimum { status: design.result.solver.status });
        }
        match report {
            None => reasons
                .push(Self::NoSensitivities { why: no_sensitivity.cloned().unwrap_or(NoSensitivity::OptimumNotClean) }),
            Some(report) => reasons.extend(
                report
                    .parameters
                    .iter()
                    .filter(|p| p.derivative.is_none() && (p.increase.is_none() || p.decrease.is_none()))
                    .map(|p| Self::NoDerivative {
                        parameter: p.name.clone(),
                        why: p.note.clone().unwrap_or_else(|| "the conditions fail".into()),
                    }),
            ),
        }
        reasons
    }
}

impl std::fmt::Display for NotClean {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Optimum { status } => {
                write!(f, "the optimum is not clean (Ipopt: {status}; see its warnings and certificate)")
            }
            Self::NoSensitivities { why } => write!(f, "no sensitivities: {why}"),
            Self::NoDerivative { parameter, why } => write!(f, "no derivative with respect to {parameter}: {why}"),
        }
    }
}
