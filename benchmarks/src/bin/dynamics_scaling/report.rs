//! The benchmark's outputs: `benchmarks/DYNAMICS.md` (tables at matched accuracy, cost exponents,
//! every run) and the work–precision figure.

use super::peers::PEERS;
use super::{Run, Size, MATCHED, REFERENCE_RTOL};
use spine_plot::{Figure, Panel, Series};
use std::fmt::Write as _;

fn fmt_err(e: f64) -> String {
    if e.is_finite() {
        format!("{e:.1e}")
    } else {
        "no rise".into()
    }
}

/// Least-squares slope of `ln y` against `ln x`.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    if points.len() < 2 {
        return None;
    }
    let k = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / k, sy / k);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    Some(num / den)
}

pub(crate) fn report(results: &[Size], budget: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Dynamics: work against precision, this workspace against scipy Radau and CasADi's SUNDIALS integrators\n\n\
         Written by `just bench-dynamics` (benchmarks/src/bin/dynamics_scaling/). The scaled step case of \
         `docs/PEERS.md` (1 s of response to a −400 N step), N links; every program simulates the same model \
         file (`target/bench-dynamics/model-N.json`) with its own equations of motion: scipy's Radau with \
         numpy and a finite-difference Jacobian (benchmarks/peers/scipy_dynamics.py), CasADi 3.8's IDAS (the \
         index-1 DAE) and CVODES (the ODE, the bordered system solved inside) with exact Jacobians by \
         CasADi's AD and T_90 by root finding on the integrator's output (benchmarks/peers/casadi_dynamics.py). \
         Times are the integration alone (CasADi's construction of the integrator is listed apart), on one \
         core (`OPENBLAS_NUM_THREADS=1`), the fastest of runs repeated until they take 0.3 s together (at \
         most 30; ours and CasADi's alike, scipy's once); errors against the workspace at rtol {REFERENCE_RTOL:e}. Peer runs \
         stop after {budget} s.\n"
    );
    matched_section(&mut s, results);
    every_run_section(&mut s, results, budget);
    s
}

/// `time (rtol)` of a run, or "not reached".
fn cell(x: Option<&Run>) -> String {
    x.map_or("not reached".into(), |x| format!("{:.4} s ({:e})", x.time, x.rtol))
}

/// The table at matched accuracy and the cost exponents.
fn matched_section(s: &mut String, results: &[Size]) {
    let _ = writeln!(
        s,
        "## At matched accuracy (cheapest run with error ≤ {MATCHED:e}: max(|T_90 error| in s, |Δ(1 s) error|/Δ∞))\n"
    );
    let names: Vec<&str> = PEERS.iter().map(|p| p.name).collect();
    let _ = writeln!(
        s,
        "| N | ours: time (rtol) | {} | best peer / ours | reference T_90 (s) | cross-check: each peer's tightest run − reference |",
        names.iter().map(|n| format!("{n}: time (rtol)")).collect::<Vec<_>>().join(" | ")
    );
    let _ = writeln!(s, "|---|---|{}---|---|---|", "---|".repeat(PEERS.len()));
    let mut ours_matched = Vec::new();
    for r in results {
        let a = r.matched(&r.ours);
        let peers: Vec<Option<&Run>> = r.peers.iter().map(|p| r.matched(&p.runs)).collect();
        let best = peers.iter().flatten().min_by(|x, y| x.time.total_cmp(&y.time));
        let ratio = match (a, best) {
            (Some(a), Some(b)) => format!("{:.1}×", b.time / a.time),
            (Some(_), None) => "no peer reached it".into(),
            _ => "—".into(),
        };
        // The cross-check of the reference: each peer's tightest completed run.
        let cross: Vec<String> = r
            .peers
            .iter()
            .zip(&names)
            .map(|(p, name)| {
                let tightest = p.runs.iter().min_by(|a, b| a.rtol.total_cmp(&b.rtol));
                tightest
                    .map_or(format!("{name}: not run"), |c| format!("{name} {:.1e} (rtol {:e})", r.error(c), c.rtol))
            })
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.n,
            cell(a),
            peers.iter().map(|p| cell(*p)).collect::<Vec<_>>().join(" | "),
            ratio,
            r.reference.t90.map_or("—".into(), |t| format!("{t:.10}")),
            cross.join("; ")
        );
        if let Some(a) = a {
            if r.n >= 10 {
                ours_matched.push((r.n as f64, a.time));
            }
        }
    }
    if let Some(p) = slope(&ours_matched) {
        let _ = writeln!(
            s,
            "\nOurs at matched accuracy: time ∝ N^{p:.2} (least squares over N ≥ 10; from N = 200 the error is \
             that of Δ(1 s) alone, the chain rising after 1 s)."
        );
    }
    for (peer, name) in (0..PEERS.len()).zip(&names) {
        let matched: Vec<(f64, f64)> = results
            .iter()
            .filter(|r| r.n >= 10)
            .filter_map(|r| r.matched(&r.peers[peer].runs).map(|x| (r.n as f64, x.time)))
            .collect();
        if let Some(p) = slope(&matched) {
            let _ = writeln!(s, "\n{name} at matched accuracy: time ∝ N^{p:.2} (N ≥ 10 where it reached it).");
        }
    }
    for rtol in [1e-6, 1e-8] {
        let fixed: Vec<(f64, f64)> = results
            .iter()
            .filter(|r| r.n >= 10)
            .filter_map(|r| r.ours.iter().find(|x| x.rtol == rtol).map(|x| (r.n as f64, x.time)))
            .collect();
        if let Some(p) = slope(&fixed) {
            let _ = writeln!(s, "\nOurs at rtol {rtol:e}: time per simulated second ∝ N^{p:.2} (N ≥ 10).");
        }
    }
}

