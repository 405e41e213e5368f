//! Changes to a case from the command line or a Python call ([`Overrides`]): each `None` keeps the
//! case file's value; the values are checked where they are read ([`crate::option_values`]).

use serde::{Deserialize, Serialize};
use spine_case::{DynamicsTask, ValidDesign, ValidDynamics};
use spine_design::refine::Refine;
use spine_design::Formulation;
use spine_dynamic_design::SearchMethod;

/// Changes to a case from the command line (each `None` keeps the case file's value).
#[derive(Clone, Debug, Default)]
pub struct Overrides {
    pub design: DesignOverrides,
    pub dynamics: DynamicsOverrides,
    /// Wall-clock limit of the whole run (`None`: none). When it passes, Ipopt stops at its next
    /// iteration, the integrator at its next step, equilibrium continuation at its next step, the
    /// GA and pattern search at their next generation or poll, a multi-start before its next
    /// start; the run returns what it reached, marked [`crate::CaseResult::stopped`] (exit code 3).
    pub time_limit: Option<std::time::Duration>,
    /// Animations: a dynamic run (`simulate`, `damping`, `periodic`) writes `animation.gif` when
    /// set; a figure with an animation (fig9–fig11) always writes one, with these options when
    /// set and the defaults otherwise.
    pub animation: Option<crate::animation::AnimationOptions>,
    /// Worker processes for the seeded starts of a multi-start (`None`, or one job: every solve in
    /// this process). The census is the same either way.
    pub workers: Option<crate::workers::Workers>,
}

/// Changes to a design case from the command line (each `None` keeps the case file's value).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DesignOverrides {
    pub formulation: Option<Formulation>,
    /// Extra seeded feasible starts.
    pub starts: Option<usize>,
    pub seed: Option<u64>,
    /// `--confidence P`: the census runs until P(a better optimum unseen) ≤ P
    /// (`multistart.confidence`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub confidence: Option<f64>,
    pub refine: Option<Refine>,
    /// `spine design --sensitivity`: the derivatives of the reported optimum with respect to the
    /// case's parameters ([`crate::sensitivity::differentiate`]) in the result.
    #[serde(default)]
    pub sensitivity: bool,
}

impl DesignOverrides {
    /// With a confidence and no `starts`, `starts` is the census's cap: 0, the largest allowed
    /// (the CLI's `--confidence` and flexspine's `confidence=` alike).
    pub fn with_confidence_cap(mut self) -> Self {
        if self.confidence.is_some() {
            self.starts = self.starts.or(Some(0));
        }
        self
    }

    /// Applies the overrides; errors (naming the field) when they do not fit the case (the
    /// reduced space with another criterion than the paper's).
    pub fn apply(&self, valid: &mut ValidDesign) -> Result<(), spine_case::CaseError> {
        if let Some(f) = self.formulation {
            spine_case::check_formulation(f, &valid.problem)?;
            valid.formulation = f;
        }
        if let Some(s) = self.starts {
            // A census's cap is only a cap: its batches are checked as they come.
            if self.confidence.or(valid.multistart.confidence).is_none() {
                spine_case::check_runs_memory("starts", s + 1, valid.problem.n_links())?;
            }
            valid.multistart.starts = s;
        }
        if let Some(s) = self.seed {
            valid.multistart.seed = s;
        }
        if let Some(p) = self.confidence {
            let p = spine_case::check_confidence(p)
                .map_err(|m| spine_case::CaseError::invalid("overrides.confidence", m))?;
            valid.multistart.confidence = Some(p);
        }
        if let Some(r) = self.refine {
            valid.settings.refine = r;
        }
        Ok(())
    }
}

/// Changes to a dynamic case from the command line.
#[derive(Clone, Copy, Debug, Default)]
pub struct DynamicsOverrides {
    /// The search of eq. (37) (kind `periodic`).
    pub method: Option<SearchMethod>,
}

impl DynamicsOverrides {
    pub fn apply(&self, valid: &mut ValidDynamics) {
        if let (Some(m), DynamicsTask::Periodic { method, .. }) = (self.method, &mut valid.task) {
            *method = m;
        }
    }
}
