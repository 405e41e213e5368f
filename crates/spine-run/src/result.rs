//! The typed result of a case ([`CaseResult`]): what `result.json` holds, the files written beside
//! it, and whether it is clean (exit code 0) or not (exit code 3). A run stopped by its time limit
//! still gives its result, marked `"stopped": "time_limit"` and never clean.

use crate::files::OutputFile;
use crate::registry::KindResult;
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

/// `value` serialised, with its wall times under `timings` (see [`CaseResult::to_json`]).
pub fn with_timings(value: &impl Serialize) -> Value {
    // Invariant: stated in the message; serde_json fails only on maps with non-string keys.
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
