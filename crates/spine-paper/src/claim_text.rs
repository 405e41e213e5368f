//! How the reports write one claim of a `result.json`: whether it passed, whether a knife edge
//! split it, its verdict and its measured numbers with each branch's.

use serde_json::Value;
use spine_run::claims::BranchVerdict;
use std::fmt::Write as _;

pub(crate) fn passed(claim: &Value) -> bool {
    claim.get("pass") == Some(&Value::Bool(true))
}

/// The claim's branches disagree (a knife edge, `Claim::split`).
pub(crate) fn split(claim: &Value) -> bool {
    claim.get("split") == Some(&Value::Bool(true))
}

/// The measured numbers, and for a claim held to several branches of a knife edge each branch's
/// verdict and numbers.
pub(crate) fn measured(claim: &Value) -> String {
    let mut text = text_of(claim, "measured").to_string();
    let branches = claim.get("branches").and_then(Value::as_array).map_or(&[][..], Vec::as_slice);
    if branches.len() > 1 {
        let parsed = branches.iter().filter_map(|b| serde_json::from_value::<BranchVerdict>(b.clone()).ok());
        for branch in parsed {
            let _ = write!(text, " — {}", branch.text());
        }
    }
    text
}

pub(crate) fn text_of<'a>(claim: &'a Value, key: &str) -> &'a str {
    claim.get(key).and_then(Value::as_str).unwrap_or("")
}

pub(crate) fn verdict(pass: bool) -> &'static str {
    if pass {
        "PASS"
    } else {
        "FAIL"
    }
}
