//! One dispatch per kind. A kind's runner implements [`RunKind`] on its case type and its result
//! implements [`KindOutput`]; the registry of case kinds (`spine_case::case_kinds!`, one line per
//! kind) then makes, through [`define_results!`](crate::define_results), the one result enum
//! [`KindResult`](crate::KindResult) (its serde tag is the kind's name) and the one dispatch
//! ([`run_kind`](crate::run_kind), [`in_figure`](crate::in_figure), [`moves`](crate::moves)). No other
//! code matches on a case's kind to run it.
//!
//! The registry itself (the macro's expansion for the workspace's kinds) is in `registry.rs`, above
//! the runners; this file is below them. Adding a kind (docs/case-format.md, "Adding a kind"): its
//! case type in spine-case, its line in the registry, its runner (`impl RunKind`), its section in
//! docs/case-format.md and a paper case. The test in `registry.rs` registers a small kind of its own
//! the same way.

use crate::error::RunError;
use crate::files::OutputFile;
use crate::output::RunOutput;
use crate::overrides::Overrides;
use crate::progress::Progress;
use crate::recipes::FigureRecipes;

/// What a runner is given besides its case.
pub struct RunContext<'a> {
    /// Changes from the command line or the Python call.
    pub overrides: &'a Overrides,
    /// The recipes that draw figure cases.
    pub recipes: &'a dyn FigureRecipes,
    /// Where a long run reports how far it is.
    pub progress: &'a mut dyn FnMut(Progress<'_>),
    /// How a figure runs its runs: the registry's dispatch ([`crate::in_figure`]), handed down so
    /// that the figure's runner does not depend on the registry that holds it.
    pub figure_run: &'a FigureRun,
}

