//! Kind `design`: eq. (33) with Ipopt from the case's start, and optionally from seeded
//! multi-starts; also the eq. (33) run a figure or a dynamic case depends on.

use crate::confidence::{Batches, ConfidenceCensus};
use crate::error::RunError;
use crate::output::{BestDesign, KnifeEdgeDesigns, StaticDesign};
use crate::progress::Progress;
use crate::workers::{solve_starts, Task, Workers};
use serde::Serialize;
use spine_case::{DesignCase, ValidDesign};
use spine_design::adjoint::adjoint_hand;
use spine_design::knife_edge::{moved_starts, KnifeEdge};
use spine_design::multistart::{cluster, feasible_starts, settle_all, ConfidenceRun, MultiStartSummary};
use spine_design::result::DesignResult;
use spine_design::settings::SolverPreset;
use spine_design::solver_run::SolverRun;
use spine_model::{Design, State};

/// The passive and loaded states of a result, where it has both.
pub(crate) fn states(result: &DesignResult) -> Option<(State, State)> {
    let (p, l) = (result.passive.as_ref()?, result.loaded.as_ref()?);
    Some((State { theta: p.theta.clone(), lambda: p.lambda }, State { theta: l.theta.clone(), lambda: l.lambda }))
}

/// Eq. (33) from `start`. Ipopt stops at its next iteration when a stop is requested (the run
/// returns [`RunError::Interrupted`]) or the time limit passes (its status says `time_limit`).
fn solve(valid: &ValidDesign, start: &Design) -> Result<DesignResult, RunError> {
    settled(valid, solve_unchecked(valid, start)?)
}

/// The optimum a run reports, as the case's preset reports it ([`spine_design::solve::Solver::report`]):
/// checked, and with the exact preset certified to second order and left for a lower minimum
/// where it is not one.
pub(crate) fn settled(valid: &ValidDesign, run: SolverRun) -> Result<DesignResult, RunError> {
    let result = valid.solver().report(&valid.problem, run).map_err(RunError::Design)?;
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    Ok(result)
}

/// Eq. (33) from `start`, before the result's check ([`SolverRun::check`]); an interrupt is
/// [`RunError::Interrupted`].
fn solve_unchecked(valid: &ValidDesign, start: &Design) -> Result<SolverRun, RunError> {
    let run = valid.solver().run(&valid.problem, start, &mut |_| true).map_err(RunError::Design)?;
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    Ok(run)
}

/// Eq. (33) from the case's start; with `multistart.confidence`, also the best optimum of a census
/// to that confidence (seeded starts in this process, `census_to`).
/// Each run from a start is repeated from its moved starts (the case's `knife_edge`,
/// [`spine_design::knife_edge`]).
pub fn run_design(valid: &ValidDesign, workers: Option<&Workers>) -> Result<StaticDesign, RunError> {
    let mut design = run_design_alone(valid, workers)?;
    design.knife_edge = knife_edge(valid, &design.result, workers)?;
    if valid.fmincon_like_beside {
        let fmincon = valid.with_preset(SolverPreset::FminconLike);
        let mut beside = static_design(&fmincon, solve(&fmincon, &fmincon.start)?);
        beside.knife_edge = knife_edge(&fmincon, &beside.result, workers)?;
        design.fmincon_like = Some(Box::new(beside));
    }
    Ok(design)
}

/// The knife-edge check of the run from the case's start, whose settled result is `own`: eq. (33)
/// from each of its moved starts ([`moved_starts`], in `workers` when given), settled as the case's
/// preset settles a run, and the optima they and `own` reached, each branch's run kept for the
/// claims. `None` with `knife_edge.pairs = 0`.
fn knife_edge(
    valid: &ValidDesign,
    own: &DesignResult,
    workers: Option<&Workers>,
) -> Result<Option<Box<KnifeEdgeDesigns>>, RunError> {
    if valid.knife_edge.pairs == 0 {
        return Ok(None);
    }
    let moved = moved_starts(&valid.problem, &valid.start, &valid.knife_edge);
    let fmincon_like = valid.preset == SolverPreset::FminconLike;
    let tasks: Vec<Task> = moved.iter().map(|m| Task { fmincon_like, ..Task::start(m) }).collect();
    let runs = solve_all(valid, &tasks, workers, &mut |_| {})?;
    if runs.len() < tasks.len() {
        // A time limit passed: the check is incomplete, and no edge is reported from part of it.
        return Ok(None);
    }
    let mut results = vec![own.clone()];
    results.extend(settle_all(&valid.problem, runs, &valid.solver()).map_err(RunError::Design)?);
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    let edge = KnifeEdge::of(&valid.knife_edge, &results);
    let designs = edge.branches.iter().map(|b| static_design(valid, results[b.starts[0]].clone())).collect();
    let failed = edge.failed.iter().find(|(k, _)| *k > 0).map(|(k, _)| static_design(valid, results[*k].clone()));
    Ok(Some(Box::new(KnifeEdgeDesigns { edge, designs, failed })))
}

