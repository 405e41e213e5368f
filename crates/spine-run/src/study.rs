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

/// One solve of the sweep.
#[derive(Clone, Debug, Serialize)]
pub struct CkRow {
    pub stiffness_scale: f64,
    pub scaling: ScalingMethod,
    pub status: spine_ipopt::Status,
    pub clean: bool,
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

/// The sweep's rows, in the order (scaling, C_K).
#[derive(Clone, Debug, Serialize)]
pub struct CkStudy {
    pub rows: Vec<CkRow>,
}

const SCALINGS: [ScalingMethod; 2] = [ScalingMethod::GradientBased, ScalingMethod::None];

fn scaling_name(s: ScalingMethod) -> &'static str {
    match s {
        ScalingMethod::GradientBased => "gradient-based",
        ScalingMethod::None => "none",
    }
}

/// Solves `case` for every `C_K` of `values` with each scaling; `progress(done, total)`.
pub fn ck_study(
    case: &ValidDesign,
    values: &[f64],
    workers: Option<&Workers>,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CkStudy, RunError> {
    let tasks: Vec<Task> = SCALINGS
        .into_iter()
        .flat_map(|scaling| {
            values.iter().map(move |&ck| Task {
                start: case.start.clone(),
                stiffness_scale: Some(ck),
                scaling: Some(scaling),
            })
        })
        .collect();
    let total = tasks.len();
    let row = |task: &Task, r: &DesignResult| {
        let valid = task.case(case);
        let (start, _) = valid.problem.project_start(&valid.start);
        CkRow {
            stiffness_scale: valid.problem.stiffness_scale,
            scaling: valid.settings.scaling,
            status: r.solver.status,
            clean: r.is_clean(),
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
            for (task, run) in tasks.iter().zip(runs) {
                let valid = task.case(case);
                rows.push(row(task, &crate::design::settled(&valid, run)?));
            }
        }
        None => {
            for task in &tasks {
                progress(rows.len(), total);
                rows.push(row(task, &run_design(&task.case(case))?.result));
            }
        }
    }
    progress(total, total);
    Ok(CkStudy { rows })
}

/// Values closer than this, relative to the larger, are ties for [`kendall`] (a trend must be more
/// than solver tolerance).
const TIE: f64 = 1e-3;
/// The smallest relative change between the first and the last C_K that counts as an effect.
pub const EFFECT: f64 = 0.10;

fn differ(a: f64, b: f64) -> f64 {
    if (a - b).abs() <= TIE * a.abs().max(b.abs()) {
        0.0
    } else {
        (b - a).signum()
    }
}

/// Kendall's rank correlation of `y` against `x` (near ties count zero): +1 for a monotone increase.
fn kendall(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len();
    let mut s = 0.0;
    let mut pairs = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            s += differ(x[i], x[j]) * differ(y[i], y[j]);
            pairs += 1.0;
        }
    }
    if pairs > 0.0 {
        s / pairs
    } else {
        0.0
    }
}

impl CkStudy {
    fn of(&self, scaling: ScalingMethod) -> Vec<&CkRow> {
        self.rows.iter().filter(|r| r.scaling == scaling && r.clean).collect()
    }

