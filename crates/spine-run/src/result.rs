//! The typed result of a case ([`CaseResult`]): what `result.json` holds, the files written beside
//! it, and whether it is clean (exit code 0) or not (exit code 3). A run stopped by its time limit
//! still gives its result, marked `"stopped": "time_limit"` and never clean.

use crate::design::DesignCaseResult;
use crate::dynamics::DynamicsResult;
use crate::equilibrium::EquilibriumResult;
use crate::figure::FigureResult;
use crate::files::OutputFile;
use crate::sensitivity::{FigureSensitivityResult, SensitivityResult};
use crate::study::StudyResult;
use crate::sweep::SweepCaseResult;
use crate::twolink::TwoLinkResult;
use serde::Serialize;
use serde_json::{Map, Value};

/// What a case computed ([`KindResult`]), and whether its time limit stopped it early.
#[derive(Clone, Debug)]
pub struct CaseResult {
    pub result: KindResult,
    /// Set when some loop of the run saw its wall-clock limit pass
    /// ([`crate::Overrides::time_limit`]) and ended early: the result holds what was reached
    /// (each solver's status says where it stopped) and is not clean.
    pub stopped: Option<spine_stop::StopReason>,
}

impl From<KindResult> for CaseResult {
    fn from(result: KindResult) -> Self {
        Self { result, stopped: None }
    }
}

impl CaseResult {
    /// Clean: every solver converged, every equilibrium it reports is stable, every solver check
    /// passed, and no time limit stopped it. Not clean is exit code 3 (the result is still
    /// written, with its status).
    pub fn is_clean(&self) -> bool {
        self.stopped.is_none() && self.result.is_clean()
    }

    /// The files written beside `result.json` (CSV tables, figures), in writing order.
    pub fn files(&self) -> Vec<OutputFile> {
        self.result.files()
    }

    /// `result.json` as a JSON value: the serialised result with every wall time (a `*_seconds`
    /// field, at any depth) moved under the top-level `timings`, keyed by its path, so that
    /// dropping `timings` leaves the same bytes for the same input; `"stopped"` when a time limit
    /// ended the run.
    pub fn to_json(&self) -> Value {
        let mut value = with_timings(&self.result);
        if let (Some(reason), Value::Object(map)) = (self.stopped, &mut value) {
            map.insert("stopped".into(), Value::String(reason.name().into()));
        }
        value
    }
}

impl std::fmt::Display for CaseResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(reason) = self.stopped {
            writeln!(f, "STOPPED EARLY ({}): the run's time limit passed; what it reached so far:", reason.name())?;
        }
        self.result.fmt(f)
    }
}

/// What any case computed, by kind: `"kind"` in `result.json` is the variant's name in snake_case
/// (the case file's kind; `study`, `sensitivity`, `figure_sensitivity` and `sweep` for the
/// commands of those names), derived here and nowhere else.
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One value per run: boxing the large variants would buy nothing.
#[allow(clippy::large_enum_variant)]
pub enum KindResult {
    Equilibrium(EquilibriumResult),
    Twolink(TwoLinkResult),
    Design(DesignCaseResult),
    /// A step or periodic response.
    Simulate(DynamicsResult),
    /// The damping design, eq. (35).
    Damping(DynamicsResult),
    /// The periodic-load design, eq. (37).
    Periodic(DynamicsResult),
    Figure(FigureResult),
    Study(StudyResult),
    Sensitivity(SensitivityResult),
    /// `spine sensitivity` on a figure case: each design run's sensitivities.
    FigureSensitivity(FigureSensitivityResult),
    Sweep(SweepCaseResult),
}

