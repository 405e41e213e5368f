//! `spine sweep`: eq. (33)'s optimum followed along one parameter of a design case
//! ([`spine_design::sweep`]), with a census (multi-start) at every k-th point saying whether the
//! followed optimum is still the best known.

use crate::design::{run_design_case, DesignCaseResult};
use crate::error::RunError;
use crate::files::{FileContent, OutputFile};
use crate::overrides::DesignOverrides;
use crate::progress::Progress;
use crate::sweep_census::{case_at, census};
pub use crate::sweep_census::{CensusPlan, CensusPoint};
use crate::table::Table;
use crate::workers::Workers;
use serde::Serialize;
use spine_case::{CaseError, DesignCase};
use spine_check::FieldError;
use spine_design::sweep::settings::SweepSettings;
use spine_design::sweep::{PointStatus, Sweep, SweepError, SweepResult};
use spine_design::{DesignProblem, ProblemTangent};

/// `result.json` of `spine sweep`.
#[derive(Clone, Debug, Serialize)]
pub struct SweepCaseResult {
    pub title: String,
    /// The design run at the sweep's first value, whose reported optimum is followed.
    pub start: DesignCaseResult,
    pub sweep: SweepResult,
    pub census: Vec<CensusPoint>,
    pub files: Vec<String>,
    pub solve_seconds: f64,
    pub sweep_seconds: f64,
    pub census_seconds: f64,
}

