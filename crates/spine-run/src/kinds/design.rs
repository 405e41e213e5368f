//! Kind `design`'s runner: eq. (33) from the case's start and its seeded starts, then, when asked,
//! the sensitivities of the reported optimum; inside a figure, the run from the case's own start.

use crate::design::{run_design, run_design_case, DesignCaseResult};
use crate::error::RunError;
use crate::progress::Progress;
use spine_case::DesignCase;

impl crate::RunKind for DesignCase {
    type Output = DesignCaseResult;
    const IN_FIGURE: bool = true;

    /// Eq. (33) from the case's start and its seeded starts ([`run_design_case`]), with the
    /// sensitivities of the reported optimum when asked for.
    fn run(&self, cx: &mut crate::RunContext<'_>) -> Result<DesignCaseResult, RunError> {
        let mut valid = self.validate()?;
        cx.overrides.design.apply(&mut valid)?;
        let mut result = run_design_case(self, &valid, cx.overrides.workers.as_ref(), cx.progress)?;
        crate::sensitivity::attach(self, &valid, &cx.overrides.design, &mut result)?;
        Ok(result)
    }

    /// Eq. (33) from the case's own start, with what a figure draws ([`run_design`]; its census
    /// in `workers`).
    fn in_figure(
        &self,
        workers: Option<&crate::workers::Workers>,
        _: &mut dyn FnMut(Progress<'_>),
    ) -> Option<Result<crate::RunOutput, RunError>> {
        Some(
            self.validate()
                .map_err(RunError::from)
                .and_then(|valid| Ok(crate::RunOutput::new(run_design(&valid, workers)?))),
        )
    }
}
