//! `spine sensitivity`: an eq. (33) optimum (one start, full space) and its derivatives with
//! respect to the case's parameters ([`spine_design::sensitivity`]), with a CSV per parameter.

use crate::design::{run_design_case, states, DesignCaseResult, DesignOverrides};
use crate::error::RunError;
use crate::files::OutputFile;
use crate::progress::Progress;
use crate::workers::Workers;
use serde::Serialize;
use spine_case::{CaseError, DesignCase, ValidDesign};
use spine_design::sensitivity::{polish, sensitivities, Derivative, Optimum, Parameter, SensitivityReport};
use spine_design::DesignResult;
use std::fmt::Write;

/// `result.json` of `spine sensitivity`: the optimum and its sensitivities.
#[derive(Clone, Debug, Serialize)]
pub struct SensitivityResult {
    pub title: String,
    pub design: DesignCaseResult,
    /// `None` when the reported optimum is not clean (the design's status and warnings say why).
    /// The derivatives belong to that optimum re-solved tightly from itself (`J` within 1e-6).
    pub sensitivity: Option<SensitivityReport>,
    /// Why there is no `sensitivity` block, where there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_sensitivity: Option<String>,
    /// Why the result is not clean (exit code 3), one entry per reason; absent when it is clean.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub not_clean: Vec<NotClean>,
    pub files: Vec<String>,
    /// Wall times (under `timings` in `result.json`): the design solve, the polishing re-solve,
    /// and the sensitivities themselves (active set, one factorisation, a solve per parameter).
    pub solve_seconds: f64,
    pub polish_seconds: f64,
    pub sensitivity_seconds: f64,
}

