//! A run inside a figure: a checked case computed and kept as a value ([`RunOutput`]) that a
//! recipe draws and checks.

use crate::design::{run_design, StaticDesign};
use crate::dynamics::{run_dynamics, DynamicOutput, UsedDesign};
use crate::error::RunError;
use crate::progress::Progress;
use serde::Serialize;
use spine_case::{ValidCase, ValidTwoLink};

/// What one run of a figure computed.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One value per run: boxing the two-link study as well would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum RunOutput {
    Twolink { study: spine_solve::twolink::Study, stiffness: f64 },
    Design(Box<StaticDesign>),
    Dynamics { used: Box<UsedDesign>, output: DynamicOutput },
}

/// The two-link study of Sec. 3.
pub fn run_twolink(valid: &ValidTwoLink) -> RunOutput {
    RunOutput::Twolink {
        study: spine_solve::twolink::study(&valid.twolink, &valid.spec, &valid.options),
        stiffness: valid.spec.stiffness,
    }
}

/// Runs a checked case inside a figure.
pub fn run(valid: &ValidCase, progress: &mut dyn FnMut(Progress<'_>)) -> Result<RunOutput, RunError> {
    match valid {
        ValidCase::Twolink(v) => Ok(run_twolink(v)),
        ValidCase::Design(v) => Ok(RunOutput::Design(Box::new(run_design(v)?))),
        ValidCase::Dynamics(v) => {
            let (used, output) = run_dynamics(v, progress)?;
            Ok(RunOutput::Dynamics { used: Box::new(used), output })
        }
        ValidCase::Equilibrium(_) => {
            Err(RunError::NotInFigure("an equilibrium case has no figure recipe; use `spine equilibrium`"))
        }
        ValidCase::Figure(_) => Err(RunError::NotInFigure("a figure cannot run inside a figure")),
    }
}
