//! The side-by-side comparison of eq. (33) with CasADi + IPOPT (`just bench-peers`): one row per
//! N, both programs on the same case file from the same start point.

use serde::{Deserialize, Serialize};
use spine_design::fixtures::arch_start;
use spine_design::refine::{Ladder, AUTO_LADDER};
use std::fmt::Write;

/// Two optima agree when their `J` differ by at most this, relative.
pub const SAME_OPTIMUM: f64 = 1e-6;

/// Tolerances of the peers run, the same for every program: Ipopt `tol` 1e-8, and a constraint
/// tolerance of 1e-9 scaled like `s²` (the equilibrium rows are moments in N·m, and the springs,
/// hence the moments and their round-off, grow like `s²` in this family; at N = 1000 K reaches
/// 1e8 N·m/rad).
pub fn peer_tolerances(n: usize) -> (f64, f64) {
    let s = n as f64 / 10.0;
    (1e-8, 1e-9 * (s * s).max(1.0))
}

/// The ladder of the refined runs: "auto"'s (from 50, factor 2) for N ≥ 100, from N/2 for
/// 10 ≤ N < 100, none below.
pub fn bench_ladder(n: usize) -> Option<Ladder> {
    match n {
        0..=9 => None,
        10..=99 => Some(Ladder { from: n / 2, factor: 2.0 }),
        _ => Some(AUTO_LADDER),
    }
}

/// The scaled-family case of `N` links ([`scaled_family_case`]), parsed and checked.
pub fn scaled_family_design(n: usize) -> spine_case::ValidDesign {
    let Ok(spine_case::Case::Design(case)) = spine_case::Case::from_json(&scaled_family_case(n).to_string()) else {
        unreachable!("the generated case is a design case")
    };
    // Invariant: the family's case is built from valid values for every `n ≥ 1` (the peers'
    // tests run it through the same check).
    case.validate().expect("the generated case is valid")
}

/// The scaled family of PEERS.md as a case file (the same problem as
/// `spine_design::fixtures::scaled_family`, which a test checks), with [`peer_tolerances`].
pub fn scaled_family_case(n: usize) -> serde_json::Value {
    let s = n as f64 / 10.0;
    let (tolerance, constraint_tolerance) = peer_tolerances(n);
    let start = arch_start(n, 0.3, 1e3 * s * s);
    serde_json::json!({
        "kind": "design",
        "title": format!("Scaled family of PEERS.md, N = {n} (s = N/10)"),
        "notes": { "paper": ["Sec. 5.1 configuration scaled with N: P_Y = -5 N per node, P_X = -400 s N, K in [1e2 s², 1e4 s²], C_K = s²."], "assumptions": [
            { "what": "solver.tolerance, solver.constraint_tolerance", "reason": "1e-8 and 1e-9 s² for every program alike: the equilibrium rows are moments (N·m) that grow like s² in this family" },
            { "what": "solver.refine", "reason": "off: the case is each program's cold solve; the refined runs of bench_peers set their ladder themselves" }
        ] },
        "chain": { "links": n, "length_x": 1.0 },
        "loads": { "p_y": -5.0, "p_x": -400.0 * s, "self_weight": false },
        "delta_d": -0.02,
        "stiffness_scale": s * s,
        "bounds": { "theta0_max": std::f64::consts::FRAC_PI_6, "relative_angle_max": std::f64::consts::FRAC_PI_6, "stiffness_min": 1e2 * s * s, "stiffness_max": 1e4 * s * s, "height_min": 0.01 * (10.0 / n as f64).min(1.0), "height_max": 0.25 },
        "start": { "theta0": start.theta0, "stiffness": start.stiffness[0] },
        "formulation": "full",
        "solver": { "tolerance": tolerance, "constraint_tolerance": constraint_tolerance, "refine": "off" }
    })
}

/// One program's solve of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SolverRun {
    /// The solver's own status word (Ipopt's return status).
    pub status: String,
    /// Converged to the requested tolerances (Ipopt `Solve_Succeeded`).
    pub converged: bool,
    pub iterations: usize,
    /// Wall time of the solve, s (ours: start equilibria, Ipopt and the final check; CasADi: the
    /// solver call, without building the expression graph).
    pub wall_seconds: f64,
    /// `J`, J.
    pub objective: f64,
    /// Largest violation of the constraint rows at the returned point (equilibria N·m, end
    /// conditions and heights m, relative angles rad), without the variables' own bounds: Ipopt's
    /// unscaled measure for CasADi, the design check's `Violations::constraint_rows` for ours.
    pub constraint_violation: f64,
    pub theta0: Vec<f64>,
    pub stiffness: Vec<f64>,
    /// The Ipopt that ran (ours: the build's; CasADi: its bundled one).
    #[serde(default)]
    pub ipopt_version: String,
    /// Levels of a mesh-sequenced run (empty for a cold solve).
    #[serde(default)]
    pub levels: Vec<LevelRun>,
    /// Ours: why a run Ipopt ended with `Solve_Succeeded` is not counted as converged (the
    /// result's warnings, e.g. a point that is not a minimum); empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One level of a mesh-sequenced run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LevelRun {
    pub links: usize,
    pub status: String,
    pub iterations: usize,
    pub wall_seconds: f64,
}