/// A case run as a run of a figure ([`RunKind::in_figure`] of its kind), with the worker
/// processes its multi-start may use (already pointed at this run of the figure).
pub type FigureRun = dyn Fn(&spine_case::Case, Option<&crate::workers::Workers>, &mut dyn FnMut(Progress<'_>)) -> Result<RunOutput, RunError>
    + Sync;

/// The result of a kind: `result.json`'s body (serialised with the kind's name as its `"kind"`),
/// the summary a person reads (`Display`), whether it is clean (exit code 0, else 3) and the
/// files written beside it.
pub trait KindOutput: serde::Serialize + std::fmt::Display + Clone + std::fmt::Debug {
    /// Clean: every solver converged, every equilibrium reported is stable and every solver check
    /// passed.
    fn is_clean(&self) -> bool;

    /// The files written beside `result.json` (CSV tables, figures), in writing order.
    fn files(&self) -> Vec<OutputFile> {
        Vec::new()
    }

    /// Why the result is not clean, one line each, where it carries its reasons as a typed field;
    /// empty otherwise (the summary says why).
    fn not_clean_reasons(&self) -> Vec<String> {
        Vec::new()
    }
}

/// How a case type runs.
pub trait RunKind {
    /// What a run gives.
    type Output: KindOutput;

    /// Whether the kind's runs move, so that `--animate` can draw them.
    const MOVES: bool = false;

    /// Whether a figure may hold the kind's runs: its [`RunKind::in_figure`] gives one. The
    /// registry names the kinds that say so when a figure's run is of another kind.
    const IN_FIGURE: bool = false;

    /// Checks the case (with its overrides) and runs it.
    fn run(&self, cx: &mut RunContext<'_>) -> Result<Self::Output, RunError>;

    /// The run as a run of a figure (what a recipe draws: a value of the kind's own type,
    /// [`RunOutput::new`]), or `None` for a kind a figure cannot hold ([`RunKind::IN_FIGURE`]
    /// false); `workers` may solve its multi-start (the figure's `--jobs`).
    fn in_figure(
        &self,
        _workers: Option<&crate::workers::Workers>,
        _progress: &mut dyn FnMut(Progress<'_>),
    ) -> Option<Result<RunOutput, RunError>> {
        None
    }
}

/// Makes the result enum and the dispatch of a list of kinds (the registry's, or a test's own):
/// `KindResult` (one variant per kind, holding its runner's output, and one per command that is
/// not a kind: `study`, `sensitivity`, `figure_sensitivity`, `sweep`), `run_kind`, `in_figure` and
/// `moves`. `Case` is the case enum of the same list, in scope where this is expanded.
#[doc(hidden)]
#[macro_export]
macro_rules! define_results {
    ($( $(#[$doc:meta])* $kind:ident($parsed:ty) = $name:literal, )+) => {
        $crate::define_results! {
            @kinds [$( $(#[$doc])* $kind($parsed) = $name, )+]
            @commands [
                /// `spine study`: the C_K study of eq. (34) on a design case.
                Study($crate::study::StudyResult) = "study",
                /// `spine sensitivity` on a design case.
                Sensitivity($crate::sensitivity::SensitivityResult) = "sensitivity",
                /// `spine sensitivity` on a figure case: each design run's sensitivities.
                FigureSensitivity($crate::sensitivity::FigureSensitivityResult) = "figure_sensitivity",
                /// `spine sweep`: an optimum followed along a parameter.
                Sweep($crate::sweep::SweepCaseResult) = "sweep",
            ]
        }
    };
    (
        @kinds [$( $(#[$kdoc:meta])* $kind:ident($parsed:ty) = $kname:literal, )+]
        @commands [$( $(#[$cdoc:meta])* $command:ident($output:ty) = $cname:literal, )+]
    ) => {
        /// What any case computed, by kind: `"kind"` in `result.json` is the kind's name (the
        /// case file's; `study`, `sensitivity`, `figure_sensitivity` and `sweep` for the
        /// commands of those names), derived here and nowhere else.
        #[derive(Clone, Debug, serde::Serialize)]
        #[serde(tag = "kind")]
        // One value per run: boxing the large variants would buy nothing.
        #[allow(clippy::large_enum_variant)]
        pub enum KindResult {
            $( $(#[$kdoc])* #[serde(rename = $kname)] $kind(<$parsed as $crate::RunKind>::Output), )+
            $( $(#[$cdoc])* #[serde(rename = $cname)] $command($output), )+
        }

        impl KindResult {
            /// `result.json`'s `"kind"` (serde's tag of the variant), without serialising.
            pub fn kind(&self) -> &'static str {
                match self {
                    $( Self::$kind(_) => $kname, )+
                    $( Self::$command(_) => $cname, )+
                }
            }

            /// See [`KindOutput::is_clean`]($crate::KindOutput::is_clean).
            pub fn is_clean(&self) -> bool {
                match self {
                    $( Self::$kind(r) => $crate::KindOutput::is_clean(r), )+
                    $( Self::$command(r) => $crate::KindOutput::is_clean(r), )+
                }
            }

            /// See [`KindOutput::files`]($crate::KindOutput::files).
            pub fn files(&self) -> Vec<$crate::OutputFile> {
                match self {
                    $( Self::$kind(r) => $crate::KindOutput::files(r), )+
                    $( Self::$command(r) => $crate::KindOutput::files(r), )+
                }
            }

            /// See [`KindOutput::not_clean_reasons`]($crate::KindOutput::not_clean_reasons).
            pub fn not_clean_reasons(&self) -> Vec<String> {
                match self {
                    $( Self::$kind(r) => $crate::KindOutput::not_clean_reasons(r), )+
                    $( Self::$command(r) => $crate::KindOutput::not_clean_reasons(r), )+
                }
            }
        }

        impl std::fmt::Display for KindResult {
            /// The summary a user reads: status, the numbers that show it, and warnings.
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                match self {
                    $( Self::$kind(r) => std::fmt::Display::fmt(r, f), )+
                    $( Self::$command(r) => std::fmt::Display::fmt(r, f), )+
                }
            }
        }

        /// Runs a case of any kind with its runner ([`RunKind::run`]($crate::RunKind::run)).
        pub fn run_kind(case: &Case, cx: &mut $crate::RunContext<'_>) -> Result<KindResult, $crate::RunError> {
            match case {
                $( Case::$kind(c) => $crate::RunKind::run(c, cx).map(KindResult::$kind), )+
            }
        }

        /// Runs a case as a run of a figure ([`RunKind::in_figure`]($crate::RunKind::in_figure)).
        pub fn in_figure(
            case: &Case,
            workers: Option<&$crate::workers::Workers>,
            progress: &mut dyn FnMut($crate::Progress<'_>),
        ) -> Result<$crate::RunOutput, $crate::RunError> {
            let refused = || $crate::RunError::WrongKind {
                command: "a figure's run",
                needs: format!("{} case", figure_kinds()).into(),
                kind: case.kind(),
            };
            match case {
                $( Case::$kind(c) if <$parsed as $crate::RunKind>::IN_FIGURE =>
                    $crate::RunKind::in_figure(c, workers, progress).unwrap_or_else(|| Err(refused())), )+
                _ => Err(refused()),
            }
        }

        /// The kinds a figure may hold ([`RunKind::IN_FIGURE`]($crate::RunKind::IN_FIGURE)), as
        /// an error names them: `a "twolink", "design" or "simulate"`.
        pub fn figure_kinds() -> String {
            let kinds: Vec<String> = [$( (<$parsed as $crate::RunKind>::IN_FIGURE, $kname), )+]
                .into_iter()
                .filter(|(held, _)| *held)
                .map(|(_, name)| format!("\"{name}\""))
                .collect();
            match kinds.split_last() {
                None => "no".to_string(),
                Some((last, [])) => format!("a {last}"),
                Some((last, rest)) => format!("a {} or {last}", rest.join(", ")),
            }
        }

        /// Whether a case's runs move ([`RunKind::MOVES`]($crate::RunKind::MOVES)).
        pub fn moves(case: &Case) -> bool {
            match case {
                $( Case::$kind(_) => <$parsed as $crate::RunKind>::MOVES, )+
            }
        }
    };
}