    /// The paper's statement, checked for each scaling on the clean solves: Kendall's τ of the
    /// stiffness coefficient of variation against C_K must be positive and that of `‖θ0 − θ0_s‖`
    /// negative, and each must change by more than 10 % from the smallest to the largest C_K.
    pub fn claims(&self) -> Vec<Claim> {
        let mut claims = Vec::new();
        for scaling in SCALINGS {
            let rows = self.of(scaling);
            let all = self.rows.iter().filter(|r| r.scaling == scaling).count();
            let x: Vec<f64> = rows.iter().map(|r| r.stiffness_scale).collect();
            let cv: Vec<f64> = rows.iter().map(|r| r.change.stiffness_variation).collect();
            let shape: Vec<f64> = rows.iter().map(|r| r.change.theta0_change).collect();
            let (tk, ts) = (kendall(&x, &cv), kendall(&x, &shape));
            let ends = |v: &[f64]| match (v.first(), v.last()) {
                (Some(a), Some(b)) => format!("{a:.4} → {b:.4} ({:+.1} %)", 100.0 * (b / a - 1.0)),
                _ => "—".into(),
            };
            let change = |v: &[f64]| match (v.first(), v.last()) {
                (Some(a), Some(b)) => b / a - 1.0,
                _ => 0.0,
            };
            let scope = format!("scaling {}", scaling_name(scaling));
            claims.push(Claim::solver(
                &scope,
                "eq. (33) solves cleanly at every C_K of the sweep",
                "Ipopt converged, constraints met, both equilibria stable, on the load path",
                rows.len() == all,
                format!("{} of {all} solves clean", rows.len()),
            ));
            claims.push(Claim::new(
                &scope,
                "\"as the C_K is increased the stiffness variation between the nodes increases\" (Sec. 5.1)",
                format!("Kendall's τ of the coefficient of variation (CV) of K against C_K > 0 and CV up by more than {:.0} % from the smallest to the largest C_K (clean solves)", 100.0 * EFFECT),
                rows.len() >= 2 && tk > 0.0 && change(&cv) > EFFECT,
                format!("τ = {tk:.3}; CV of K from C_K = 1 to 10⁴: {}", ends(&cv)),
            ));
            claims.push(Claim::new(
                &scope,
                "\"whereas the change in orientation of the links is less apparent\" (Sec. 5.1)",
                format!("Kendall's τ of ‖θ0 − θ0_start‖ against C_K < 0 and ‖θ0 − θ0_start‖ down by more than {:.0} % from the smallest to the largest C_K (clean solves)", 100.0 * EFFECT),
                rows.len() >= 2 && ts < 0.0 && change(&shape) < -EFFECT,
                format!("τ = {ts:.3}; ‖θ0 − θ0_start‖ from C_K = 1 to 10⁴: {} rad", ends(&shape)),
            ));
        }
        claims
    }

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
            .labels("scaling", rows.iter().map(|r| scaling_name(r.scaling)))
            .labels("status", rows.iter().map(|r| r.status))
            .labels("clean", rows.iter().map(|r| r.clean))
            .counts("iterations", rows.iter().map(|r| r.iterations))
            .numbers("objective_j", rows.iter().map(|r| r.objective))
            .numbers("stiffness_cv", rows.iter().map(|r| r.change.stiffness_variation))
            .numbers("stiffness_max_over_min", rows.iter().map(|r| r.change.stiffness_max_over_min))
            .numbers("theta0_change_rad", rows.iter().map(|r| r.change.theta0_change))
            .numbers("theta0_relative_change", rows.iter().map(|r| r.change.theta0_relative_change))
            .numbers("stiffness_relative_change", rows.iter().map(|r| r.change.stiffness_relative_change))
    }

    /// Stiffness spread and shape change against `log10 C_K`, one series per scaling.
    pub fn figure(&self, title: &str) -> Figure {
        let x = "log₁₀ C_K (C_K dimensionless)";
        let series = |f: &dyn Fn(&CkRow) -> f64, panel: Panel| {
            SCALINGS.iter().enumerate().fold(panel, |p, (k, &s)| {
                p.with(
                    Series::line_markers(
                        format!("Ipopt scaling {}", scaling_name(s)),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kendall_and_half_decades() {
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[1.0, 5.0, 9.0]), 1.0);
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]), -1.0);
        assert!((kendall(&[1.0, 2.0, 3.0], &[1.0, 3.0, 2.0]) - 1.0 / 3.0).abs() < 1e-15);
        // Differences below the tie tolerance are no trend.
        assert_eq!(kendall(&[1.0, 2.0, 3.0], &[1.0, 1.0001, 1.0002]), 0.0);
        let v = half_decades();
        assert_eq!(v.len(), 9);
        assert_eq!(v[0], 1.0);
        assert!((v[8] - 1e4).abs() < 1e-9);
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
            "{title}: {} values of C_K from {:e} to {:e}, Ipopt scaling gradient-based and none",
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
            "{:>10} {:>15} {:>22} {:>5} {:>12} {:>8} {:>10} {:>10}",
            "C_K", "scaling", "status", "iter", "J (J)", "CV(K)", "maxK/minK", "‖Δθ0‖"
        )?;
        for r in &self.study_rows {
            writeln!(
                f,
                "{:>10.4e} {:>15} {:>22} {:>5} {:>12.5e} {:>8.4} {:>10.2} {:>10.4}",
                r.stiffness_scale,
                scaling_name(r.scaling),
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
