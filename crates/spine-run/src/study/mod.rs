//! The C_K study of eq. (34): one design case solved for C_K over half-decades, with Ipopt's own
//! scaling on and off, and the paper's statement "as the C_K is increased the stiffness variation
//! between the nodes increases whereas the change in orientation of the links is less apparent"
//! (Sec. 5.1) checked on the results.

use crate::claims::Claim;
use crate::design::run_design;
use crate::error::RunError;
use crate::files::{FileContent, OutputFile};
use crate::metrics::DesignChange;
use crate::progress::Progress;
use crate::table::Table;
use crate::workers::{solve_starts, Task, Workers};
use serde::Serialize;
use spine_case::ValidDesign;
use spine_design::{DesignResult, ScalingMethod};
use spine_plot::{Figure, Panel, Series};

/// `C_K = 10^(k/2)` for `k = 0..=8`: 1 to 10⁴ in half-decades.
pub fn half_decades() -> Vec<f64> {
    (0..=8).map(|k| 10f64.powf(0.5 * f64::from(k))).collect()
}

mod claims;
pub use claims::EFFECT;

/// One solver of the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CkSolver {
    /// The workspace's: the full space with the exact Hessian, with Ipopt's scaling on or off.
    Exact(ScalingMethod),
    /// Like the paper's fmincon (`SolverSettings::fmincon_like`): the reduced space (the
    /// equilibria solved inside, adjoint gradients), an L-BFGS Hessian, fmincon's default stopping
    /// rules, Ipopt's gradient-based scaling.
    FminconLike,
}

impl CkSolver {
    pub fn fmincon_like(self) -> bool {
        self == Self::FminconLike
    }

    /// The solver in words (the claims' scope, the table's and figure's labels).
    pub fn name(self) -> String {
        match self {
            Self::Exact(s) => format!("exact Hessian, scaling {}", scaling_name(s)),
            Self::FminconLike => "fmincon-like (reduced space, L-BFGS)".into(),
        }
    }

    /// The task of this solver at `stiffness_scale` from `start`.
    fn task(self, start: &spine_model::Design, stiffness_scale: f64) -> Task {
        let (scaling, fmincon_like) = match self {
            Self::Exact(s) => (s, false),
            Self::FminconLike => (ScalingMethod::GradientBased, true),
        };
        Task {
            start: start.clone(),
            stiffness_scale: Some(stiffness_scale),
            scaling: Some(scaling),
            fmincon_like,
            seeded: false,
        }
    }
}

/// The study's solvers, in the rows' order.
pub const SOLVERS: [CkSolver; 3] =
    [CkSolver::Exact(ScalingMethod::GradientBased), CkSolver::Exact(ScalingMethod::None), CkSolver::FminconLike];

/// One solve of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct CkRow {
    pub stiffness_scale: f64,
    pub solver: CkSolver,
    pub scaling: ScalingMethod,
    pub status: spine_ipopt::Status,
    /// Converged, constraints met, both equilibria stable, on the load path.
    pub clean: bool,
    /// The constraints met and both equilibria stable, converged or not.
    pub feasible: bool,
    pub iterations: usize,
    /// `J`, J.
    pub objective: f64,
    /// The second-order certificate's verdict on the reported point (`None`: not converged), and
    /// `J` at each point left on the way because it was not a minimum.
    pub certificate: Option<spine_design::certificate::MinimumStatus>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub left: Vec<f64>,
    pub change: DesignChange,
    pub theta0: Vec<f64>,
    pub stiffness: Vec<f64>,
    pub ipopt_seconds: f64,
}

/// The sweep's rows, in the order (solver, C_K).
#[derive(Clone, Debug, Serialize)]
pub struct CkStudy {
    pub rows: Vec<CkRow>,
}

fn scaling_name(s: ScalingMethod) -> &'static str {
    match s {
        ScalingMethod::GradientBased => "gradient-based",
        ScalingMethod::None => "none",
    }
}