/// Every run of every program.
fn every_run_section(s: &mut String, results: &[Size], budget: f64) {
    let _ = writeln!(s, "\n## Every run\n");
    let _ = writeln!(
        s,
        "| N | method | rtol | time (s) | T_90 error (s) | Δ(1 s) error / Δ∞ | steps | f evaluations | construction (s) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for r in results {
        let named = std::iter::once(("ours (Radau IIA, O(N))", &r.ours, &[][..]))
            .chain(PEERS.iter().zip(&r.peers).map(|(p, runs)| (p.name, &runs.runs, &runs.stopped[..])));
        for (name, runs, stopped) in named {
            for x in runs.iter() {
                let _ = writeln!(
                    s,
                    "| {} | {name} | {:e} | {:.4} | {} | {:.1e} | {} | {} | {} |",
                    r.n,
                    x.rtol,
                    x.time,
                    fmt_err(r.t90_error(x)),
                    r.delta_error(x),
                    x.steps,
                    x.evaluations,
                    x.construction.map_or("—".into(), |c| format!("{c:.3}"))
                );
            }
            if !stopped.is_empty() {
                let list: Vec<String> = stopped.iter().map(|v| format!("{v:e}")).collect();
                let _ = writeln!(
                    s,
                    "| {} | {name} | {} | over budget ({budget} s), failed or skipped | | | | | |",
                    r.n,
                    list.join(", ")
                );
            }
        }
    }
}

pub(crate) fn figure(results: &[Size]) -> Figure {
    let mut fig = Figure::new("Step response, 1 s: wall time against error (T_90 in s, Δ(1 s)/Δ∞)", 3);
    for r in results {
        let pts = |runs: &[Run]| -> Vec<(f64, f64)> {
            runs.iter().map(|x| (r.error(x).max(1e-16), x.time)).filter(|(e, _)| e.is_finite()).collect()
        };
        let mut panel = Panel::new(format!("N = {}", r.n), "error", "time (s)")
            .x_log()
            .y_log()
            .with(Series::line_markers("ours", pts(&r.ours)).colour(0));
        for (k, (peer, runs)) in PEERS.iter().zip(&r.peers).enumerate() {
            panel = panel.with(Series::line_markers(peer.name, pts(&runs.runs)).colour(k + 1));
        }
        fig = fig.with(panel);
    }
    fig
}
