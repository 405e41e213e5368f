//! One count of the claims, for REPORT.md, report.html and `report.json` (which the docs quote):
//! the paper's statements (PASS, FAIL, SPLIT by a knife edge) apart from the solver checks.

use crate::claim_text::{passed, split, text_of};
use crate::report::FolderResult;
use serde_json::{json, Value};

/// Claims of one kind: how many, how many pass, how many a knife edge splits (a split claim is
/// neither PASS nor FAIL).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Tally {
    pub total: usize,
    pub pass: usize,
    pub split: usize,
}

impl Tally {
    pub fn fail(&self) -> usize {
        self.total - self.pass - self.split
    }

    fn add(&mut self, claim: &Value) {
        self.total += 1;
        if split(claim) {
            self.split += 1;
        } else if passed(claim) {
            self.pass += 1;
        }
    }

    fn to_json(self) -> Value {
        json!({"total": self.total, "pass": self.pass, "fail": self.fail(), "split": self.split})
    }
}

/// A claim is a statement of the paper unless it says it is a solver check.
pub fn is_paper(claim: &Value) -> bool {
    text_of(claim, "check") != "solver"
}

/// The counts of one case or of all: the paper's statements and the solver checks.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    pub paper: Tally,
    pub solver: Tally,
}

impl Counts {
    /// The claims of one result.
    pub fn of(result: &FolderResult) -> Self {
        let mut counts = Self::default();
        for claim in result.value.get("claims").and_then(Value::as_array).into_iter().flatten() {
            if is_paper(claim) {
                counts.paper.add(claim);
            } else {
                counts.solver.add(claim);
            }
        }
        counts
    }

    /// The claims of every result, plus `across` cross-figure statements of the paper (their
    /// verdicts, e.g. the C_K trend over Figs. 6–8).
    pub fn all(results: &[FolderResult], across: &[bool]) -> Self {
        let mut total = Self::default();
        for r in results {
            let c = Self::of(r);
            for (t, part) in [(&mut total.paper, c.paper), (&mut total.solver, c.solver)] {
                t.total += part.total;
                t.pass += part.pass;
                t.split += part.split;
            }
        }
        total.paper.total += across.len();
        total.paper.pass += across.iter().filter(|p| **p).count();
        total
    }

    /// "P of the paper's T statements pass, F fail[, S are split by a knife edge]; s of t solver
    /// checks pass."
    pub fn sentence(&self) -> String {
        let split = match self.paper.split {
            0 => String::new(),
            1 => ", 1 is split by a knife edge".into(),
            n => format!(", {n} are split by a knife edge"),
        };
        format!(
            "{} of the paper's {} statements pass, {} fail{split}; {} of {} solver checks pass.",
            self.paper.pass,
            self.paper.total,
            self.paper.fail(),
            self.solver.pass,
            self.solver.total
        )
    }
}

/// Per result: the paper's statements passed and counted, the solver checks passed and counted,
/// and the run time (s, "—" when unknown).
pub(crate) fn rows(results: &[FolderResult]) -> Vec<(String, String, String)> {
    results
        .iter()
        .map(|r| {
            let c = Counts::of(r);
            let t = r
                .value
                .get("timings")
                .and_then(|t| t.get("total_seconds"))
                .and_then(Value::as_f64)
                .map_or("—".into(), |t| format!("{t:.1}"));
            let split = if c.paper.split > 0 { format!(" ({} split)", c.paper.split) } else { String::new() };
            (
                format!("{} / {}{split}", c.paper.pass, c.paper.total),
                format!("{} / {}", c.solver.pass, c.solver.total),
                t,
            )
        })
        .collect()
}

/// `report.json`: the counts over all cases and per case, the failing statements of the paper
/// and the anchor of their explanation in `docs/findings.md` (none where there is none).
pub fn report_json(
    results: &[FolderResult],
    across: &[(bool, &str)],
    why: &dyn Fn(&str) -> Option<&'static str>,
) -> Value {
    let verdicts: Vec<bool> = across.iter().map(|(p, _)| *p).collect();
    let all = Counts::all(results, &verdicts);
    let cases: Vec<Value> = results
        .iter()
        .map(|r| {
            let c = Counts::of(r);
            json!({"name": r.name, "paper": c.paper.to_json(), "solver": c.solver.to_json()})
        })
        .collect();
    let mut failing: Vec<Value> = Vec::new();
    for r in results {
        for c in r.value.get("claims").and_then(Value::as_array).into_iter().flatten() {
            if is_paper(c) && !passed(c) && !split(c) {
                let statement = text_of(c, "statement");
                failing.push(json!({"case": r.name, "scope": text_of(c, "scope"), "statement": statement, "why": why(statement)}));
            }
        }
    }
    for (_, statement) in across.iter().filter(|(p, _)| !p) {
        failing.push(
            json!({"case": "Figs. 6–8", "scope": "across figures", "statement": statement, "why": why(statement)}),
        );
    }
    let explained = failing.iter().filter(|f| !f["why"].is_null()).count();
    json!({
        "paper": all.paper.to_json(),
        "solver": all.solver.to_json(),
        "across_figures": verdicts.len(),
        "failing_explained": explained,
        "failing": failing,
        "cases": cases,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn result(claims: Value) -> FolderResult {
        FolderResult { name: "fig".into(), value: json!({ "claims": claims }), assets: vec![] }
    }

    #[test]
    fn paper_statements_and_solver_checks_are_counted_apart_and_split_claims_neither_pass_nor_fail() {
        let r = result(json!([
            {"check": "paper", "pass": true, "statement": "a"},
            {"check": "paper", "pass": false, "statement": "b"},
            {"check": "paper", "pass": false, "split": true, "statement": "c"},
            {"check": "solver", "pass": true, "statement": "d"},
        ]));
        let c = Counts::all(std::slice::from_ref(&r), &[false]);
        assert_eq!(c.paper, Tally { total: 4, pass: 1, split: 1 });
        assert_eq!(c.paper.fail(), 2);
        assert_eq!(c.solver, Tally { total: 1, pass: 1, split: 0 });
        assert_eq!(
            c.sentence(),
            "1 of the paper's 4 statements pass, 2 fail, 1 is split by a knife edge; 1 of 1 solver checks pass."
        );
        let j = report_json(&[r], &[(false, "e")], &|s| (s == "b").then_some("why-b"));
        assert_eq!(j["paper"]["fail"], 2);
        assert_eq!(j["failing"].as_array().unwrap().len(), 2);
        assert_eq!(j["failing_explained"], 1);
    }
}
