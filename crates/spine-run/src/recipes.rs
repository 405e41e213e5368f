//! The recipes that draw a figure case's runs ([`FigureRecipes`]; the paper's are
//! `spine_paper::PaperFigures`): what a recipe reads ([`NamedRun`]) and what it makes
//! ([`FigureOutput`]).

use crate::animation::Animation;
use crate::claims::Claim;
use crate::output::RunOutput;
use crate::table::Table;
use serde_json::{Map, Value};
use spine_check::FieldError;

/// The recipes that turn a figure case's runs into its panels, tables and checked claims, by the
/// figure's name (`"figure": "fig6"`). The paper's are `spine_paper::PaperFigures`.
pub trait FigureRecipes: Sync {
    /// Draws the runs of figure `figure`. Errors say which run does not fit the recipe.
    /// The error names the run that does not fit (`runs.NAME`) or the figure (`figure`).
    fn draw(&self, figure: &str, title: &str, runs: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError>;
}

/// No recipes: a figure case is refused ([`RunError::Recipe`](crate::RunError::Recipe)). For callers that run only
/// solver kinds.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoRecipes;

impl FigureRecipes for NoRecipes {
    fn draw(&self, figure: &str, _: &str, _: &[NamedRun<'_>]) -> Result<FigureOutput, FieldError> {
        Err(FieldError::new(
            "figure",
            format!("no recipe for {figure:?}: figure cases are drawn by spine-paper's recipes"),
        ))
    }
}

/// A run of a figure, with its result: what a recipe reads.
pub struct NamedRun<'a> {
    pub name: &'a str,
    pub label: &'a str,
    pub output: &'a RunOutput,
}

impl NamedRun<'_> {
    /// A recipe's refusal of this run, named `runs.NAME`.
    pub fn error(&self, message: impl Into<String>) -> FieldError {
        FieldError::new(format!("runs.{}", self.name), message)
    }

    /// The label, or the name when the case gives none.
    pub fn title(&self) -> &str {
        if self.label.is_empty() {
            self.name
        } else {
            self.label
        }
    }
}

/// Everything a recipe makes.
#[derive(Default)]
pub struct FigureOutput {
    /// File stem → figure (written as `STEM.svg`, `STEM.png` and `STEM.pdf`).
    pub figures: Vec<(String, spine_plot::Figure)>,
    /// File name → CSV text.
    pub tables: Vec<(String, Table)>,
    /// File stem → animation of the chain's motion (written as `STEM.gif`).
    pub animations: Vec<(String, Animation)>,
    pub claims: Vec<Claim>,
    /// Numbers the report and the cross-figure checks read back (`result.json` → `summary`).
    pub summary: Map<String, Value>,
}
