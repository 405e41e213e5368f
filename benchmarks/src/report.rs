//! `just bench` → `benchmarks/RESULTS.md` and `benchmarks/scaling.svg`: criterion's mean times read
//! back from `target/criterion`, the fitted exponent `p` of `time ∝ N^p` per benchmark, the
//! targets of the benchmark issue checked against them, and the CasADi comparison of
//! `just bench-peers` when it has been run (`benchmarks/peers/results.json`).

use crate::peers::PeerRow;
pub use crate::targets::{peer_targets, targets, Target};
use spine_plot::{Figure, Panel, Series};
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// The benchmark groups of `benches/scaling.rs`, in report order, with what each times.
pub const GROUPS: [(&str, &str); 9] = [
    ("residual", "equilibrium residual, eq. (5)"),
    ("jacobian", "residual + ∂r/∂(θ, λ), eqs. (46)–(49)"),
    ("newton_step", "one Newton step (residual, AD Jacobian, O(N) factorisation, solve)"),
    ("equilibrium_solve", "θ0 → θ1 → θ2 continuation with stability certificates"),
    ("gradients", "dJ/d(θ0, K) and dX/d(θ0, K) (Appendices I–II)"),
    ("hessian", "Hessian of the Lagrangian of eq. (33), second-order AD"),
    ("design_solve", "whole eq. (33) solve from the arch start"),
    ("kkt_factorization", "one factorisation of a KKT matrix Ipopt formed in an eq. (33) solve (order 10 N + 3)"),
    (
        "optimum_parameters",
        "N = 10: the optimum followed over Fig. 5's loads (40 points); design10's tight re-solve, that plus its sensitivities to all 19 default parameters, the sensitivity step alone, its baseline (the reduced KKT matrix built, factorised and solved for the step's 19 right-hand sides), the 19 tangents from the case",
    ),
];

/// Sizes at or above which the exponent is fitted (below, fixed costs dominate).
pub const FIT_FROM_N: usize = 50;

/// One benchmark: group, method (empty when the group has one), size, mean time in seconds.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    pub group: String,
    pub method: String,
    pub n: usize,
    pub seconds: f64,
}

impl Measurement {
    pub fn name(&self) -> String {
        if self.method.is_empty() {
            self.group.clone()
        } else {
            format!("{}/{}", self.group, self.method)
        }
    }
}

/// Reads `<criterion>/<group>[/<method>]/<N>/new/estimates.json` for the groups in [`GROUPS`].
pub fn read_criterion(criterion: &Path) -> Result<Vec<Measurement>, String> {
    let mut out = Vec::new();
    for (group, _) in GROUPS {
        let dir = criterion.join(group);
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        let mut paths: Vec<_> = entries.filter_map(|e| e.ok()).map(|e| e.path()).collect();
        paths.sort();
        for path in paths {
            let name = path.file_name().and_then(|s| s.to_str()).unwrap_or_default().to_string();
            let mut push = |method: &str, n: usize, estimates: &Path| -> Result<(), String> {
                let text = std::fs::read_to_string(estimates).map_err(|e| format!("{}: {e}", estimates.display()))?;
                let json: serde_json::Value =
                    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", estimates.display()))?;
                let ns = json["mean"]["point_estimate"]
                    .as_f64()
                    .ok_or_else(|| format!("{}: no mean", estimates.display()))?;
                out.push(Measurement { group: group.into(), method: method.into(), n, seconds: ns * 1e-9 });
                Ok(())
            };
            if let Ok(n) = name.parse::<usize>() {
                let estimates = path.join("new/estimates.json");
                if estimates.exists() {
                    push("", n, &estimates)?;
                }
            } else if path.is_dir() && name != "report" {
                let mut sizes: Vec<_> = std::fs::read_dir(&path)
                    .map_err(|e| e.to_string())?
                    .filter_map(|e| e.ok())
                    .map(|e| e.path())
                    .collect();
                sizes.sort();
                for size in sizes {
                    let estimates = size.join("new/estimates.json");
                    if let (Some(n), true) =
                        (size.file_name().and_then(|s| s.to_str()).and_then(|s| s.parse().ok()), estimates.exists())
                    {
                        push(&name, n, &estimates)?;
                    }
                }
            }
        }
    }
    out.sort_by(|a, b| (group_rank(&a.group), &a.method, a.n).cmp(&(group_rank(&b.group), &b.method, b.n)));
    Ok(out)
}

fn group_rank(group: &str) -> usize {
    GROUPS.iter().position(|(g, _)| *g == group).unwrap_or(usize::MAX)
}

