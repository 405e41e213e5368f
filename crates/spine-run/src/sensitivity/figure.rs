//! `spine sensitivity` on a figure case: each design run's optimum and its derivatives.

use super::{run_design_sensitivity, SensitivityResult};
use crate::error::RunError;
use crate::files::OutputFile;
use crate::overrides::DesignOverrides;
use crate::progress::Progress;
use crate::workers::Workers;
use serde::Serialize;
use spine_case::CaseError;

/// `spine sensitivity` on a figure case: the sensitivities of each static design run's optimum
/// (the figure's dynamics runs have no eq. (33) optimum and are listed as skipped).
#[derive(Clone, Debug, Serialize)]
pub struct FigureSensitivityResult {
    pub figure: String,
    pub title: String,
    pub runs: Vec<RunSensitivity>,
    /// Runs that are not design cases.
    pub skipped: Vec<SkippedRun>,
}

/// A run of a figure that is not a design case (it has no eq. (33) optimum to differentiate).
#[derive(Clone, Debug, Serialize)]
pub struct SkippedRun {
    pub name: String,
    pub kind: &'static str,
}

impl std::fmt::Display for SkippedRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({})", self.name, self.kind)
    }
}

/// One design run of a figure with its sensitivities.
#[derive(Clone, Debug, Serialize)]
pub struct RunSensitivity {
    pub name: String,
    pub label: String,
    pub result: SensitivityResult,
}

/// The sensitivities of every design run of a figure case (`runs`: the figure's validated runs),
/// each run as [`run_design_sensitivity`] runs a design case.
pub fn run_figure_sensitivity(
    case: &spine_case::FigureCase,
    runs: &[spine_case::ValidRun],
    overrides: &DesignOverrides,
    workers: Option<&Workers>,
    names: &[String],
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<FigureSensitivityResult, RunError> {
    let mut out = Vec::new();
    let mut skipped = Vec::new();
    for (index, run) in runs.iter().enumerate() {
        let spine_case::Case::Design(c) = &run.case else {
            skipped.push(SkippedRun { name: run.name.clone(), kind: run.case.kind() });
            continue;
        };
        // The optimum each panel draws from the run's own start is differentiated; a figure's
        // census of the best design (`multistart.confidence`) is not repeated here.
        let mut c = c.clone();
        c.multistart.confidence = None;
        let mut result = run_design_sensitivity(&c, overrides, workers, names, progress)
            .map_err(|e| RunError::InRun { index, name: run.name.clone(), source: Box::new(e) })?;
        result.files.iter_mut().for_each(|f| *f = format!("{}_{f}", run.name));
        out.push(RunSensitivity { name: run.name.clone(), label: run.label.clone(), result });
    }
    if out.is_empty() {
        let message = format!(
            "figure {:?} has no design runs to differentiate (its runs: {})",
            case.figure,
            crate::text::joined(&skipped)
        );
        return Err(RunError::Case(CaseError::invalid("runs", message)));
    }
    let title = case.shown_title();
    Ok(FigureSensitivityResult { figure: case.figure.clone(), title, runs: out, skipped })
}

impl crate::KindOutput for FigureSensitivityResult {
    fn not_clean_reasons(&self) -> Vec<String> {
        let reasons = |run: &RunSensitivity| {
            run.result.not_clean.iter().map(|r| format!("{}: {r}", run.name)).collect::<Vec<_>>()
        };
        self.runs.iter().flat_map(reasons).collect()
    }

    /// Clean when every design run's sensitivities are.
    fn is_clean(&self) -> bool {
        self.runs.iter().all(|r| r.result.is_clean())
    }

    /// Each run's CSVs, prefixed with the run's name: `<run>_sensitivity_<name>.csv`.
    fn files(&self) -> Vec<OutputFile> {
        self.runs
            .iter()
            .flat_map(|r| {
                r.result.files().into_iter().map(move |mut f| {
                    f.name = format!("{}_{}", r.name, f.name);
                    f
                })
            })
            .collect()
    }
}

impl std::fmt::Display for FigureSensitivityResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "{}: sensitivities of {} design runs", self.title, self.runs.len())?;
        for r in &self.runs {
            writeln!(f, "── run {} ({}) ──", r.name, r.label)?;
            r.result.fmt(f)?;
        }
        if !self.skipped.is_empty() {
            writeln!(f, "skipped (not design runs): {}", crate::text::joined(&self.skipped))?;
        }
        Ok(())
    }
}