/// [`run_design`] without the fmincon-like solve beside it.
fn run_design_alone(valid: &ValidDesign, workers: Option<&Workers>) -> Result<StaticDesign, RunError> {
    let Some(target) = valid.multistart.confidence else {
        return Ok(static_design(valid, solve(valid, &valid.start)?));
    };
    // The census's start 0 is the case's own start, settled as `solve` settles it.
    let own = solve_unchecked(valid, &valid.start)?;
    let (results, confidence) = census_to(valid, own, target, workers, &mut |_| {})?;
    let mut design = static_design(valid, results[0].clone());
    let summary = cluster(results, valid.multistart.seed);
    if let Some(best) = summary.best_clean() {
        // The best optimum leads the list, so its image is the clean optimum that names it.
        let image = summary.optima.iter().find(|o| o.clean && o.mirror_of == Some(0));
        design.best = Some(Box::new(BestDesign {
            design: static_design(valid, best.result.clone()),
            reported_start: best.starts[0],
            same_as_start: best.starts.contains(&0),
            optima: summary.optima.iter().filter(|o| o.clean).count(),
            census: summary.census.clone(),
            confidence,
            mirror_image: image.map(|o| static_design(valid, o.result.clone())),
        }));
    }
    Ok(design)
}

/// A result with the projected start it is measured from and its hand-adjoint gradients.
fn static_design(valid: &ValidDesign, result: DesignResult) -> StaticDesign {
    let (start, _) = valid.problem.project_start(&valid.start);
    let gradients = states(&result).and_then(|(s1, s2)| adjoint_hand(&valid.problem, &result.design, &s1, &s2).ok());
    StaticDesign {
        result,
        start,
        gradients,
        problem: valid.problem.clone(),
        best: None,
        preset: valid.preset,
        fmincon_like: None,
        knife_edge: None,
    }
}

/// `result.json` of kind `design`: the solver's result from the case's start or, with
/// multi-start, the best clean optimum found (the headline, the exit code and the top-level
/// fields all describe the same run), with the multi-start summary (every distinct optimum with
/// its full result).
#[derive(Clone, Debug, Serialize)]
pub struct DesignCaseResult {
    pub title: String,
    /// The start whose run the top-level fields describe: 0 is the case's own start, `k ≥ 1` the
    /// k-th seeded start. With multi-start, the first start that reached the best clean optimum,
    /// or 0 when no start ended clean.
    pub reported_start: usize,
    #[serde(flatten)]
    pub result: DesignResult,
    pub multistart: Option<MultiStartSummary>,
    /// With `--sensitivity`: the derivatives of the reported optimum (re-solved tightly from it)
    /// with respect to the case's parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<spine_design::sensitivity::SensitivityReport>,
}