/// The design case run as `spine design` runs it (its own start, and a multi-start when the case
/// or the overrides ask for one, in `workers`), then the derivatives of the reported optimum with
/// respect to `names` (the case's field paths; empty:
/// [`spine_case::DesignCase::default_parameters`]).
pub fn run_design_sensitivity(
    c: &DesignCase,
    overrides: &DesignOverrides,
    workers: Option<&Workers>,
    names: &[String],
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<SensitivityResult, RunError> {
    let mut valid = c.validate()?;
    overrides.apply(&mut valid);
    let names = if names.is_empty() { c.default_parameters() } else { names.to_vec() };
    names.iter().try_for_each(|name| c.parameter_value(name).map(|_| ()))?;
    let clock = std::time::Instant::now();
    let design = run_design_case(c, &valid, workers, progress)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    progress(Progress::Done { message: format!("the optimum's derivatives for {} parameters", names.len()) });
    let (differentiated, polish_seconds) = if design.result.is_clean() {
        differentiate(c, &valid, overrides, &names, &design.result)?
    } else {
        (Err("the optimum is not clean (see the design's status and warnings)".into()), 0.0)
    };
    let (sensitivity, no_sensitivity) = match differentiated {
        Ok(report) => (Some(report), None),
        Err(why) => (None, Some(why)),
    };
    let files =
        sensitivity.as_ref().map(|s| s.parameters.iter().map(|p| csv_name(&p.name)).collect()).unwrap_or_default();
    let sensitivity_seconds = clock.elapsed().as_secs_f64() - solve_seconds - polish_seconds;
    let not_clean = NotClean::of(&design, sensitivity.as_ref(), no_sensitivity.as_deref());
    Ok(SensitivityResult {
        title: design.title.clone(),
        design,
        sensitivity,
        no_sensitivity,
        not_clean,
        files,
        solve_seconds,
        polish_seconds,
        sensitivity_seconds,
    })
}

/// The sensitivities of a design case's optimum `first` (a clean result of `valid`'s problem):
/// re-solved tightly from it (see `spine_design::sensitivity::polish`), then, when that ends clean
/// on the same optimum, differentiated with respect to `names`. Returns the report (or why there
/// is none: the polishing solve's status, or how far it moved `J`) and the polishing solve's wall
/// time.
pub fn differentiate(
    c: &DesignCase,
    valid: &ValidDesign,
    overrides: &DesignOverrides,
    names: &[String],
    first: &DesignResult,
) -> Result<(Result<SensitivityReport, String>, f64), RunError> {
    let values = names.iter().map(|name| c.parameter_value(name)).collect::<Result<Vec<f64>, CaseError>>()?;
    let problem = &valid.problem;
    let clock = std::time::Instant::now();
    let polished = polish(problem, &first.design, &valid.settings).map_err(RunError::Design)?;
    let multipliers = polished.multipliers.clone();
    let design = polished.check(problem, &valid.settings);
    let polish_seconds = clock.elapsed().as_secs_f64();
    let moved = (design.objective - first.objective).abs() / first.objective.abs().max(1e-12);
    let shape_moved =
        design.design.theta0.iter().zip(&first.design.theta0).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    // The same optimum as the certificate judges it (`J` within 1e-6, or a little lower along a
    // flat valley of `K` with the same shape); another local optimum moves more.
    let same = spine_design::certificate::same_optimum(first, &design);
    let why_not = if !design.is_clean() {
        Some(format!(
            "the polishing re-solve (tol 1e-12) from the optimum did not end clean: {} after {} iterations{}",
            design.solver.status,
            design.solver.iterations,
            design.warnings.iter().map(|w| format!("; {w}")).collect::<String>()
        ))
    } else if !same {
        Some(format!(
            "the polishing re-solve (tol 1e-12) moved J by {moved:.1e} relative (to {:.10e} J) and θ0 by {shape_moved:.1e} rad: another optimum",
            design.objective
        ))
    } else {
        None
    };
    let (Some(multipliers), None, Some((passive, loaded))) = (&multipliers, &why_not, states(&design)) else {
        let why = why_not.unwrap_or_else(|| "the polished optimum has no multipliers or equilibria".into());
        return Ok((Err(why), polish_seconds));
    };
    let layout = design.solver.layout(problem.n_links());
    let heights = problem.node_heights(&design.design.theta0);
    let x = layout.pack(&design.design, problem.stiffness_scale, &passive, &loaded, &heights);
    let parameters: Vec<Parameter<'_>> = names
        .iter()
        .zip(&values)
        .map(|(name, &value)| Parameter {
            name: name.clone(),
            value,
            problem_at: Box::new(move |v| {
                let mut changed = c.with_parameter(name, v).and_then(|c| c.validate()).map_err(|e| e.to_string())?;
                overrides.apply(&mut changed);
                Ok(changed.problem)
            }),
        })
        .collect();
    let optimum = Optimum { problem, layout, x: &x, multipliers };
    let report = sensitivities(&optimum, &parameters)
        .map_err(|e| RunError::Case(CaseError::invalid("--param", e.to_string())))?;
    Ok((Ok(report), polish_seconds))
}

/// With `spine design --sensitivity` (`overrides.sensitivity`): the derivatives of `result`'s
/// reported optimum, when it is clean, in its `sensitivity` block (the single run and a merge of
/// its shards both call this).
pub(crate) fn attach(
    c: &DesignCase,
    valid: &ValidDesign,
    overrides: &DesignOverrides,
    result: &mut crate::design::DesignCaseResult,
) -> Result<(), RunError> {
    if overrides.sensitivity && result.result.is_clean() {
        let names = c.default_parameters();
        let (report, _) = differentiate(c, valid, overrides, &names, &result.result)?;
        result.sensitivity = report.ok();
    }
    Ok(())
}

/// The parameters to differentiate by: each name written plainly
/// ([`spine_case::canonical_parameter`]) and given once (`loads.p_y[2]` twice, or as
/// `loads.p_y[02]`, is one parameter). Refuses, before any work, a parameter that is not a number
/// of a design case's physics, or two whose CSV files would have one name.
pub(crate) fn parameter_names(case: &spine_case::Case, given: &[String]) -> Result<Vec<String>, RunError> {
    let mut names: Vec<String> = Vec::new();
    for name in given.iter().map(|n| spine_case::canonical_parameter(n)) {
        if !names.contains(&name) {
            names.push(name);
        }
    }
    if let spine_case::Case::Design(c) = case {
        for name in &names {
            c.parameter_value(name)?;
        }
    }
    let mut files: Vec<(String, &String)> = names.iter().map(|n| (csv_name(n), n)).collect();
    files.sort();
    if let Some(w) = files.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(RunError::Case(CaseError::invalid(
            "--param",
            format!(
                "`{}` and `{}` name the same parameter; give it once",
                spine_check::shown(w[0].1),
                spine_check::shown(w[1].1)
            ),
        )));
    }
    Ok(names)
}