/// The design case run as `spine design` runs it at `settings.from` (its start and multi-start),
/// then its reported optimum followed to `settings.to`, with a census as `plan` says.
pub fn run_design_sweep(
    c: &DesignCase,
    overrides: &DesignOverrides,
    workers: Option<&Workers>,
    name: &str,
    settings: SweepSettings,
    plan: Option<CensusPlan>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<SweepCaseResult, RunError> {
    c.parameter_value(name)?;
    settings.validate().map_err(|e| CaseError::invalid(format!("--{}", e.field.replace('_', "-")), e.message))?;
    let clock = std::time::Instant::now();
    let first = case_at(c, overrides, name, settings.from)?;
    let start = run_design_case(c, &first, workers, progress)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    progress(Progress::Done { message: format!("following the optimum over {} points", settings.points) });
    let problem_at = |v: f64| -> Result<DesignProblem, FieldError> {
        case_at(c, overrides, name, v).map(|valid| valid.problem).map_err(FieldError::from)
    };
    // The case maps each parameter affinely, so its rates are the same at every value.
    let tangent_at = |v: f64| -> Result<ProblemTangent, FieldError> {
        c.parameter_tangent(name, &problem_at(v)?).map_err(FieldError::from)
    };
    let sweep = Sweep::new(name, &problem_at, &tangent_at, &first.settings, settings).map_err(sweep_error)?;
    // A start that is not clean is the start run's finding (exit 3 with its result), as `spine
    // design` reports it, not bad input.
    let followed = if !start.result.is_clean() {
        let why = format!("the optimum at the sweep's start is not clean ({})", start.result.solver.status);
        SweepResult::unfollowed(name, settings, why)
    } else {
        match sweep.follow(&start.result.design) {
            Err(SweepError::Start(status)) => SweepResult::unfollowed(
                name,
                settings,
                format!("the tight re-solve of the start optimum did not end clean ({status})"),
            ),
            other => other.map_err(sweep_error)?,
        }
    };
    let sweep_seconds = clock.elapsed().as_secs_f64() - solve_seconds;
    let census = match plan {
        Some(plan) => census(c, overrides, workers, name, &followed, plan, progress)?,
        None => Vec::new(),
    };
    let census_seconds = clock.elapsed().as_secs_f64() - solve_seconds - sweep_seconds;
    Ok(SweepCaseResult {
        title: if c.title.is_empty() { "sweep".into() } else { c.title.clone() },
        start,
        sweep: followed,
        census,
        files: ["sweep.csv", "sweep.svg", "sweep.png", "sweep.pdf"].map(String::from).to_vec(),
        solve_seconds,
        sweep_seconds,
        census_seconds,
    })
}

fn sweep_error(e: SweepError) -> RunError {
    match e {
        SweepError::Solver(e) => RunError::Design(e),
        e => RunError::Case(CaseError::invalid("--param", e.to_string())),
    }
}

impl SweepCaseResult {
    /// One row per point: the parameter, `objective` (J*), θ0*, K*, the end displacement, the
    /// status, and the best-known J* where a census ran there.
    pub fn table(&self) -> Table {
        let points = &self.sweep.points;
        let n = points.first().map_or(0, |p| p.design.theta0.len());
        let mut table = Table::new()
            .numbers(self.sweep.parameter.clone(), points.iter().map(|p| p.parameter))
            .numbers("objective_J", points.iter().map(|p| p.objective));
        for i in 0..n {
            table = table.numbers(format!("theta0_{}_rad", i + 1), points.iter().map(|p| p.design.theta0[i]));
        }
        for j in 0..=n {
            table = table.numbers(format!("K_{}_Nm_per_rad", j + 1), points.iter().map(|p| p.design.stiffness[j]));
        }
        let best = |k: usize| self.census.iter().find(|c| c.point == k).and_then(|c| c.best_objective);
        table
            .optional("end_displacement_m", points.iter().map(|p| p.end_displacement))
            .labels("status", points.iter().map(|p| p.status.name()))
            .optional("best_known_objective_J", (0..points.len()).map(best))
    }
}

impl std::fmt::Display for SweepCaseResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.sweep;
        let start = &self.start.result;
        writeln!(
            f,
            "{}: the optimum at {} = {} (J* = {:.10e} J, {}) followed to {} over {} points",
            self.title,
            s.parameter,
            s.settings.from,
            start.objective,
            start.solver.status,
            s.settings.to,
            s.settings.points
        )?;
        let count = |status| s.points.iter().filter(|p| p.status == status).count();
        writeln!(
            f,
            "points: {} followed, {} after a jump, {} FAILED; {} corrector solves ({} Ipopt iterations, {} steps halved)",
            count(PointStatus::Followed),
            count(PointStatus::Jumped),
            count(PointStatus::Failed),
            s.solves,
            s.iterations,
            s.rejected_steps
        )?;
        writeln!(
            f,
            "times: start {:.3} s, sweep {:.3} s, census {:.3} s",
            self.solve_seconds, self.sweep_seconds, self.census_seconds
        )?;
        for e in &s.events {
            writeln!(
                f,
                "  event at {} = {:.6e} (in [{:.6e}, {:.6e}]): {} {}",
                s.parameter,
                e.parameter,
                e.bracket[0],
                e.bracket[1],
                e.kind.name(),
                e.what
            )?;
        }
        if let Some(why) = &s.not_followed {
            writeln!(f, "NOT FOLLOWED: {why}")?;
        }
        if let Some(reason) = s.stopped {
            let last = s.points.last().map_or("before its first point".into(), |p| {
                format!(
                    "after {} of {} points, at {} = {:.6e}",
                    s.points.len(),
                    s.settings.points,
                    s.parameter,
                    p.parameter
                )
            });
            writeln!(f, "STOPPED ({}) {last}: only the points computed are written", reason.name())?;
        }
        if let (Some(first), Some(last)) = (s.points.first(), s.points.last()) {
            writeln!(f, "J* from {:.6e} J to {:.6e} J", first.objective, last.objective)?;
        }
        for c in &self.census {
            writeln!(
                f,
                "  census at {} = {:.6e}: followed J* {:.6e} J, best known {} ({}){}",
                s.parameter,
                c.parameter,
                c.followed_objective,
                c.best_objective.map_or("none".into(), |b| format!("{b:.6e} J")),
                match (c.best_objective, c.followed_is_best) {
                    (None, _) => "the census found no clean optimum to compare with",
                    (Some(_), true) => "the followed optimum is the best known",
                    (Some(_), false) => "ANOTHER OPTIMUM IS BETTER",
                },
                c.estimate
                    .as_ref()
                    .and_then(|e| e.probability_better_unseen)
                    .map_or(String::new(), |p| { format!("; P(a better one unseen) {p:.3}") })
            )?;
            if let Some(reason) = c.stopped {
                writeln!(f, "    this census was cut short ({}): fewer starts than planned", reason.name())?;
            }
        }
        Ok(())
    }
}

impl crate::KindOutput for SweepCaseResult {
    /// Clean: every point computed (no stop), followed or jumped to a clean optimum (a failed
    /// point is not clean), every census complete.
    fn is_clean(&self) -> bool {
        self.sweep.stopped.is_none()
            && self.sweep.points.len() == self.sweep.settings.points
            && self.sweep.points.iter().all(|p| p.status != PointStatus::Failed)
            && self.census.iter().all(|c| c.stopped.is_none())
    }

    /// `sweep.csv` and the figure.
    fn files(&self) -> Vec<OutputFile> {
        vec![
            OutputFile::table("sweep.csv", self.table()),
            OutputFile {
                name: "sweep".into(),
                content: FileContent::Figure(crate::sweep_figure::figure(&self.title, &self.sweep, &self.census)),
            },
        ]
    }
}