impl SolverRun {
    /// A table cell: status mark, iterations, wall time (`✓` converged to the tolerances,
    /// `acc.` Ipopt's acceptable level only, `✗` converged with a warning: [`SolverRun::warnings`]).
    pub fn cell(&self) -> String {
        let mark = if self.converged {
            "✓".to_string()
        } else if !self.warnings.is_empty() {
            "✗".to_string()
        } else if self.status.to_lowercase().contains("acceptable") {
            "acc.".to_string()
        } else {
            self.status.clone()
        };
        format!("{mark} {} it, {:.3} s", self.iterations, self.wall_seconds)
    }

    /// `links:iterations` of every level, e.g. `50:125 100:208 1000:123`.
    pub fn ladder(&self) -> String {
        self.levels
            .iter()
            .map(|l| {
                format!("{}:{}{}", l.links, l.iterations, if l.status == "solve_succeeded" { "" } else { "(acc.)" })
            })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// Our solver started from CasADi's optimum: if it stays there, CasADi's point is a KKT point of
/// our NLP too, so the two programs solve the same problem even where their paths end at
/// different local optima.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CrossCheck {
    pub status: String,
    pub converged: bool,
    pub iterations: usize,
    pub objective: f64,
}

/// One N.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PeerRow {
    pub n: usize,
    /// The case file both programs read.
    pub case: String,
    pub ours: SolverRun,
    pub casadi: Option<SolverRun>,
    /// Why CasADi gave no result (not installed, crashed, timed out).
    pub casadi_error: Option<String>,
    pub cross_check: Option<CrossCheck>,
    /// Ours with mesh sequencing ([`bench_ladder`]) on Debian's Ipopt.
    #[serde(default)]
    pub ours_refined: Option<SolverRun>,
    /// Ours on the Ipopt 3.14 backend (`just ipopt314 build`), cold and refined.
    #[serde(default)]
    pub ipopt314: Option<SolverRun>,
    #[serde(default)]
    pub ipopt314_refined: Option<SolverRun>,
    /// CasADi through the same ladder: each level's coarse case and our prolongation of CasADi's
    /// previous optimum, solved by CasADi with the same warm-start options (`--casadi-refined`).
    #[serde(default)]
    pub casadi_refined: Option<SolverRun>,
    /// Ours cold on Debian's Ipopt with the MUMPS it ships (`linear_solver = "mumps"`) instead of
    /// the default, the workspace's own factorisation (`crates/spine-kkt`).
    #[serde(default)]
    pub ours_mumps: Option<SolverRun>,
}

impl PeerRow {
    /// `|J_ours − J_casadi| / |J_casadi|`.
    pub fn relative_difference(&self) -> Option<f64> {
        self.casadi
            .as_ref()
            .map(|c| (self.ours.objective - c.objective).abs() / c.objective.abs().max(f64::MIN_POSITIVE))
    }

    /// Our wall time over CasADi's.
    pub fn ratio(&self) -> Option<f64> {
        self.casadi.as_ref().map(|c| self.ours.wall_seconds / c.wall_seconds)
    }

    /// Our fastest run that converged to the tolerances, with its name.
    pub fn best(&self) -> Option<(&'static str, &SolverRun)> {
        [
            ("cold 3.11", Some(&self.ours)),
            ("refined 3.11", self.ours_refined.as_ref()),
            ("cold 3.14", self.ipopt314.as_ref()),
            ("refined 3.14", self.ipopt314_refined.as_ref()),
        ]
        .into_iter()
        .filter_map(|(name, r)| r.filter(|r| r.converged).map(|r| (name, r)))
        .min_by(|a, b| a.1.wall_seconds.total_cmp(&b.1.wall_seconds))
    }

    /// Our best converged wall time over CasADi's cold one.
    pub fn best_ratio(&self) -> Option<f64> {
        let c = self.casadi.as_ref()?;
        self.best().map(|(_, r)| r.wall_seconds / c.wall_seconds)
    }

