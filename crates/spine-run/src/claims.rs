//! A claim of the paper, checked by the program: what the paper says, what is measured and the
//! threshold it is held to (fixed before the run), the verdict and the numbers.

use serde::Serialize;

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
    pub pass: bool,
    /// The measured numbers, in words with units.
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

    /// `PASS` or `FAIL`.
    pub fn verdict(&self) -> &'static str {
        if self.pass {
            "PASS"
        } else {
            "FAIL"
        }
    }
}

impl std::fmt::Display for Claim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} [{}] {} — {}: {}", self.verdict(), self.scope, self.statement, self.test, self.measured)
    }
}
