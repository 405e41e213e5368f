//! A claim of the paper, checked by the program: what the paper says, what is measured and the
//! threshold it is held to (fixed before the run), the verdict and the numbers.

use serde::{Deserialize, Serialize};

/// What a claim checks.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Check {
    /// That this program's computation did what was asked (converged, met δ_d, met T_d). A failure
    /// means the figure is not a valid reproduction; the command exits with 3.
    Solver,
    /// A statement of the paper about the results. A failure is a finding, reported with its numbers.
    Paper,
}

/// One checked claim.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Claim {
    pub check: Check,
    /// Where it applies: a run name, or `figure` for the whole figure.
    pub scope: String,
    /// The paper's statement (quoted where it quotes).
    pub statement: String,
    /// What this program measures and the threshold.
    pub test: String,
    /// With branches: every branch passes.
    pub pass: bool,
    /// The measured numbers, in words with units (with branches: the unmoved start's branch).
    pub measured: String,
    /// Where the run sits on a knife edge (its moved starts reached more than one optimum): the
    /// claim held to each optimum, never one picked by rounding.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub branches: Vec<BranchVerdict>,
    /// The branches disagree: the verdict is decided by which optimum a run reaches.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub split: bool,
}

/// A claim's verdict on one optimum of a knife edge ([`spine_design::knife_edge::Branch`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BranchVerdict {
    /// The branch's index among the run's knife-edge branches.
    pub branch: usize,
    /// `J` at the branch's optimum, J.
    pub objective: f64,
    /// How many of the starts (the unmoved one and the moved ones) reached it.
    pub starts: usize,
    /// Whether the unmoved start reached it (this build's run).
    pub unmoved: bool,
    /// Whether a moved start reached it (or failed so): only such branches decide the verdict. A
    /// branch only the unmoved start reached is shown, not counted (a fact about rounding).
    pub counted: bool,
    pub pass: bool,
    pub measured: String,
}

impl Claim {
    /// A statement of the paper.
    pub fn new(scope: &str, statement: &str, test: impl Into<String>, pass: bool, measured: impl Into<String>) -> Self {
        Self {
            check: Check::Paper,
            scope: scope.into(),
            statement: statement.into(),
            test: test.into(),
            pass,
            measured: measured.into(),
            branches: Vec::new(),
            split: false,
        }
    }

    /// A check of this program's own computation.
    pub fn solver(
        scope: &str,
        statement: &str,
        test: impl Into<String>,
        pass: bool,
        measured: impl Into<String>,
    ) -> Self {
        Self { check: Check::Solver, ..Self::new(scope, statement, test, pass, measured) }
    }

    /// The same claims held to each branch of a knife edge: `per_branch[b]` is the list of claims
    /// for branch `b` (the same statements in the same order, as one function makes them for each
    /// branch's design). The verdict is over the counted branches (those moved starts reached):
    /// `pass` where every one passes, `split` where they disagree; `measured` is the unmoved
    /// start's counted branch's, else the first counted branch's.
    pub fn branched(per_branch: Vec<(BranchOf, Vec<Claim>)>) -> Vec<Claim> {
        let lead = per_branch
            .iter()
            .position(|(of, _)| of.counted && of.unmoved)
            .or_else(|| per_branch.iter().position(|(of, _)| of.counted))
            .unwrap_or(0);
        let Some((_, first)) = per_branch.get(lead) else {
            return Vec::new();
        };
        let mut claims = first.clone();
        for (k, claim) in claims.iter_mut().enumerate() {
            claim.branches = per_branch
                .iter()
                .enumerate()
                .filter_map(|(b, (of, list))| {
                    let c = list.get(k).filter(|c| c.statement == claim.statement && c.test == claim.test)?;
                    Some(BranchVerdict {
                        branch: b,
                        objective: of.objective,
                        starts: of.starts,
                        unmoved: of.unmoved,
                        counted: of.counted,
                        pass: c.pass,
                        measured: c.measured.clone(),
                    })
                })
                .collect();
            let counted: Vec<bool> = claim.branches.iter().filter(|b| b.counted).map(|b| b.pass).collect();
            claim.pass = counted.iter().all(|p| *p);
            claim.split = counted.iter().any(|p| *p != counted[0]);
        }
        claims
    }

    /// `PASS`, `FAIL`, or `SPLIT` where the branches of a knife edge disagree.
    pub fn verdict(&self) -> &'static str {
        if self.split {
            "SPLIT"
        } else if self.pass {
            "PASS"
        } else {
            "FAIL"
        }
    }
}

/// What a claim's branch is: its optimum's `J` (J), how many starts reached it, whether the
/// unmoved start is among them and whether a moved start is ([`BranchVerdict::counted`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BranchOf {
    pub objective: f64,
    pub starts: usize,
    pub unmoved: bool,
    pub counted: bool,
}

impl BranchVerdict {
    /// The branch's verdict in words, as the command line and the reports write it: `branch B
    /// (J = … J, N starts[, the unmoved start's[ only: not counted]]): PASS|FAIL, measured`.
    pub fn text(&self) -> String {
        let whose = match (self.unmoved, self.counted) {
            (true, true) => ", the unmoved start's",
            (true, false) => ", the unmoved start's only: not counted",
            _ => "",
        };
        let verdict = if self.pass { "PASS" } else { "FAIL" };
        format!(
            "branch {} (J = {:.6e} J, {} starts{whose}): {verdict}, {}",
            self.branch, self.objective, self.starts, self.measured
        )
    }
}

impl std::fmt::Display for Claim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} [{}] {} — {}: {}", self.verdict(), self.scope, self.statement, self.test, self.measured)?;
        for b in self.branches.iter().filter(|_| self.branches.len() > 1) {
            write!(f, "; {}", b.text())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn of(objective: f64, starts: usize, unmoved: bool, counted: bool) -> BranchOf {
        BranchOf { objective, starts, unmoved, counted }
    }

    fn claims(first: bool, second: bool) -> Vec<Claim> {
        vec![
            Claim::new("n10", "A", "a > 1", first, format!("a = {first}")),
            Claim::solver("n10", "B", "b", second, "b"),
        ]
    }

    #[test]
    fn a_claim_held_to_each_branch_is_split_where_the_counted_branches_disagree() {
        let made = Claim::branched(vec![
            (of(1.0, 3, false, true), claims(true, true)),
            (of(1.0, 2, true, true), claims(false, true)),
        ]);
        assert_eq!(made.len(), 2);
        let (a, b) = (&made[0], &made[1]);
        assert!(a.split && !a.pass && a.verdict() == "SPLIT", "{a}");
        // The unmoved start's branch gives the headline numbers.
        assert_eq!(a.measured, "a = false");
        assert_eq!(a.branches.len(), 2);
        assert!(a.branches[1].unmoved && !a.branches[0].unmoved);
        assert!(b.pass && !b.split && b.verdict() == "PASS", "{b}");
        assert!(a.to_string().contains("branch 0") && a.to_string().contains("branch 1"), "{a}");
    }

    #[test]
    fn a_branch_only_the_unmoved_start_reached_is_shown_but_does_not_decide() {
        let made = Claim::branched(vec![
            (of(1.0, 4, false, true), claims(true, true)),
            (of(2.0, 1, true, false), claims(false, false)),
        ]);
        let a = &made[0];
        assert!(a.pass && !a.split, "{a}");
        assert_eq!(a.measured, "a = true");
        assert!(!a.branches[1].counted && !a.branches[1].pass);
        assert!(made[1].pass);
        assert!(Claim::branched(Vec::new()).is_empty());
    }
}
