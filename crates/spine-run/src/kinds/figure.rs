//! Kind `figure`: every run of a figure case, then its recipe's panels, tables and checked claims.

use crate::animation::{Animation, AnimationOptions};
use crate::claims::{Check, Claim};
use crate::error::RunError;
use crate::files::{FileContent, OutputFile};
use crate::kind::{FigureRun, KindOutput};
use crate::output::RunOutput;
use crate::progress::Progress;
use crate::recipes::{FigureRecipes, NamedRun};
use crate::table::Table;
use serde::Serialize;
use serde_json::{Map, Value};
use spine_case::{FigureCase, Notes, ValidRun};

/// One run of a figure with its result.
#[derive(Clone, Debug, Serialize)]
pub struct FigureRunResult {
    pub name: String,
    pub label: String,
    pub kind: &'static str,
    pub result: RunOutput,
    pub wall_seconds: f64,
}

/// `result.json` of kind `figure`.
#[derive(Clone, Debug, Serialize)]
pub struct FigureResult {
    pub figure: String,
    pub title: String,
    pub notes: Notes,
    pub claims: Vec<Claim>,
    pub claims_passed: usize,
    pub claims_total: usize,
    /// Numbers the report and the cross-figure checks read back.
    pub summary: Map<String, Value>,
    /// The files written beside `result.json`.
    pub files: Vec<String>,
    pub runs: Vec<FigureRunResult>,
    pub total_seconds: f64,
    #[serde(skip)]
    pub figures: Vec<(String, spine_plot::Figure)>,
    #[serde(skip)]
    pub tables: Vec<(String, Table)>,
    /// File stem → animation (written as `STEM.gif`).
    #[serde(skip)]
    pub animations: Vec<(String, Animation)>,
}

/// Runs every run of `case` (checked as `runs`) with `figure_run` (the registry's dispatch), then
/// its recipe; its animations (if any) are drawn with `animation`, or the default options.
pub fn run_figure(
    case: &FigureCase,
    runs: &[ValidRun],
    recipes: &dyn FigureRecipes,
    figure_run: &FigureRun,
    workers: Option<&crate::workers::Workers>,
    animation: Option<AnimationOptions>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<FigureResult, RunError> {
    let title = case.shown_title();
    let clock = std::time::Instant::now();
    progress(Progress::Done { message: format!("{title} ({} runs)", runs.len()) });
    let mut results = Vec::new();
    for (index, r) in runs.iter().enumerate() {
        let stage = format!("run {} ({})", r.name, r.case.kind());
        let started = std::time::Instant::now();
        let run_workers = workers.map(|w| w.for_run(&r.name));
        let output = figure_run(&r.case, run_workers.as_ref(), &mut |p| match p {
            Progress::Step { done, total, .. } => progress(Progress::Step { stage: &stage, done, total }),
            Progress::Done { .. } => progress(p),
        })
        .map_err(|e| RunError::InRun { index, name: r.name.clone(), source: Box::new(e) })?;
        let wall_seconds = started.elapsed().as_secs_f64();
        progress(Progress::Done { message: format!("  {stage} done in {wall_seconds:.2} s") });
        results.push(FigureRunResult {
            name: r.name.clone(),
            label: r.label.clone(),
            kind: r.case.kind(),
            result: output,
            wall_seconds,
        });
    }
    let named: Vec<NamedRun<'_>> =
        results.iter().map(|r| NamedRun { name: &r.name, label: &r.label, output: &r.result }).collect();
    let made = recipes
        .draw(&case.figure, &title, &named)
        .map_err(|error| RunError::Recipe { figure: case.figure.clone(), error })?;
    let mut files: Vec<String> = made.tables.iter().map(|(name, _)| name.clone()).collect();
    for (stem, _) in &made.figures {
        files.push(format!("{stem}.svg"));
        files.push(format!("{stem}.png"));
        files.push(format!("{stem}.pdf"));
    }
    let mut animations = made.animations;
    for (stem, a) in &mut animations {
        files.push(format!("{stem}.gif"));
        a.options = animation.unwrap_or(a.options);
    }
    Ok(FigureResult {
        figure: case.figure.clone(),
        title,
        notes: case.notes.clone(),
        claims_passed: made.claims.iter().filter(|c| c.pass).count(),
        claims_total: made.claims.len(),
        claims: made.claims,
        summary: made.summary,
        files,
        runs: results,
        total_seconds: clock.elapsed().as_secs_f64(),
        figures: made.figures,
        tables: made.tables,
        animations,
    })
}

impl crate::KindOutput for FigureResult {
    /// Every solver check passed (a failed solver check means the figure is not a valid
    /// reproduction; a failed claim of the paper is a finding, not a failure).
    fn is_clean(&self) -> bool {
        self.claims.iter().all(|c| c.pass || c.check != Check::Solver)
    }

    /// The recipe's CSV tables, then its figures, then its animations.
    fn files(&self) -> Vec<OutputFile> {
        let tables = self.tables.iter().map(|(name, table)| OutputFile::table(name.clone(), table.clone()));
        let figures = self
            .figures
            .iter()
            .map(|(stem, fig)| OutputFile { name: stem.clone(), content: FileContent::Figure(fig.clone()) });
        let animations = self
            .animations
            .iter()
            .map(|(stem, a)| OutputFile { name: stem.clone(), content: FileContent::Animation(a.clone()) });
        tables.chain(figures).chain(animations).collect()
    }
}

impl std::fmt::Display for FigureResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "claims ({} of {} PASS):", self.claims_passed, self.claims_total)?;
        for c in &self.claims {
            writeln!(f, "  {c}")?;
        }
        if !self.is_clean() {
            writeln!(f, "a solver check FAILED: this figure is not a valid reproduction (see the claims above)")?;
        }
        Ok(())
    }
}

impl crate::RunKind for FigureCase {
    type Output = FigureResult;
    /// Figs. 9–11 draw animations.
    const MOVES: bool = true;

    fn run(&self, cx: &mut crate::RunContext<'_>) -> Result<FigureResult, RunError> {
        let workers = cx.overrides.workers.as_ref();
        run_figure(self, &self.validate()?, cx.recipes, cx.figure_run, workers, cx.overrides.animation, cx.progress)
    }
}