impl KindResult {
    /// `result.json`'s `"kind"` (serde's tag of the variant), without serialising the result.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Equilibrium(_) => "equilibrium",
            Self::Twolink(_) => "twolink",
            Self::Design(_) => "design",
            Self::Simulate(_) => "simulate",
            Self::Damping(_) => "damping",
            Self::Periodic(_) => "periodic",
            Self::Figure(_) => "figure",
            Self::Study(_) => "study",
            Self::Sensitivity(_) => "sensitivity",
            Self::FigureSensitivity(_) => "figure_sensitivity",
            Self::Sweep(_) => "sweep",
        }
    }

    /// Clean: every solver converged, every equilibrium it reports is stable and every solver
    /// check passed.
    pub fn is_clean(&self) -> bool {
        match self {
            Self::Equilibrium(r) => r.is_clean(),
            Self::Twolink(r) => r.is_clean(),
            Self::Design(r) => r.is_clean(),
            Self::Simulate(r) | Self::Damping(r) | Self::Periodic(r) => r.is_clean(),
            Self::Figure(r) => r.is_clean(),
            Self::Study(r) => r.is_clean(),
            Self::Sensitivity(r) => r.is_clean(),
            Self::FigureSensitivity(r) => r.is_clean(),
            Self::Sweep(r) => r.is_clean(),
        }
    }

    /// Why the result is not clean, one line each, where it carries its reasons as a typed field
    /// (`not_clean` of a sensitivity result); empty otherwise (the summary says why).
    pub fn not_clean_reasons(&self) -> Vec<String> {
        match self {
            Self::Sensitivity(r) => r.not_clean.iter().map(ToString::to_string).collect(),
            Self::FigureSensitivity(r) => r
                .runs
                .iter()
                .flat_map(|run| run.result.not_clean.iter().map(move |reason| format!("{}: {reason}", run.name)))
                .collect(),
            _ => Vec::new(),
        }
    }

    /// The files written beside `result.json` (CSV tables, figures), in writing order.
    pub fn files(&self) -> Vec<OutputFile> {
        match self {
            Self::Equilibrium(_) | Self::Twolink(_) | Self::Design(_) => Vec::new(),
            Self::Simulate(r) | Self::Damping(r) | Self::Periodic(r) => r.files(),
            Self::Figure(r) => r.files(),
            Self::Study(r) => r.files(),
            Self::Sensitivity(r) => r.files(),
            Self::FigureSensitivity(r) => r.files(),
            Self::Sweep(r) => r.files(),
        }
    }
}

impl std::fmt::Display for KindResult {
    /// The summary a user reads: status, the numbers that show it, and warnings.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Equilibrium(r) => r.fmt(f),
            Self::Twolink(r) => r.fmt(f),
            Self::Design(r) => r.fmt(f),
            Self::Simulate(r) | Self::Damping(r) | Self::Periodic(r) => r.fmt(f),
            Self::Figure(r) => r.fmt(f),
            Self::Study(r) => r.fmt(f),
            Self::Sensitivity(r) => r.fmt(f),
            Self::FigureSensitivity(r) => r.fmt(f),
            Self::Sweep(r) => r.fmt(f),
        }
    }
}

/// `value` serialised, with its wall times under `timings` (see [`CaseResult::to_json`]).
pub fn with_timings(value: &impl Serialize) -> Value {
    let mut value = serde_json::to_value(value).expect("results serialise: their maps have string keys");
    let mut timings = Map::new();
    split_timings(&mut value, "", &mut timings);
    if let Value::Object(map) = &mut value {
        map.insert("timings".into(), Value::Object(timings));
    }
    value
}

/// Moves every `*_seconds` entry of `value` into `timings`, keyed by its path (`solver.ipopt_seconds`,
/// `runs.0.wall_seconds`).
fn split_timings(value: &mut Value, path: &str, timings: &mut Map<String, Value>) {
    match value {
        Value::Object(map) => {
            let keys: Vec<String> = map.keys().filter(|k| k.ends_with("_seconds")).cloned().collect();
            for k in keys {
                if let Some(v) = map.remove(&k) {
                    timings.insert(format!("{path}{k}"), v);
                }
            }
            for (k, v) in map.iter_mut() {
                split_timings(v, &format!("{path}{k}."), timings);
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter_mut().enumerate() {
                split_timings(v, &format!("{path}{i}."), timings);
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn wall_times_move_under_timings_by_path_and_nothing_else_moves() {
        let v = with_timings(&json!({
            "a": 1.0,
            "total_seconds": 2.0,
            "solver": { "ipopt_seconds": 3.0, "iterations": 4 },
            "runs": [{ "wall_seconds": 5.0, "seconds_left": 6.0 }],
        }));
        assert_eq!(
            v,
            json!({
                "a": 1.0,
                "solver": { "iterations": 4 },
                "runs": [{ "seconds_left": 6.0 }],
                "timings": { "total_seconds": 2.0, "solver.ipopt_seconds": 3.0, "runs.0.wall_seconds": 5.0 },
            })
        );
    }
}
