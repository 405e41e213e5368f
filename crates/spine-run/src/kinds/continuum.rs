//! Kind `continuum`: eq. (33) for one rod at a ladder of `N` (`spine_continuum::design_study`):
//! `J*(N)`, the optimal profiles, the active-bound pattern and a Richardson estimate of `J*∞`.

use crate::files::{FileContent, OutputFile};
use crate::table::Table;
use serde::Serialize;
use spine_case::ContinuumCase;
use spine_continuum::design::RodDesign;
use spine_continuum::design_figure::figure;
use spine_continuum::design_study::{runs, study, RodStudy, StudySettings};

/// `result.json` of kind `continuum`.
#[derive(Clone, Debug, Serialize)]
pub struct ContinuumResult {
    pub title: String,
    pub rod: RodDesign,
    pub settings: StudySettings,
    pub study: RodStudy,
    pub total_seconds: f64,
}

impl ContinuumResult {
    /// One row per level: `N`, `J*`, the kept attempt's status and certificate, the pattern's
    /// switches and soft share, time.
    pub fn levels_table(&self) -> Table {
        let levels = &self.study.levels;
        Table::new()
            .counts("links", levels.iter().map(|l| l.links))
            .numbers("objective_J", levels.iter().map(|l| l.result.objective))
            .labels("status", levels.iter().map(|l| l.result.solver.status.to_string()))
            .labels("certificate", levels.iter().map(certificate))
            .labels("clean", levels.iter().map(|l| l.result.is_clean()))
            .counts("switches", levels.iter().map(|l| l.switches))
            .numbers("soft_share", levels.iter().map(|l| l.soft_share))
            .numbers("theta0_at_bound_share", levels.iter().map(|l| l.theta0_at_bound_share))
            .numbers("curvature_at_bound_share", levels.iter().map(|l| l.curvature_at_bound_share))
            .counts("first_run_iterations", levels.iter().map(|l| l.attempts.iter().map(|a| a.first_run_iterations).sum()))
            .labels("pattern_runs", levels.iter().map(|l| runs(&l.pattern)))
    }

    /// Every level's profiles in one long table: `links, x_m, quantity, value` (`theta0_rad` at
    /// the links' middles, `EI_Nm2` at the joints).
    pub fn profiles_table(&self) -> Table {
        let mut table = Table::new();
        for level in &self.study.levels {
            let theta = &level.result.design.theta0;
            let rows = theta.len() + level.bending_stiffness.len();
            table.extend(
                Table::new()
                    .counts("links", std::iter::repeat_n(level.links, rows))
                    .numbers("x_m", level.x_links.iter().chain(&level.x_joints).copied())
                    .labels(
                        "quantity",
                        std::iter::repeat_n("theta0_rad", theta.len())
                            .chain(std::iter::repeat_n("EI_Nm2", level.bending_stiffness.len())),
                    )
                    .numbers("value", theta.iter().chain(&level.bending_stiffness).copied()),
            );
        }
        table
    }
}

fn certificate(level: &spine_continuum::design_study::RodOptimum) -> String {
    level.result.certificate.as_ref().map_or("none".into(), |c| c.status.name().to_string())
}

impl crate::KindOutput for ContinuumResult {
    /// Every level kept a clean optimum that is not certified `not_a_minimum`.
    fn is_clean(&self) -> bool {
        self.study.levels.iter().all(|l| l.is_clean())
    }

    fn files(&self) -> Vec<OutputFile> {
        vec![
            OutputFile { name: "continuum".into(), content: FileContent::Figure(figure(&self.study)) },
            OutputFile::table("levels.csv", self.levels_table()),
            OutputFile::table("profiles.csv", self.profiles_table()),
        ]
    }

    fn not_clean_reasons(&self) -> Vec<String> {
        self.study
            .levels
            .iter()
            .filter(|l| !l.is_clean())
            .map(|l| {
                format!(
                    "N = {}: no attempt ended clean and certified ({})",
                    l.links,
                    l.attempts.iter().map(|a| a.status.name()).collect::<Vec<_>>().join(", ")
                )
            })
            .collect()
    }
}

impl std::fmt::Display for ContinuumResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let title = if self.title.is_empty() { "eq. (33) for one rod as N grows" } else { &self.title };
        writeln!(f, "{title}")?;
        writeln!(
            f,
            "{:>7} {:>16} {:>28} {:>16} {:>6} {:>9} {:>8}  EI pattern (L lower, U upper, f between)",
            "N", "J* (J)", "status", "certificate", "clean", "switches", "time (s)"
        )?;
        for l in &self.study.levels {
            writeln!(
                f,
                "{:>7} {:>16.9e} {:>28} {:>16} {:>6} {:>9} {:>8.2}  {}",
                l.links,
                l.result.objective,
                l.result.solver.status.to_string(),
                certificate(l),
                if l.is_clean() { "yes" } else { "NO" },
                l.switches,
                l.wall_seconds,
                runs(&l.pattern)
            )?;
        }
        match &self.study.richardson {
            Some(r) => writeln!(
                f,
                "Richardson through N = {}, {}, {}: J*∞ = {:.9e} J, order {:.2}, the finest level {:.1e} from it",
                r.links[0], r.links[1], r.links[2], r.limit, r.order, r.remaining
            )?,
            None => writeln!(f, "no Richardson estimate: the last three clean levels' changes do not shrink with one sign")?,
        }
        writeln!(f, "total {:.1} s", self.total_seconds)
    }
}

impl crate::RunKind for ContinuumCase {
    type Output = ContinuumResult;

    fn run(&self, cx: &mut crate::RunContext<'_>) -> Result<ContinuumResult, crate::RunError> {
        let valid = self.validate()?;
        let clock = std::time::Instant::now();
        let total = valid.links.len();
        let mut done = 0;
        let study = study(&valid.rod, &valid.links, &valid.settings, &mut |_, _| {
            done += 1;
            (cx.progress)(crate::Progress::Step { stage: "levels", done, total });
        })
        .map_err(crate::RunError::Design)?;
        Ok(ContinuumResult {
            title: self.title.clone(),
            rod: valid.rod,
            settings: valid.settings,
            study,
            total_seconds: clock.elapsed().as_secs_f64(),
        })
    }
}