/// Least-squares slope of `log t` against `log N` over the points with `N ≥ from` (`None` with
/// fewer than two such points).
pub fn fit_exponent(points: &[(usize, f64)], from: usize) -> Option<f64> {
    let xy: Vec<(f64, f64)> =
        points.iter().filter(|(n, _)| *n >= from).map(|&(n, t)| ((n as f64).ln(), t.ln())).collect();
    if xy.len() < 2 {
        return None;
    }
    let m = xy.len() as f64;
    let (sx, sy) = xy.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / m, sy / m);
    let (sxy, sxx) = xy.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + (x - mx) * (y - my), b + (x - mx) * (x - mx)));
    Some(sxy / sxx)
}

/// Measurements by benchmark name, each as `(N, seconds)` in increasing `N`.
pub fn series(measurements: &[Measurement]) -> BTreeMap<String, Vec<(usize, f64)>> {
    let mut map: BTreeMap<String, Vec<(usize, f64)>> = BTreeMap::new();
    for m in measurements {
        map.entry(m.name()).or_default().push((m.n, m.seconds));
    }
    map
}

/// `a / b` at every N that both series have.
pub fn ratios(a: &[(usize, f64)], b: &[(usize, f64)]) -> Vec<(usize, f64)> {
    a.iter().filter_map(|&(n, t)| b.iter().find(|(m, _)| *m == n).map(|&(_, u)| (n, t / u))).collect()
}

/// A time with a unit that keeps three significant digits.
pub fn format_time(seconds: f64) -> String {
    if seconds >= 1.0 {
        format!("{seconds:.3} s")
    } else if seconds >= 1e-3 {
        format!("{:.3} ms", seconds * 1e3)
    } else {
        format!("{:.3} µs", seconds * 1e6)
    }
}

/// The machine the numbers come from: CPU, cores, memory, OS kernel and the Rust compiler.
pub fn machine() -> String {
    let read = |p: &str| std::fs::read_to_string(p).unwrap_or_default();
    let cpuinfo = read("/proc/cpuinfo");
    let cpu = cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split(':').nth(1))
        .unwrap_or("unknown")
        .trim()
        .to_string();
    let cores = std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0);
    let memory = read("/proc/meminfo")
        .lines()
        .find(|l| l.starts_with("MemTotal"))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|kb| kb.parse::<f64>().ok()))
        .map(|kb| format!("{:.1} GiB", kb / 1024.0 / 1024.0))
        .unwrap_or_else(|| "unknown".into());
    let os = read("/etc/os-release")
        .lines()
        .find(|l| l.starts_with("PRETTY_NAME="))
        .map(|l| l[12..].trim_matches('"').to_string())
        .unwrap_or_default();
    let kernel = read("/proc/sys/kernel/osrelease").trim().to_string();
    let rustc = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    format!("{cpu}, {cores} cores available, {memory}; {os}, Linux {kernel}; {rustc}")
}