/// `sensitivity_<name>.csv`, with the path's punctuation as `_`.
fn csv_name(name: &str) -> String {
    let stem: String = name.chars().map(|ch| if ch.is_ascii_alphanumeric() { ch } else { '_' }).collect();
    format!("sensitivity_{}.csv", stem.trim_end_matches('_'))
}

/// One row per link (and the end spring): `i, dθ0, dK, dθ1, dθ2` of the two-sided derivative, or
/// of the one-sided ones for an increase and a decrease.
fn csv(derivatives: &[(&str, &Derivative)]) -> String {
    let mut out = String::from("direction,link,dtheta0_rad,dstiffness_Nm_per_rad,dtheta1_rad,dtheta2_rad\n");
    for (direction, d) in derivatives {
        for j in 0..d.stiffness.len() {
            let angle = |v: &[f64]| v.get(j).map_or(String::new(), |x| format!("{x:e}"));
            let _ = writeln!(
                out,
                "{direction},{},{},{:e},{},{}",
                j + 1,
                angle(&d.theta0),
                d.stiffness[j],
                angle(&d.theta1),
                angle(&d.theta2)
            );
        }
    }
    out
}

/// Why a sensitivity result is not clean (in `result.json`: `{"reason": "no_derivative", …}`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum NotClean {
    /// The optimum is not clean: its status, warnings and certificate say why.
    Optimum { status: spine_ipopt::Status },
    /// No sensitivities were computed, and why.
    NoSensitivities { why: String },
    /// A parameter has neither a two-sided derivative nor both one-sided ones, and why.
    NoDerivative { parameter: String, why: String },
}

impl NotClean {
    /// The reasons a result with this optimum and these sensitivities is not clean (none: clean).
    fn of(design: &DesignCaseResult, report: Option<&SensitivityReport>, no_sensitivity: Option<&str>) -> Vec<Self> {
        let mut reasons = Vec::new();
        if !design.result.is_clean() {
            reasons.push(Self::Optimum { status: design.result.solver.status });
        }
        match report {
            None => reasons
                .push(Self::NoSensitivities { why: no_sensitivity.unwrap_or("the optimum is not clean").to_string() }),
            Some(report) => reasons.extend(
                report
                    .parameters
                    .iter()
                    .filter(|p| p.derivative.is_none() && (p.increase.is_none() || p.decrease.is_none()))
                    .map(|p| Self::NoDerivative {
                        parameter: p.name.clone(),
                        why: p.note.clone().unwrap_or_else(|| "the conditions fail".into()),
                    }),
            ),
        }
        reasons
    }
}

impl std::fmt::Display for NotClean {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Optimum { status } => {
                write!(f, "the optimum is not clean (Ipopt: {status}; see its warnings and certificate)")
            }
            Self::NoSensitivities { why } => write!(f, "no sensitivities: {why}"),
            Self::NoDerivative { parameter, why } => write!(f, "no derivative with respect to {parameter}: {why}"),
        }
    }
}

impl crate::KindOutput for SensitivityResult {
    fn not_clean_reasons(&self) -> Vec<String> {
        self.not_clean.iter().map(ToString::to_string).collect()
    }

    /// Clean: the optimum is clean and every parameter has its derivative, two-sided or as the
    /// pair of one-sided ones (where LICQ or strict complementarity fails for some parameters,
    /// the others' derivatives still hold; `conditions` says which condition failed). Otherwise
    /// [`SensitivityResult::not_clean`] says why.
    fn is_clean(&self) -> bool {
        self.not_clean.is_empty()
    }

