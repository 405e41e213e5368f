//! The peer programs of the benchmark (scipy, CasADi's IDAS and CVODES): each a Python script run
//! once per tolerance on the model file, answering one JSON line.

use super::Run;
use serde::Deserialize;

#[derive(Deserialize)]
pub(crate) struct PeerLine {
    rtol: f64,
    status: String,
    time: f64,
    t90: Option<f64>,
    delta_end: Option<f64>,
    steps: Option<usize>,
    nfev: Option<usize>,
    construction: Option<f64>,
}

/// A peer program: its script and arguments before the tolerances, and its name in the tables.
pub(crate) struct Peer {
    pub(crate) name: &'static str,
    script: &'static str,
    args: &'static [&'static str],
}

pub(crate) const PEERS: [Peer; 3] = [
    Peer { name: "scipy Radau", script: "benchmarks/peers/scipy_dynamics.py", args: &[] },
    Peer { name: "CasADi IDAS", script: "benchmarks/peers/casadi_dynamics.py", args: &["idas"] },
    Peer { name: "CasADi CVODES", script: "benchmarks/peers/casadi_dynamics.py", args: &["cvodes"] },
];

/// One peer's runs on one chain.
pub(crate) struct PeerRuns {
    pub(crate) runs: Vec<Run>,
    /// Tolerances the peer did not finish within the budget, or skipped.
    pub(crate) stopped: Vec<f64>,
}

/// The peer's completed runs, the tolerances it did not complete (over budget or failed), and those
/// over budget (skipped at the next N).
pub(crate) fn run_peer(
    peer: &Peer,
    python: &str,
    model: &std::path::Path,
    budget: f64,
    rtols: &[f64],
) -> (Vec<Run>, Vec<f64>, Vec<f64>) {
    if rtols.is_empty() {
        return (Vec::new(), Vec::new(), Vec::new());
    }
    let (mut runs, mut stopped, mut over_budget) = (Vec::new(), Vec::new(), Vec::new());
    for &rtol in rtols {
        // Tolerances tighter than one that ran out of budget are not tried.
        if over_budget.iter().any(|&b| b >= rtol) {
            stopped.push(rtol);
            continue;
        }
        // One process per tolerance under `timeout`: a peer's budget alarm cannot interrupt a long
        // call inside its C++ (CasADi's construction of the integrator at N = 500), the kill can.
        let mut cmd = std::process::Command::new("timeout");
        cmd.args(["-s", "KILL", &format!("{}", budget + 15.0)]).arg(python);
        cmd.arg(peer.script).arg(model).arg(budget.to_string()).args(peer.args).arg(format!("{rtol:e}"));
        cmd.env("OPENBLAS_NUM_THREADS", "1").env("OMP_NUM_THREADS", "1");
        let clock = std::time::Instant::now();
        let out = cmd.output().expect("the peer runs (just bench-dynamics sets up its venv)");
        let line = String::from_utf8_lossy(&out.stdout).lines().last().map(str::to_string);
        let Some(line) = line.filter(|_| out.status.success()) else {
            eprintln!(
                "{} on {}: rtol {rtol:e}: killed or failed after {:.1} s: {}",
                peer.name,
                model.display(),
                clock.elapsed().as_secs_f64(),
                String::from_utf8_lossy(&out.stderr).lines().last().unwrap_or("")
            );
            stopped.push(rtol);
            over_budget.push(rtol);
            continue;
        };
        let p: PeerLine = serde_json::from_str(&line).expect("one JSON object per line");
        if p.status == "budget" {
            over_budget.push(p.rtol);
        }
        if p.status == "ok" {
            runs.push(Run {
                rtol: p.rtol,
                time: p.time,
                t90: p.t90,
                delta_end: p.delta_end.unwrap_or(f64::NAN),
                steps: p.steps.unwrap_or(0),
                evaluations: p.nfev.unwrap_or(0),
                construction: p.construction,
            });
        } else {
            eprintln!("{} on {}: rtol {:e}: {} after {:.1} s", peer.name, model.display(), p.rtol, p.status, p.time);
            stopped.push(p.rtol);
        }
    }
    (runs, stopped, over_budget)
}