/// `benchmarks/RESULTS.md`.
pub fn results_markdown(measurements: &[Measurement], peers: &[PeerRow], machine: &str, notes: &str) -> String {
    let mut md = String::new();
    let by_name = series(measurements);
    let _ = writeln!(md, "# Benchmark results\n");
    let _ = writeln!(md, "Written by `just bench` (criterion, mean of 10 samples; `just bench-peers` adds the CasADi table). Machines here are shared and noisy: compare ratios within one run.\n");
    let _ = writeln!(md, "**Machine:** {machine}\n");
    let _ = writeln!(md, "## Targets\n\n| target | measured | met |\n|---|---|---|");
    for t in targets(measurements, peers) {
        let met = match t.met {
            Some(true) => "yes",
            Some(false) => "**no**",
            None => "not measured",
        };
        let _ = writeln!(md, "| {} | {} | {met} |", t.statement, t.measured);
    }
    let sizes: Vec<usize> = {
        let mut s: Vec<usize> = measurements.iter().map(|m| m.n).collect();
        s.sort();
        s.dedup();
        s
    };
    let _ = writeln!(md, "\n## Times per N and fitted exponents\n\n`p` is the least-squares slope of log time against log N over N ≥ {FIT_FROM_N}.\n");
    let _ = write!(md, "| benchmark | what |");
    for n in &sizes {
        let _ = write!(md, " N = {n} |");
    }
    let _ = writeln!(md, " p |");
    let _ = writeln!(md, "|---|---|{}---|", "---|".repeat(sizes.len()));
    for (group, what) in GROUPS {
        for (name, points) in by_name.iter().filter(|(k, _)| k.split('/').next() == Some(group)) {
            let _ = write!(md, "| `{name}` | {what} |");
            for n in &sizes {
                let cell = points.iter().find(|(m, _)| m == n).map_or("–".into(), |&(_, t)| format_time(t));
                let _ = write!(md, " {cell} |");
            }
            let p = fit_exponent(points, FIT_FROM_N).map_or("–".into(), |p| format!("{p:.2}"));
            let _ = writeln!(md, " {p} |");
        }
    }
    let ratio_rows: Vec<(&str, &str, &str)> = vec![
        ("jacobian", "ad", "hand"),
        ("jacobian", "ad", "hand_fused"),
        ("jacobian", "hand", "hand_fused"),
        ("jacobian", "fd", "hand"),
        ("gradients", "ad", "hand"),
        ("gradients", "forward_ad", "hand"),
        ("gradients", "fd", "hand"),
        ("optimum_parameters", "sensitivity_step", "factorisation_and_solves"),
    ];
    let _ =
        writeln!(md, "\n## Ratios to the hand-derived derivatives (and the sensitivity step to its factorisation)\n");
    let _ = write!(md, "| ratio |");
    for n in &sizes {
        let _ = write!(md, " N = {n} |");
    }
    let _ = writeln!(md, "\n|---|{}", "---|".repeat(sizes.len()));
    for (group, a, b) in ratio_rows {
        let (Some(sa), Some(sb)) = (by_name.get(&format!("{group}/{a}")), by_name.get(&format!("{group}/{b}"))) else {
            continue;
        };
        let _ = write!(md, "| {group}: {a} / {b} |");
        let by_size = ratios(sa, sb);
        for n in &sizes {
            let r = by_size.iter().find(|(m, _)| m == n).map(|&(_, r)| r);
            let _ = write!(md, " {} |", r.map_or("–".into(), |r| format!("{r:.2}")));
        }
        let _ = writeln!(md);
    }
    let _ = writeln!(md, "\n## Eq. (33) against CasADi + IPOPT\n");
    if peers.is_empty() {
        let _ = writeln!(md, "Not run yet: `just bench-peers`.");
    } else {
        let _ = writeln!(md, "Same case file and start point for every run (`just bench-peers`; tolerances in `peers::peer_tolerances`). `✓`: `solve_succeeded`; `✗`: Ipopt's `solve_succeeded` at a point our result refuses (the warning in the last column); `acc.`: Ipopt's acceptable level only. Our iterations count the certificate's re-solves (finest level and after for a refined run). Wall times include our start equilibria and final check; CasADi's exclude building its expression graph.\n");
        md.push_str(&crate::peers::table(peers));
        let _ = writeln!(md, "\nIterations per level of the refined runs (`links:iterations`, `(acc.)` where a level stopped at the acceptable level):\n");
        md.push_str(&crate::peers::ladder_table(peers));
    }
    let _ = writeln!(md, "\n![scaling](scaling.svg)\n");
    md.push_str(notes);
    md
}

/// The log-log plot: time against N on logarithmic axes with decade labels, one line per
/// benchmark, in two panels (derivatives and solves).
pub fn figure(measurements: &[Measurement]) -> Figure {
    let by_name = series(measurements);
    let points_of = |points: &[(usize, f64)]| points.iter().map(|&(n, t)| (n as f64, t)).collect::<Vec<_>>();
    let mut derivatives = Panel::new("Derivatives", "N (links)", "time (s)").x_log().y_log();
    let mut solves = Panel::new("Steps and solves", "N (links)", "time (s)").x_log().y_log();
    for (k, (name, points)) in by_name.iter().enumerate() {
        let series = Series::line_markers(name.clone(), points_of(points)).colour(k);
        if name.starts_with("jacobian")
            || name.starts_with("gradients")
            || name.starts_with("hessian")
            || name == "residual"
        {
            derivatives = derivatives.with(series);
        } else {
            solves = solves.with(series);
        }
    }
    Figure::new("Time against N (log-log; a slope of 1 is linear)", 2).with(derivatives).with(solves)
}

/// Replaces the lines between `<!-- BEGIN name -->` and `<!-- END name -->` of `text` with
/// `block`; `None` when the markers are missing.
pub fn replace_block(text: &str, name: &str, block: &str) -> Option<String> {
    let (begin, end) = (format!("<!-- BEGIN {name} -->"), format!("<!-- END {name} -->"));
    let a = text.find(&begin)? + begin.len();
    let b = text[a..].find(&end)? + a;
    Some(format!("{}\n{}{}", &text[..a], block, &text[b..]))
}
