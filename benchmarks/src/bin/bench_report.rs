//! Writes `benchmarks/RESULTS.md` and `benchmarks/scaling.svg` from criterion's results in
//! `target/criterion` (`just bench`) and `benchmarks/peers/results.json` (`just bench-peers`),
//! followed by the hand-written analysis in `benchmarks/analysis.md`.
#![forbid(unsafe_code)]

use spine_benchmarks::peers::PeerRow;
use spine_benchmarks::report::{figure, machine, read_criterion, replace_block, results_markdown};
use std::path::Path;

fn main() {
    let measurements = read_criterion(Path::new("target/criterion")).unwrap_or_else(|e| {
        eprintln!("bench_report: {e}");
        std::process::exit(1)
    });
    let peers: Vec<PeerRow> = match std::fs::read_to_string("benchmarks/peers/results.json") {
        Ok(text) => serde_json::from_str(&text).unwrap_or_else(|e| {
            eprintln!("bench_report: benchmarks/peers/results.json: {e}");
            std::process::exit(1)
        }),
        Err(_) => Vec::new(),
    };
    if !peers.is_empty() {
        // The README's measured table is this table, regenerated, never typed by hand.
        let readme = std::fs::read_to_string("README.md").expect("README.md");
        let block =
            format!("{}\n{}", spine_benchmarks::peers::table(&peers), spine_benchmarks::peers::ladder_table(&peers));
        match replace_block(&readme, "bench-peers", &block) {
            Some(text) => std::fs::write("README.md", text).expect("README.md"),
            None => {
                eprintln!("bench_report: README.md has no <!-- BEGIN bench-peers --> … <!-- END bench-peers --> block")
            }
        }
    }
    let analysis = std::fs::read_to_string("benchmarks/analysis.md").unwrap_or_default();
    let mut md = results_markdown(&measurements, &peers, &machine(), &analysis);
    // CasADi's AD beside ours (`just bench-ad-peers`), before the eq. (33) comparison.
    if let Ok(text) = std::fs::read_to_string("benchmarks/peers/ad-results.json") {
        let rows: Vec<spine_benchmarks::ad_peers::AdPeerRow> = serde_json::from_str(&text).unwrap_or_else(|e| {
            eprintln!("bench_report: benchmarks/peers/ad-results.json: {e}");
            std::process::exit(1)
        });
        let section = format!(
            "## AD against CasADi's\n\nThe same functions built as CasADi SX functions and evaluated inside CasADi \
             (`just bench-ad-peers`, `benchmarks/peers/casadi_ad.py`): its virtual machine and its generated C code \
             compiled with `gcc -O3`, each mapped over a batch of evaluations so that Python's call overhead does not \
             count; ours timed in the same run on the same point (best of 5 batches). Jacobian: the passive \
             equilibrium rows `[r; Φ]` and `∂/∂(θ1, λ1)`; Hessian: the lower triangle of `σ∇²f + Σλ_r∇²g_r` of \
             eq. (33). Seconds per evaluation; the last column is the largest difference of the two programs' \
             values over the largest value. CasADi {}.\n\n{}\n",
            rows.first().map_or("", |r| r.casadi_version.as_str()),
            spine_benchmarks::ad_peers::table(&rows)
        );
        md = match md.find("## Eq. (33) against CasADi") {
            Some(at) => format!("{}{}\n{}", &md[..at], section, &md[at..]),
            None => md + "\n" + &section,
        };
    }
    // Without criterion data (a `just bench-peers` alone), the criterion sections of the file
    // before are kept, not wiped.
    if measurements.is_empty() {
        if let Some(merged) = std::fs::read_to_string("benchmarks/RESULTS.md")
            .ok()
            .and_then(|earlier| spine_benchmarks::report_merge::keep_earlier_measurements(&earlier, &md))
        {
            md = merged;
        }
    }
    std::fs::write("benchmarks/RESULTS.md", md).expect("benchmarks/RESULTS.md");
    if !measurements.is_empty() {
        let svg = figure(&measurements).to_svg().unwrap_or_else(|e| {
            eprintln!("bench_report: {e}");
            std::process::exit(1)
        });
        std::fs::write("benchmarks/scaling.svg", svg).expect("benchmarks/scaling.svg");
    }
    eprintln!(
        "wrote benchmarks/RESULTS.md ({} measurements, {} peer rows) and benchmarks/scaling.svg",
        measurements.len(),
        peers.len()
    );
}