/// Solves `case` for every `C_K` of `values` with each solver; `progress(done, total)`.
pub fn ck_study(
    case: &ValidDesign,
    values: &[f64],
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CkStudy, RunError> {
    let solvers: Vec<CkSolver> = SOLVERS.iter().flat_map(|&s| values.iter().map(move |_| s)).collect();
    let tasks: Vec<Task> = SOLVERS.iter().flat_map(|s| values.iter().map(|&ck| s.task(&case.start, ck))).collect();
    let total = tasks.len();
    let row = |solver: CkSolver, task: &Task, r: &DesignResult| {
        let valid = task.case(case);
        let (start, _) = valid.problem.project_start(&valid.start);
        CkRow {
            stiffness_scale: valid.problem.stiffness_scale,
            solver,
            scaling: valid.settings.scaling,
            status: r.solver.status,
            clean: r.is_clean(),
            feasible: r.is_feasible(),
            iterations: r.solver.iterations,
            objective: r.objective,
            certificate: r.certificate.as_ref().map(|c| c.status),
            left: r.escapes.iter().map(|e| e.objective).collect(),
            change: DesignChange::new(&r.design, &start),
            theta0: r.design.theta0.clone(),
            stiffness: r.design.stiffness.clone(),
            ipopt_seconds: r.solver.ipopt_seconds,
        }
    };
    let mut rows = Vec::new();
    match workers.filter(|w| w.jobs > 1) {
        // The points in worker processes, each run checked here (the same rows).
        Some(w) => {
            progress(0, total);
            let runs = solve_starts(w, &tasks, &mut |k| progress(k, total))?;
            for ((task, run), &solver) in tasks.iter().zip(runs).zip(&solvers) {
                let valid = task.case(case);
                rows.push(row(solver, task, &crate::design::settled(&valid, run)?));
            }
        }
        None => {
            for (task, &solver) in tasks.iter().zip(&solvers) {
                progress(rows.len(), total);
                rows.push(row(solver, task, &run_design(&task.case(case), None)?.result));
            }
        }
    }
    progress(total, total);
    Ok(CkStudy { rows })
}

impl CkStudy {
    /// What the sweep shows, in words: how many distinct optima the solves reached and whether
    /// the stiffness spread moved at all.
    pub fn conclusion(&self) -> String {
        let mut optima: Vec<f64> = Vec::new();
        for r in self.rows.iter().filter(|r| r.clean) {
            if !optima.iter().any(|j| (j - r.objective).abs() <= 1e-6 * j.abs()) {
                optima.push(r.objective);
            }
        }
        optima.sort_by(f64::total_cmp);
        let ratios: Vec<f64> = self.rows.iter().map(|r| r.change.stiffness_max_over_min).collect();
        let (lo, hi) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
        let mut text = format!(
            "{} clean solves reached {} distinct optima of eq. (33) (J = {} J); max K / min K ranges over [{lo:.3}, {hi:.3}].",
            self.rows.iter().filter(|r| r.clean).count(),
            optima.len(),
            optima.iter().map(|j| format!("{j:.5e}")).collect::<Vec<_>>().join(", "),
        );
        let fmincon: Vec<&CkRow> = self.rows.iter().filter(|r| r.solver.fmincon_like()).collect();
        let stopped: Vec<&&CkRow> = fmincon.iter().filter(|r| !r.clean).collect();
        if !stopped.is_empty() {
            let cv = stopped.iter().map(|r| r.change.stiffness_variation).fold(0.0f64, f64::max);
            let at: Vec<String> = stopped.iter().map(|r| format!("{:.3}", r.stiffness_scale)).collect();
            text.push_str(&format!(
                " The fmincon-like solver (reduced space, L-BFGS, fmincon's stopping rules) stops without converging at C_K = {} ({} of {}), its springs where they started (CV of K at most {cv:.1e}): there the paper's trend in the stiffness spread comes from the optimiser, not from eq. (33).",
                at.join(", "),
                stopped.len(),
                fmincon.len()
            ));
        }
        if optima.len() < self.rows.len() {
            text.push_str(
                " C_K rescales a variable (k = K / C_K); the KKT points of eq. (33) do not depend on that, so with exact \
                 second derivatives C_K changes only Ipopt's path and hence which of the same local optima it ends in — \
                 not the kind of design. A trend in C_K, where the claims find one, is the choice among these optima.",
            );
        }
        text
    }

    /// The table: one row per solve.
    pub fn table(&self) -> Table {
        let rows = &self.rows;
        Table::new()
            .numbers("stiffness_scale", rows.iter().map(|r| r.stiffness_scale))
            .labels("solver", rows.iter().map(|r| r.solver.name()))
            .labels("scaling", rows.iter().map(|r| scaling_name(r.scaling)))
            .labels("status", rows.iter().map(|r| r.status))
            .labels("clean", rows.iter().map(|r| r.clean))
            .labels("feasible", rows.iter().map(|r| r.feasible))
            .counts("iterations", rows.iter().map(|r| r.iterations))
            .numbers("objective_j", rows.iter().map(|r| r.objective))
            .numbers("stiffness_cv", rows.iter().map(|r| r.change.stiffness_variation))
            .numbers("stiffness_max_over_min", rows.iter().map(|r| r.change.stiffness_max_over_min))
            .numbers("theta0_change_rad", rows.iter().map(|r| r.change.theta0_change))
            .numbers("theta0_relative_change", rows.iter().map(|r| r.change.theta0_relative_change))
            .numbers("stiffness_relative_change", rows.iter().map(|r| r.change.stiffness_relative_change))
    }

    /// Stiffness spread and shape change against `log10 C_K`, one series per solver (on the rows
    /// its claims read).
    pub fn figure(&self, title: &str) -> Figure {
        let x = "log₁₀ C_K (C_K dimensionless)";
        let series = |f: &dyn Fn(&CkRow) -> f64, panel: Panel| {
            SOLVERS.iter().enumerate().fold(panel, |p, (k, &s)| {
                p.with(
                    Series::line_markers(
                        s.name(),
                        self.of(s).iter().map(|r| (r.stiffness_scale.log10(), f(r))).collect(),
                    )
                    .colour(k),
                )
            })
        };
        Figure::new(title, 2)
            .with(series(
                &|r| r.change.stiffness_variation,
                Panel::new("(a) stiffness spread: coefficient of variation of K", x, "std(K) / mean(K)"),
            ))
            .with(series(
                &|r| r.change.stiffness_max_over_min.log10(),
                Panel::new("(b) stiffness spread: max K / min K", x, "log₁₀ (max K / min K)"),
            ))
            .with(series(
                &|r| r.change.theta0_change,
                Panel::new("(c) shape change ‖θ₀ − θ₀,start‖", x, "‖θ₀ − θ₀,start‖ (rad)"),
            ))
            .with(series(&|r| r.objective * 1e3, Panel::new("(d) stored energy J at the optimum", x, "J (mJ)")))
    }
}

/// `result.json` of `spine study ck`: the sweep, its claims and its conclusion.
#[derive(Clone, Debug, Serialize)]
pub struct StudyResult {
    pub study: &'static str,
    pub title: String,
    /// The `C_K` values swept.
    pub stiffness_scales: Vec<f64>,
    pub claims: Vec<Claim>,
    pub claims_passed: usize,
    pub claims_total: usize,
    pub conclusion: String,
    pub files: Vec<String>,
    pub study_rows: Vec<CkRow>,
    pub total_seconds: f64,
    #[serde(skip)]
    pub sweep: CkStudy,
}

/// The C_K study of eq. (34) on a design case titled `title`: the sweep, its claims, table and
/// figure.
pub fn run_ck_study(
    title: &str,
    case: &ValidDesign,
    values: &[f64],
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<StudyResult, RunError> {
    let clock = std::time::Instant::now();
    let title = format!("C_K study, eq. (34): {}", if title.is_empty() { "design case" } else { title });
    progress(Progress::Done {
        message: format!(
            "{title}: {} values of C_K from {:e} to {:e}; exact Hessian with Ipopt scaling gradient-based and none, and fmincon-like",
            values.len(),
            values.iter().copied().fold(f64::INFINITY, f64::min),
            values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        ),
    });
    let sweep = ck_study(case, values, workers, &mut |done, total| {
        progress(Progress::Step { stage: "eq. (33) solves", done, total })
    })?;
    let claims = sweep.claims();
    Ok(StudyResult {
        study: "ck",
        title,
        stiffness_scales: values.to_vec(),
        claims_passed: claims.iter().filter(|c| c.pass).count(),
        claims_total: claims.len(),
        claims,
        conclusion: sweep.conclusion(),
        files: ["ck_study.csv", "figure.svg", "figure.png", "figure.pdf"].map(String::from).to_vec(),
        study_rows: sweep.rows.clone(),
        total_seconds: clock.elapsed().as_secs_f64(),
        sweep,
    })
}

impl crate::KindOutput for StudyResult {
    /// Every solver check of the claims passed.
    fn is_clean(&self) -> bool {
        self.claims.iter().all(|c| c.pass || c.check != crate::claims::Check::Solver)
    }

    /// `ck_study.csv` and `figure` (SVG and PNG).
    fn files(&self) -> Vec<OutputFile> {
        vec![
            OutputFile::table("ck_study.csv", self.sweep.table()),
            OutputFile { name: "figure".into(), content: FileContent::Figure(self.sweep.figure(&self.title)) },
        ]
    }
}

impl std::fmt::Display for StudyResult {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{:>10} {:>38} {:>22} {:>5} {:>12} {:>8} {:>10} {:>10}",
            "C_K", "solver", "status", "iter", "J (J)", "CV(K)", "maxK/minK", "‖Δθ0‖"
        )?;
        for r in &self.study_rows {
            writeln!(
                f,
                "{:>10.4e} {:>38} {:>22} {:>5} {:>12.5e} {:>8.4} {:>10.2} {:>10.4}",
                r.stiffness_scale,
                r.solver.name(),
                if r.clean { r.status.to_string() } else { format!("{} (NOT clean)", r.status) },
                r.iterations,
                r.objective,
                r.change.stiffness_variation,
                r.change.stiffness_max_over_min,
                r.change.theta0_change
            )?;
        }
        writeln!(f, "claims ({} of {} PASS):", self.claims_passed, self.claims_total)?;
        for c in &self.claims {
            writeln!(f, "  {c}")?;
        }
        writeln!(f, "conclusion: {}", self.conclusion)
    }
}