/// Eq. (33) from the case's start, then from `valid.multistart.starts` seeded feasible starts (in
/// `workers` processes when given with more than one job: the same census).
pub fn run_design_case(
    case: &DesignCase,
    valid: &ValidDesign,
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<DesignCaseResult, RunError> {
    let own = solve_unchecked(valid, &valid.start)?;
    if let Some(target) = valid.multistart.confidence {
        return to_confidence(case, valid, own, target, workers, progress);
    }
    let seeded = feasible_starts(&valid.problem, valid.multistart.starts, valid.multistart.seed);
    let tasks: Vec<Task> = seeded.iter().map(Task::seeded).collect();
    let mut runs = vec![own];
    runs.extend(solve_all(valid, &tasks, workers, progress)?);
    census(case, valid, runs)
}

/// A census to a stated confidence as a design case's result ([`census_to`]).
fn to_confidence(
    case: &DesignCase,
    valid: &ValidDesign,
    own: SolverRun,
    target: f64,
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<DesignCaseResult, RunError> {
    let (results, confidence) = census_to(valid, own, target, workers, progress)?;
    Ok(confidence_result(case, valid, results, confidence))
}

/// The result of a census to a stated confidence from its settled results in start order (one
/// machine, or the merge of its batches' shards: the same bytes).
pub fn confidence_result(
    case: &DesignCase,
    valid: &ValidDesign,
    results: Vec<DesignResult>,
    confidence: ConfidenceRun,
) -> DesignCaseResult {
    let mut used = valid.clone();
    used.multistart.starts = results.len() - 1;
    let mut result = reported(case, &used, results);
    if let Some(summary) = result.multistart.as_mut() {
        summary.confidence = Some(confidence);
    }
    result
}

/// A census to a stated confidence: seeded starts (the same sequence as `--starts` draws, so a
/// run to confidence that stops after `k` starts is the run with `--starts k`) in batches of
/// [`CONFIDENCE_BATCH`], each batch solved (in `workers`) and settled, until the estimate gives
/// P(a better optimum unseen) ≤ `target`, the cap `multistart.starts` (0: `MAX_STARTS`) is
/// reached, or a time limit passes. The settled results in start order (`own` first) and how
/// the census ran.
pub fn census_to(
    valid: &ValidDesign,
    own: SolverRun,
    target: f64,
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<(Vec<DesignResult>, ConfidenceRun), RunError> {
    let mut census = ConfidenceCensus::new(valid, target, own)?;
    while let Some(starts) = Batches::new(valid).seeded(census.batches() + 1) {
        let drawn = feasible_starts(&valid.problem, *starts.end(), valid.multistart.seed);
        let batch: Vec<Task> = drawn[*starts.start() - 1..].iter().map(Task::seeded).collect();
        let runs = solve_all(valid, &batch, workers, progress)?;
        let complete = runs.len() == batch.len();
        if census.add_batch(runs)? || !complete {
            break;
        }
    }
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    Ok(census.finish())
}

/// Eq. (33), unchecked, for each of `tasks` in order (in `workers` processes when given with
/// more than one job), with the multi-start's progress. A time limit ends it early: the runs
/// completed come back; an interrupt is [`RunError::Interrupted`].
pub fn solve_all(
    valid: &ValidDesign,
    tasks: &[Task],
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<SolverRun>, RunError> {
    let total = tasks.len();
    if total == 0 {
        return Ok(Vec::new());
    }
    let mut runs = Vec::new();
    match workers.filter(|w| w.jobs > 1) {
        Some(w) => {
            progress(Progress::Step { stage: "multi-start", done: 0, total });
            runs = solve_starts(w, tasks, &mut |k| progress(Progress::Step { stage: "multi-start", done: k, total }))?;
        }
        None => {
            for (k, task) in tasks.iter().enumerate() {
                progress(Progress::Step { stage: "multi-start", done: k, total });
                if spine_stop::check().is_some() {
                    // Time limit: the census holds the starts run so far (`multistart.starts` says how many).
                    break;
                }
                runs.push(solve_unchecked(&task.case(valid), &task.start)?);
            }
        }
    }
    progress(Progress::Step { stage: "multi-start", done: runs.len(), total });
    Ok(runs)
}

/// The result of a design case from its runs in start order (`runs[0]` from the case's own
/// start), each reported as the case's preset reports it ([`settle_all`]): the run itself without
/// multi-start, else the census headed by the best clean optimum.
pub fn census(case: &DesignCase, valid: &ValidDesign, runs: Vec<SolverRun>) -> Result<DesignCaseResult, RunError> {
    let results = settle_all(&valid.problem, runs, &valid.solver()).map_err(RunError::Design)?;
    if spine_stop::interrupt_requested() {
        return Err(RunError::Interrupted);
    }
    Ok(reported(case, valid, results))
}

/// The result of a design case from its settled results in start order.
fn reported(case: &DesignCase, valid: &ValidDesign, mut results: Vec<DesignResult>) -> DesignCaseResult {
    let title = if case.title.is_empty() { "design".to_string() } else { case.title.clone() };
    if valid.multistart.starts == 0 && results.len() == 1 {
        let result = results.remove(0);
        return DesignCaseResult { title, reported_start: 0, result, multistart: None, sensitivity: None };
    }
    let own = results[0].clone();
    let summary = cluster(results, valid.multistart.seed);
    let (reported_start, result) = match summary.best_clean() {
        Some(best) => (best.starts[0], best.result.clone()),
        None => (0, own),
    };
    DesignCaseResult { title, reported_start, result, multistart: Some(summary), sensitivity: None }
}

impl crate::KindOutput for DesignCaseResult {
    /// The reported run ended clean (see [`DesignResult::is_clean`]): with multi-start, some start
    /// reached a clean optimum.
    fn is_clean(&self) -> bool {
        self.result.is_clean() && self.multistart.as_ref().and_then(|m| m.confidence.as_ref()).is_none_or(|c| c.reached)
    }
}
