//! Running a case file: [`run_case`] (any kind) and [`run_study`] (the C_K study), each under
//! the run's time limit, to a typed [`CaseResult`].

use crate::error::{design_case, RunError};
use crate::kind::RunContext;
use crate::overrides::Overrides;
use crate::progress::Progress;
use crate::recipes::FigureRecipes;
use crate::registry::{moves, run_kind, KindResult};
use crate::result::CaseResult;
use spine_case::Case;
use spine_check::FieldError;

/// Runs `run` under `overrides.time_limit`; a run the limit stopped is marked, or, when the limit
/// left nothing to report (a figure whose recipe needs every run), is [`RunError::TimeLimit`].
fn limited(overrides: &Overrides, run: impl FnOnce() -> Result<KindResult, RunError>) -> Result<CaseResult, RunError> {
    let (result, reached) = spine_stop::with_time_limit(overrides.time_limit, run);
    let stopped = reached.then_some(spine_stop::StopReason::TimeLimit);
    match result {
        Ok(result) => Ok(CaseResult { result, stopped }),
        // A step that failed because it was stopped (an equilibrium path cut short looks like an
        // unstable start) is reported as the stop, not as its symptom.
        Err(_) if spine_stop::interrupt_requested() => Err(RunError::Interrupted),
        Err(e) if reached && !e.is_interrupted() => Err(RunError::TimeLimit {
            seconds: overrides.time_limit.map_or(0.0, |d| d.as_secs_f64()),
            cause: Box::new(e),
        }),
        Err(e) => Err(e),
    }
}

/// Checks `case`, applies `overrides` and runs it to its typed result: the one run path of every
/// kind (under [`Overrides::time_limit`] when set). A figure case's runs are drawn by `recipes`
/// (the paper's: `spine_paper::PaperFigures`; [`NoRecipes`](crate::NoRecipes) refuses figure cases).
///
/// ```
/// let text = r#"{
///   "kind": "equilibrium",
///   "chain": { "links": 2, "length_x": 1.0 },
///   "design": { "theta0": [0.2, -0.2], "stiffness": [0, 100, 0] },
///   "loads": { "p_y": [0, -10, 0], "p_x": -50 }
/// }"#;
/// let case = spine_case::Case::from_json(text).unwrap();
/// let result = spine_run::run_case(&case, &Default::default(), &spine_run::NoRecipes, &mut spine_run::quiet).unwrap();
/// assert!(result.is_clean()); // both equilibria found and certified stable
/// let json = result.to_json();
/// assert_eq!(json["loaded"]["stability"]["stable"], true);
/// assert_eq!(json["kind"], result.result.kind()); // the tag, without serialising
/// assert!(json["timings"]["passive_seconds"].is_number()); // wall times live under `timings`
/// ```
pub fn run_case(
    case: &Case,
    overrides: &Overrides,
    recipes: &dyn FigureRecipes,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<CaseResult, RunError> {
    if let Some(a) = &overrides.animation {
        a.validate().map_err(RunError::Option)?;
        if !moves(case) {
            return Err(RunError::Option(FieldError::new(
                "animation",
                format!(
                    "a \"{}\" case has no motion to animate (kinds simulate, damping, periodic and the figures fig9-fig11 do)",
                    case.kind()
                ),
            )));
        }
    }
    limited(overrides, || {
        run_kind(case, &mut RunContext { overrides, recipes, progress, figure_run: &crate::registry::in_figure })
    })
}

/// The C_K study of eq. (34) on a design case (overrides applied), over `values`.
pub fn run_study(
    case: &Case,
    overrides: &Overrides,
    values: &[f64],
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<CaseResult, RunError> {
    let c = design_case(case, "the C_K study")?;
    let mut valid = c.validate()?;
    overrides.design.apply(&mut valid)?;
    limited(overrides, || {
        Ok(KindResult::Study(crate::study::run_ck_study(
            &c.title,
            &valid,
            values,
            overrides.workers.as_ref(),
            progress,
        )?))
    })
}

/// `spine sensitivity`: eq. (33) on a design case (overrides applied, one start, full space) and
/// the derivatives of its optimum with respect to the case fields `names` (empty: the defaults);
/// on a figure case, the same for each of its design runs.
pub fn run_sensitivity(
    case: &Case,
    overrides: &Overrides,
    names: &[String],
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<CaseResult, RunError> {
    let names = &crate::sensitivity::parameter_names(case, names)?;
    limited(overrides, || {
        let workers = overrides.workers.as_ref();
        match case {
            Case::Design(c) => {
                let result =
                    crate::sensitivity::run_design_sensitivity(c, &overrides.design, workers, names, progress)?;
                Ok(KindResult::Sensitivity(result))
            }
            Case::Figure(c) => {
                let runs = c.validate()?;
                let result =
                    crate::sensitivity::run_figure_sensitivity(c, &runs, &overrides.design, workers, names, progress)?;
                Ok(KindResult::FigureSensitivity(result))
            }
            _ => Err(RunError::WrongKind {
                command: "`spine sensitivity`",
                needs: "a \"design\" or \"figure\" case".into(),
                kind: case.kind(),
            }),
        }
    })
}

/// `spine sweep`: the design case's optimum at `settings.from` followed to `settings.to` along the
/// case field `name` ([`crate::sweep::run_design_sweep`]), with a census as `plan` says.
pub fn run_sweep(
    case: &Case,
    overrides: &Overrides,
    name: &str,
    settings: spine_design::sweep::settings::SweepSettings,
    plan: Option<crate::sweep::CensusPlan>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<CaseResult, RunError> {
    let c = design_case(case, "`spine sweep`")?;
    spine_case::check_runs_memory("points", settings.points, c.chain.links)?;
    if let Some(p) = plan {
        let bad = |field: &str, m: String| RunError::Option(spine_check::FieldError::new(field, m));
        crate::option_values::census_starts(p.starts).map_err(|m| bad("census", m))?;
        crate::option_values::every(p.every).map_err(|m| bad("census_every", m))?;
    }
    limited(overrides, || {
        let workers = overrides.workers.as_ref();
        let result = crate::sweep::run_design_sweep(c, &overrides.design, workers, name, settings, plan, progress)?;
        Ok(KindResult::Sweep(result))
    })
}
