//! `spine sensitivity`: an eq. (33) optimum (one start, full space) and its derivatives with
//! respect to the case's parameters ([`spine_design::sensitivity`]), with a CSV per parameter.
//!
//! Modules: `differentiate` (the polishing re-solve and the derivatives, or why there are none),
//! `not_clean` (why a result is not clean), `figure` (every design run of a figure case).

mod differentiate;
mod figure;
mod not_clean;

pub use differentiate::{differentiate, NoSensitivity};
pub use figure::{run_figure_sensitivity, FigureSensitivityResult, RunSensitivity, SkippedRun};
pub use not_clean::NotClean;

use crate::design::{run_design_case, DesignCaseResult};
use crate::error::RunError;
use crate::files::OutputFile;
use crate::overrides::DesignOverrides;
use crate::progress::Progress;
use crate::workers::Workers;
use serde::Serialize;
use spine_case::{CaseError, DesignCase, ValidDesign};
use spine_design::sensitivity::{Derivative, SensitivityReport};

#[derive(Clone, Debug, Serialize)]
pub struct SensitivityResult {
    pub title: String,
    pub design: DesignCaseResult,
    /// `None` when the reported optimum is not clean (the design's status and warnings say why).
    /// The derivatives belong to that optimum re-solved tightly from itself (`J` within 1e-6).
    pub sensitivity: Option<SensitivityReport>,
    /// Why there is no `sensitivity` block, where there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_sensitivity: Option<NoSensitivity>,
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
    overrides.apply(&mut valid)?;
    let names = if names.is_empty() { c.default_parameters() } else { names.to_vec() };
    names.iter().try_for_each(|name| c.parameter_value(name).map(|_| ()))?;
    let clock = std::time::Instant::now();
    let design = run_design_case(c, &valid, workers, progress)?;
    let solve_seconds = clock.elapsed().as_secs_f64();
    progress(Progress::Done { message: format!("the optimum's derivatives for {} parameters", names.len()) });
    let (differentiated, polish_seconds) = if design.result.is_clean() {
        differentiate(c, &valid, &names, &design.result)?
    } else {
        (Err(NoSensitivity::OptimumNotClean), 0.0)
    };
    let (sensitivity, no_sensitivity) = match differentiated {
        Ok(report) => (Some(report), None),
        Err(why) => (None, Some(why)),
    };
    let files =
        sensitivity.as_ref().map(|s| s.parameters.iter().map(|p| csv_name(&p.name)).collect()).unwrap_or_default();
    let sensitivity_seconds = clock.elapsed().as_secs_f64() - solve_seconds - polish_seconds;
    let not_clean = NotClean::of(&design, sensitivity.as_ref(), no_sensitivity.as_ref());
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
        let (report, _) = differentiate(c, valid, &names, &result.result)?;
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
fn table(derivatives: &[(&str, &Derivative)]) -> crate::Table {
    let mut out = crate::Table::new();
    for (direction, d) in derivatives {
        let rows = d.stiffness.len();
        let angle = |v: &[f64]| (0..rows).map(|j| v.get(j).copied()).collect::<Vec<_>>();
        out.extend(
            crate::Table::new()
                .labels("direction", std::iter::repeat_n(direction, rows))
                .counts("link", 1..=rows)
                .optional("dtheta0_rad", angle(&d.theta0))
                .numbers("dstiffness_Nm_per_rad", d.stiffness.iter().copied())
                .optional("dtheta1_rad", angle(&d.theta1))
                .optional("dtheta2_rad", angle(&d.theta2)),
        );
    }
    out
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
                OutputFile::table(csv_name(&p.name), table(&rows))
            })
            .collect()
    }
}

impl std::fmt::Display for SensitivityResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.design)?;
        let Some(report) = &self.sensitivity else {
            let why = self.no_sensitivity.as_ref().unwrap_or(&NoSensitivity::OptimumNotClean);
            return writeln!(f, "NO SENSITIVITIES: {why}");
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
            c.reduced_kkt_inertia.map_or("not computed".into(), |[p, n, z]| format!("(n₊, n₋, n₀) = ({p}, {n}, {z})")),
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
            writeln!(f, "  {} = {}: {text}", p.name, p.value)?;
        }
        Ok(())
    }
}