    /// What the row shows, in words.
    pub fn verdict(&self) -> String {
        let Some(c) = &self.casadi else {
            return format!("CasADi gave no result: {}", self.casadi_error.as_deref().unwrap_or("unknown"));
        };
        match (self.ours.converged, c.converged) {
            (false, false) => {
                let acceptable = |s: &str| s.to_lowercase().contains("acceptable");
                let diff = self.relative_difference().unwrap_or(f64::INFINITY);
                if acceptable(&self.ours.status) && acceptable(&c.status) {
                    return format!(
                        "both stopped at Ipopt's acceptable level only (not the requested tol); J differ by {diff:.1e}"
                    );
                }
                return format!("neither converged (ours {}, CasADi {})", self.ours.status, c.status);
            }
            (false, true) if !self.ours.warnings.is_empty() => {
                return format!("ours {}, but: {}", self.ours.status, self.ours.warnings.join("; "))
            }
            (false, true) => return format!("ours did not converge ({})", self.ours.status),
            (true, false) => return format!("CasADi did not converge ({})", c.status),
            (true, true) => {}
        }
        let diff = self.relative_difference().unwrap_or(f64::INFINITY);
        if diff <= SAME_OPTIMUM {
            return "same optimum".into();
        }
        let mut s = "different local optima".to_string();
        if let Some(x) = &self.cross_check {
            let back = (x.objective - c.objective).abs() / c.objective.abs();
            if x.converged && back <= SAME_OPTIMUM {
                let _ = write!(
                    s,
                    "; ours from CasADi's optimum stays there ({} iterations, J within {back:.0e}): same NLP",
                    x.iterations
                );
            } else {
                let _ = write!(
                    s,
                    "; ours from CasADi's optimum: {} after {} iterations, J rel. diff {back:.1e}",
                    x.status, x.iterations
                );
            }
        }
        s
    }
}

/// Runs the peer script `benchmarks/peers/SCRIPT` with `python` on `args` (one thread for BLAS
/// and OpenMP) and reads the JSON it writes to `out`, the last of `args`.
pub fn run_script(
    python: &str,
    script: &str,
    args: &[&std::path::Path],
    out: &std::path::Path,
) -> Result<serde_json::Value, String> {
    let status = std::process::Command::new(python)
        .arg(format!("benchmarks/peers/{script}"))
        .args(args)
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .status()
        .map_err(|e| format!("could not run {python}: {e}"))?;
    if !status.success() {
        return Err(format!("{script} exited with {status}"));
    }
    let text = std::fs::read_to_string(out).map_err(|e| format!("{}: {e}", out.display()))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", out.display()))
}

/// The comparison as a markdown table: every run's status (`✓` solve succeeded, `acc.`
/// acceptable level only), iterations and wall time, then our best converged run against CasADi.
pub fn table(rows: &[PeerRow]) -> String {
    let mut md = String::new();
    let cell = |r: Option<&SolverRun>| r.map_or("–".to_string(), SolverRun::cell);
    let _ = writeln!(md, "| N | ours cold (3.11) | ours refined (3.11) | ours cold (3.11, MUMPS) | ours cold (3.14) | ours refined (3.14) | CasADi cold | CasADi refined | best ours / CasADi cold | J ours cold (J) | J CasADi (J) | cold vs cold |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let c = r.casadi.as_ref();
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.9e} | {} | {} |",
            r.n,
            r.ours.cell(),
            cell(r.ours_refined.as_ref()),
            cell(r.ours_mumps.as_ref()),
            cell(r.ipopt314.as_ref()),
            cell(r.ipopt314_refined.as_ref()),
            cell(c),
            cell(r.casadi_refined.as_ref()),
            match (r.best(), r.best_ratio()) {
                (Some((name, _)), Some(x)) => format!("{x:.2} ({name})"),
                (Some((name, _)), None) => format!("– ({name})"),
                _ => "none converged".into(),
            },
            r.ours.objective,
            c.map_or("–".into(), |c| format!("{:.9e}", c.objective)),
            r.verdict()
        );
    }
    md
}

/// Iterations per level of the refined runs.
pub fn ladder_table(rows: &[PeerRow]) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "| N | refined 3.11: links:iterations | J | refined 3.14: links:iterations | J | CasADi refined: links:iterations | J |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|");
    for r in rows {
        let runs = [r.ours_refined.as_ref(), r.ipopt314_refined.as_ref(), r.casadi_refined.as_ref()];
        if runs.iter().all(|x| x.is_none_or(|x| x.levels.is_empty())) {
            continue;
        }
        let _ = write!(md, "| {} |", r.n);
        for x in runs {
            let _ = write!(
                md,
                " {} | {} |",
                x.map_or("–".into(), SolverRun::ladder),
                x.map_or("–".into(), |x| format!("{:.9e}", x.objective))
            );
        }
        let _ = writeln!(md);
    }
    md
}
