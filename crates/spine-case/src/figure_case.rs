//! `"kind": "figure"`: one figure of the paper, made of several runs (panels).
//!
//! A figure case holds a `base` case and a list of `runs`; each run's `case` is a JSON merge patch
//! (RFC 7396) over the base: objects merge key by key, `null` removes a key, anything else
//! replaces. So the 10-link and 5-link panels of Fig. 3 share every setting but the chain, the
//! loads and the start, and the file says only what differs. The `figure` names the recipe that
//! draws the runs and checks the paper's claims on them.

use crate::error::CaseError;
use crate::specs::Notes;
use serde::{Deserialize, Serialize};
use serde_json::Value;

/// Longest run name, characters: a file name such as `shape_<name>.csv` stays far below the
/// 255 bytes file systems allow.
pub const MAX_RUN_NAME: usize = 64;

/// The figure recipes this program has (`twolink` is Sec. 3; `objectives` goes beyond the paper:
/// eq. (33) under each built-in criterion, docs/objectives.md).
pub const FIGURES: &[&str] =
    &["twolink", "fig3", "fig4", "fig5", "fig6", "fig7", "fig8", "fig9", "fig10", "fig11", "fig12", "objectives"];

/// One run of a figure.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FigureRun {
    /// Short name, used in file names (`shape_<name>.csv`): 1 to [`MAX_RUN_NAME`] letters, digits,
    /// `-` and `_`.
    pub name: String,
    /// What the run is, for legends and the report.
    #[serde(default)]
    pub label: String,
    /// Merge patch over the figure's `base` (or a whole case when there is no base).
    #[serde(default)]
    pub case: Value,
}

/// A figure case as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FigureCase {
    /// The recipe, one of [`FIGURES`].
    pub figure: String,
    #[serde(default)]
    pub title: String,
    #[serde(default)]
    pub notes: Notes,
    /// The settings the runs share.
    #[serde(default)]
    pub base: Value,
    pub runs: Vec<FigureRun>,
}

/// A run with its case merged over the base (not yet parsed).
#[derive(Clone, Debug, PartialEq)]
pub struct MergedRun {
    pub name: String,
    pub label: String,
    /// The run's whole case as JSON.
    pub case: Value,
}

/// RFC 7396 JSON merge patch: `patch` applied to `target`.
pub fn merge_patch(target: &Value, patch: &Value) -> Value {
    match patch {
        Value::Object(p) => {
            let mut out = match target {
                Value::Object(t) => t.clone(),
                _ => serde_json::Map::new(),
            };
            for (key, value) in p {
                if value.is_null() {
                    out.remove(key);
                } else {
                    let merged = merge_patch(out.get(key).unwrap_or(&Value::Null), value);
                    out.insert(key.clone(), merged);
                }
            }
            Value::Object(out)
        }
        other => other.clone(),
    }
}

impl FigureCase {
    /// The figure's title, or its recipe's name where the file gives none.
    pub fn shown_title(&self) -> String {
        if self.title.is_empty() {
            self.figure.clone()
        } else {
            self.title.clone()
        }
    }

    /// Checks the recipe name and the run names, and merges each run's patch over the base. Errors
    /// name the run: `runs[1].name: …`. (Parsing and checking the merged cases is
    /// [`FigureCase::validate`], beside the dispatcher.)
    pub fn merged_runs(&self) -> Result<Vec<MergedRun>, CaseError> {
        if !FIGURES.contains(&self.figure.as_str()) {
            return Err(CaseError::invalid(
                "figure",
                format!("unknown figure \"{}\"; one of {}", spine_check::shown(&self.figure), FIGURES.join(", ")),
            ));
        }
        if self.runs.is_empty() {
            return Err(CaseError::invalid("runs", "give at least one run"));
        }
        let mut runs: Vec<MergedRun> = Vec::new();
        for (i, run) in self.runs.iter().enumerate() {
            let at = format!("runs[{i}]");
            let allowed = |c: char| c.is_ascii_alphanumeric() || c == '-' || c == '_';
            if run.name.is_empty() || run.name.len() > MAX_RUN_NAME || !run.name.chars().all(allowed) {
                let shown: String = run.name.chars().take(MAX_RUN_NAME + 1).collect();
                let more = if run.name.chars().count() > MAX_RUN_NAME + 1 { "…" } else { "" };
                return Err(CaseError::invalid(
                    format!("{at}.name"),
                    format!(
                        "must be 1 to {MAX_RUN_NAME} letters, digits, '-' or '_' (it names files), got {} characters: {shown:?}{more}",
                        run.name.chars().count()
                    ),
                ));
            }
            if runs.iter().any(|r| r.name == run.name) {
                return Err(CaseError::invalid(
                    format!("{at}.name"),
                    format!("{:?} is used by an earlier run", run.name),
                ));
            }
            let case = merge_patch(&self.base, &run.case);
            runs.push(MergedRun { name: run.name.clone(), label: run.label.clone(), case });
        }
        Ok(runs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn merge_patch_follows_rfc_7396() {
        let target = json!({"a": "b", "c": {"d": "e", "f": "g"}, "k": [1, 2]});
        let patch = json!({"a": "z", "c": {"f": null}, "k": [3]});
        assert_eq!(merge_patch(&target, &patch), json!({"a": "z", "c": {"d": "e"}, "k": [3]}));
        assert_eq!(merge_patch(&target, &json!([1])), json!([1]));
        assert_eq!(merge_patch(&json!(null), &json!({"x": {"y": 1}})), json!({"x": {"y": 1}}));
    }
}
