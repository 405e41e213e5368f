//! A run inside a figure: a checked case computed and kept as a value ([`RunOutput`]) that a
//! recipe draws and checks. Each kind says how it runs inside a figure
//! ([`RunKind::in_figure`](crate::RunKind::in_figure)).

use crate::design::StaticDesign;
use crate::dynamics::{DynamicOutput, UsedDesign};
use crate::twolink::TwoLinkResult;
use serde::Serialize;

/// What one run of a figure computed: for a two-link run the kind's own result; for eq. (33)
/// and the dynamics, the solver's state besides what `result.json` holds (the problem, the
/// projected start, the gradients, the whole trajectories) that a recipe draws and checks.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One value per run: boxing the two-link study as well would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum RunOutput {
    Twolink(TwoLinkResult),
    Design(Box<StaticDesign>),
    Dynamics { used: Box<UsedDesign>, output: DynamicOutput },
}
