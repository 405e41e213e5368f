//! CasADi's automatic differentiation beside the workspace's (`just bench-ad-peers`): the same
//! residual Jacobian and Lagrangian Hessian of eq. (33), built as CasADi SX functions
//! (`benchmarks/peers/casadi_ad.py`) and evaluated inside CasADi, its virtual machine and its
//! generated C code compiled with `gcc -O3`, each over a batch so that Python's call overhead does
//! not count; ours timed in the same run on the same point. The rows are written to
//! `benchmarks/peers/ad-results.json`; `bench_report` puts their table into
//! `benchmarks/RESULTS.md`.

use crate::report::format_time;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// One N of the comparison: seconds per evaluation, and the largest difference of the values.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct AdPeerRow {
    pub n: usize,
    /// Residual and state Jacobian of the passive equilibrium rows.
    pub ours_jacobian: f64,
    pub casadi_vm_jacobian: f64,
    pub casadi_c_jacobian: Option<f64>,
    /// Lower triangle of the Hessian of the Lagrangian of eq. (33).
    pub ours_hessian: f64,
    pub casadi_vm_hessian: f64,
    pub casadi_c_hessian: Option<f64>,
    /// Largest difference of the Jacobians' (and residuals') entries over the largest entry.
    pub jacobian_difference: f64,
    /// The same for the Hessians.
    pub hessian_difference: f64,
    /// Time to generate and compile CasADi's C code of both functions, s.
    pub compile_seconds: f64,
    pub casadi_version: String,
}

/// The Markdown table of the rows.
pub fn table(rows: &[AdPeerRow]) -> String {
    let mut md = String::from(
        "| N | Jacobian: ours | CasADi VM | CasADi C -O3 | ours / C | Hessian: ours | CasADi VM | CasADi C -O3 | ours / C | values agree (Jacobian, Hessian) |\n|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let time = |t: Option<f64>| t.map_or("–".into(), format_time);
    let ratio = |a: f64, b: Option<f64>| b.map_or("–".into(), |b| format!("{:.2}", a / b));
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1e}, {:.1e} |",
            r.n,
            format_time(r.ours_jacobian),
            format_time(r.casadi_vm_jacobian),
            time(r.casadi_c_jacobian),
            ratio(r.ours_jacobian, r.casadi_c_jacobian),
            format_time(r.ours_hessian),
            format_time(r.casadi_vm_hessian),
            time(r.casadi_c_hessian),
            ratio(r.ours_hessian, r.casadi_c_hessian),
            r.jacobian_difference,
            r.hessian_difference,
        );
    }
    md
}
