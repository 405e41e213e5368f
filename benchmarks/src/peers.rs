//! The side-by-side comparison of eq. (33) with CasADi + IPOPT (`just bench-peers`): one row per
//! N, both programs on the same case file from the same start point.

use serde::{Deserialize, Serialize};
use spine_design::fixtures::arch_start;
use std::fmt::Write;

/// Two optima agree when their `J` differ by at most this, relative.
pub const SAME_OPTIMUM: f64 = 1e-6;

/// The scaled family of PEERS.md as a case file (the same problem as
/// `spine_design::fixtures::scaled_family`, which a test checks).
pub fn scaled_family_case(n: usize) -> serde_json::Value {
    let s = n as f64 / 10.0;
    let start = arch_start(n, 0.3, 1e3 * s * s);
    serde_json::json!({
        "kind": "design",
        "title": format!("Scaled family of PEERS.md, N = {n} (s = N/10)"),
        "notes": { "paper": ["Sec. 5.1 configuration scaled with N: P_Y = -5 N per node, P_X = -400 s N, K in [1e2 s², 1e4 s²], C_K = s²."], "assumptions": [] },
        "chain": { "links": n, "length_x": 1.0 },
        "loads": { "p_y": -5.0, "p_x": -400.0 * s, "self_weight": false },
        "delta_d": -0.02,
        "stiffness_scale": s * s,
        "bounds": { "theta0_max": std::f64::consts::FRAC_PI_6, "relative_angle_max": std::f64::consts::FRAC_PI_6, "stiffness_min": 1e2 * s * s, "stiffness_max": 1e4 * s * s, "height_min": 0.01 * (10.0 / n as f64).min(1.0), "height_max": 0.25 },
        "start": { "theta0": start.theta0, "stiffness": start.stiffness[0] },
        "formulation": "full"
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
    /// Largest constraint violation at the returned point (Ipopt's unscaled measure for CasADi,
    /// the design check's for ours).
    pub constraint_violation: f64,
    pub theta0: Vec<f64>,
    pub stiffness: Vec<f64>,
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
}

impl PeerRow {
    /// `|J_ours − J_casadi| / |J_casadi|`.
    pub fn relative_difference(&self) -> Option<f64> {
        self.casadi.as_ref().map(|c| (self.ours.objective - c.objective).abs() / c.objective.abs().max(f64::MIN_POSITIVE))
    }

    /// Our wall time over CasADi's.
    pub fn ratio(&self) -> Option<f64> {
        self.casadi.as_ref().map(|c| self.ours.wall_seconds / c.wall_seconds)
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
                    return format!("both stopped at Ipopt's acceptable level only (not the 1e-9 tolerance); J differ by {diff:.1e}");
                }
                return format!("neither converged (ours {}, CasADi {})", self.ours.status, c.status);
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
                let _ = write!(s, "; ours from CasADi's optimum stays there ({} iterations, J within {back:.0e}): same NLP", x.iterations);
            } else {
                let _ = write!(s, "; ours from CasADi's optimum: {} after {} iterations, J rel. diff {back:.1e}", x.status, x.iterations);
            }
        }
        s
    }
}

/// The comparison as a markdown table.
pub fn table(rows: &[PeerRow]) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "| N | J ours (J) | J CasADi (J) | rel. diff | iterations ours / CasADi | wall ours (s) | wall CasADi (s) | ours / CasADi | verdict |");
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let c = r.casadi.as_ref();
        let _ = writeln!(
            md,
            "| {} | {:.9e} | {} | {} | {} / {} | {:.3} | {} | {} | {} |",
            r.n,
            r.ours.objective,
            c.map_or("–".into(), |c| format!("{:.9e}", c.objective)),
            r.relative_difference().map_or("–".into(), |d| format!("{d:.1e}")),
            r.ours.iterations,
            c.map_or("–".into(), |c| c.iterations.to_string()),
            r.ours.wall_seconds,
            c.map_or("–".into(), |c| format!("{:.3}", c.wall_seconds)),
            r.ratio().map_or("–".into(), |x| format!("{x:.2}")),
            r.verdict()
        );
    }
    md
}