    /// A CSV per parameter.
    fn files(&self) -> Vec<OutputFile> {
        let Some(report) = &self.sensitivity else { return Vec::new() };
        report
            .parameters
            .iter()
            .map(|p| {
                let rows: Vec<(&str, &Derivative)> = match (&p.derivative, &p.increase, &p.decrease) {
                    (Some(d), _, _) => vec![("both", d)],
                    (None, up, down) => {
                        up.iter().map(|d| ("increase", d)).chain(down.iter().map(|d| ("decrease", d))).collect()
                    }
                };
                OutputFile::text(csv_name(&p.name), csv(&rows))
            })
            .collect()
    }
}

impl std::fmt::Display for SensitivityResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.design)?;
        let Some(report) = &self.sensitivity else {
            return writeln!(
                f,
                "NO SENSITIVITIES: {}",
                self.no_sensitivity.as_deref().unwrap_or("the optimum is not clean")
            );
        };
        let c = &report.conditions;
        writeln!(
            f,
            "conditions {}: {} free variables, {} at bounds, {} active rows; LICQ σ_min {}; smallest active multiplier {}, smallest inactive gap {}; reduced KKT inertia {} ({}){}",
            if c.hold { "hold" } else { "FAIL" },
            c.free_variables,
            c.active_variable_bounds,
            c.active_rows,
            c.licq_smallest_singular_value.map_or("not computed".into(), |v| format!("{v:.3e}")),
            c.smallest_active_multiplier.map_or("none".into(), |v| format!("{v:.3e}")),
            c.smallest_inactive_gap.map_or("none".into(), |v| format!("{v:.3e}")),
            c.reduced_kkt_inertia.map_or("not computed".into(), |[p, n, z]| format!("[{p}, {n}, {z}]")),
            if c.second_order_sufficient { "second-order sufficient" } else { "NOT second-order sufficient" },
            if c.weakly_active.is_empty() { String::new() } else { format!("; weakly active: {}", c.weakly_active.join("; ")) }
        )?;
        writeln!(
            f,
            "times: solve {:.3} s, polish {:.3} s, sensitivities of {} parameters {:.3} s",
            self.solve_seconds,
            self.polish_seconds,
            report.parameters.len(),
            self.sensitivity_seconds
        )?;
        for p in &report.parameters {
            let summary = |d: &Derivative| {
                let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                format!(
                    "dJ*/dp {:.6e} (direct {:.6e}), max |dθ0*/dp| {:.3e}, max |dK*/dp| {:.3e}",
                    d.objective,
                    d.objective_direct,
                    largest(&d.theta0),
                    largest(&d.stiffness)
                )
            };
            let text = match (&p.derivative, &p.increase, &p.decrease) {
                (Some(d), _, _) => summary(d),
                (None, Some(up), Some(down)) => {
                    format!("one-sided: increase {}; decrease {}", summary(up), summary(down))
                }
                _ => "not computed (the conditions fail)".into(),
            };
            writeln!(
                f,
                "  {} = {}{}: {text}",
                p.name,
                p.value,
                if p.affine { "" } else { " (not affine: central difference)" }
            )?;
        }
        Ok(())
    }
}

/// `spine sensitivity` on a figure case: the sensitivities of each static design run's optimum
/// (the figure's dynamics runs have no eq. (33) optimum and are listed as skipped).
#[derive(Clone, Debug, Serialize)]
pub struct FigureSensitivityResult {
    pub figure: String,
    pub title: String,
    pub runs: Vec<RunSensitivity>,
    /// Runs that are not design cases, by name with their kind.
    pub skipped: Vec<String>,
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
            skipped.push(format!("{} ({})", run.name, run.case.kind()));
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
        let message =
            format!("figure {:?} has no design runs to differentiate (its runs: {})", case.figure, skipped.join(", "));
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
            writeln!(f, "skipped (not design runs): {}", self.skipped.join(", "))?;
        }
        Ok(())
    }
}
