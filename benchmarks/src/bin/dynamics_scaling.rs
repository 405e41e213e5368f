//! `just bench-dynamics`: work against precision of the step response, this workspace against
//! scipy's Radau on the same chains, side by side in one run.
//!
//! The chains are the scaled step case of `docs/PEERS.md`
//! ([`spine_dynamics::fixtures::peer_step_problem`]: 1 s of response to a −400 N step). For each
//! `N`, the model (lengths, masses, springs, dampers, link loads, the passive equilibrium `θ1` and
//! the rise target) is written to `target/bench-dynamics/model-N.json`; the workspace simulates it
//! with its default integrator (Radau IIA, `O(N)` Newton matrices) and
//! `benchmarks/peers/scipy_dynamics.py` with scipy's `solve_ivp(method="Radau")` (its own equations
//! of motion in numpy, finite-difference Jacobian), each over a ladder of tolerances
//! (`atol = rtol/100`). Errors are against a tight reference: the workspace at rtol 1e-10 (its
//! own T_90 error below 1e-12 s: it moves by 6e-13 s at N = 10 from rtol 1e-10 to 1e-11; from rtol
//! 1e-11 on, `atol = rtol/100` on the angular velocities is below the round-off of the stages,
//! Newton stalls and the steps shrink, at N = 50 to a stop),
//! cross-checked against scipy's tightest completed run (scipy's rtol stops at 1e-9: below it the
//! finite-difference Jacobian stalls its steps, 39 s and 11 017 steps at N = 5 for rtol 1e-9 in one
//! trial, over two minutes at 1e-10).
//!
//! Reported per run: wall time of the integration alone (fastest of `REPEATS` for runs under 1 s;
//! statics excluded on both sides), `|T_90 − T_90^ref|` (s), `|Δ(1 s) − Δ^ref(1 s)| / |Δ∞|`, steps and
//! right-hand-side evaluations. A run's error is the larger of its `T_90` error (s) and its `Δ(1 s)`
//! error relative to `Δ∞` (from N = 200 the chain rises after 1 s: the `Δ(1 s)` error alone). At
//! matched accuracy, each side's cost is its cheapest run with an error at most `MATCHED` (1e-8);
//! the ratio is scipy's over ours. The cost exponent `p` (time ∝ N^p, at matched accuracy and at
//! fixed tolerances) is the least-squares slope over N ≥ 10.
//!
//! Writes `benchmarks/DYNAMICS.md` (tables) and `benchmarks/dynamics-work-precision.svg`
//! (log–log time against that error, one panel per N).
//!
//! Usage: `dynamics_scaling [--python PATH] [--budget SECONDS] [N ...]` (default N: 5 10 20 50 100
//! 200 500; scipy runs are stopped after `--budget` seconds each, default 60, and skipped at the
//! tolerances where the previous N already ran out of budget).
#![forbid(unsafe_code)]

use serde::Deserialize;
use spine_dynamics::fixtures::peer_step_problem;
use spine_dynamics::response::{simulate_step, StaticEnds};
use spine_dynamics::{Dynamics, Forcing, Options, StepSettings};
use spine_plot::{Figure, Panel, Series};
use std::fmt::Write as _;

const REPEATS: usize = 3;
const MATCHED: f64 = 1e-8;
const OURS: [f64; 6] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
const SCIPY: [f64; 6] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
const REFERENCE_RTOL: f64 = 1e-10;

/// One run of either side.
#[derive(Clone, Debug)]
struct Run {
    rtol: f64,
    time: f64,
    t90: Option<f64>,
    delta_end: f64,
    steps: usize,
    evaluations: usize,
}

#[derive(Deserialize)]
struct PeerLine {
    rtol: f64,
    status: String,
    time: f64,
    t90: Option<f64>,
    delta_end: Option<f64>,
    steps: Option<usize>,
    nfev: Option<usize>,
}

struct Size {
    n: usize,
    reference: Run,
    delta_inf: f64,
    ours: Vec<Run>,
    scipy: Vec<Run>,
    /// Tolerances scipy did not finish within the budget.
    scipy_stopped: Vec<f64>,
}

impl Size {
    fn t90_error(&self, r: &Run) -> f64 {
        match (r.t90, self.reference.t90) {
            (Some(a), Some(b)) => (a - b).abs(),
            _ => f64::INFINITY,
        }
    }

    /// The accuracy of a run: its `T_90` error (s) when the reference rises within 1 s, and its
    /// `Δ(1 s)` error relative to `Δ∞`, whichever is larger.
    fn error(&self, r: &Run) -> f64 {
        let d = self.delta_error(r);
        match self.reference.t90 {
            Some(_) => self.t90_error(r).max(d),
            None => d,
        }
    }

    fn delta_error(&self, r: &Run) -> f64 {
        (r.delta_end - self.reference.delta_end).abs() / self.delta_inf.abs()
    }

    /// The cheapest run with an error ([`Size::error`]) at most `MATCHED`.
    fn matched<'a>(&self, runs: &'a [Run]) -> Option<&'a Run> {
        runs.iter().filter(|r| self.error(r) <= MATCHED).min_by(|a, b| a.time.total_cmp(&b.time))
    }
}

/// One chain: its dynamics and static ends, computed once and shared by every run and the model file.
struct Chain {
    n: usize,
    d: Dynamics,
    ends: StaticEnds,
}

impl Chain {
    fn new(n: usize) -> Self {
        let problem = peer_step_problem(n);
        let ends = problem.static_ends(&Default::default()).expect("the peer chains have stable ends");
        Self { n, d: problem.dynamics(Forcing::Step), ends }
    }
}

fn ours(Chain { d, ends, .. }: &Chain, rtol: f64) -> Result<Run, String> {
    let integrator = Options { rtol, atol: rtol / 100.0, max_steps: 10_000_000, ..Default::default() };
    let settings = StepSettings { t_end: 1.0, samples: 2, integrator, ..Default::default() };
    let mut best: Option<Run> = None;
    for _ in 0..REPEATS {
        let r = simulate_step(d, ends.clone(), &settings, false);
        if r.outcome != spine_dynamics::Outcome::Completed {
            return Err(format!("{:?}", r.outcome));
        }
        let run = Run {
            rtol,
            time: r.time_seconds,
            t90: r.rise_time,
            delta_end: r.final_delta,
            steps: r.stats.accepted_steps,
            evaluations: r.stats.rhs_evaluations,
        };
        let slow = run.time > 1.0;
        if best.as_ref().is_none_or(|b| run.time < b.time) {
            best = Some(run);
        }
        if slow {
            break;
        }
    }
    Ok(best.expect("at least one run"))
}

/// Writes the model scipy reads; returns `Δ∞`.
fn write_model(Chain { n, d, ends }: &Chain, path: &std::path::Path) -> f64 {
    let model = serde_json::json!({
        "n_links": n,
        "lengths": d.lengths,
        "masses": d.masses,
        "theta0": d.theta0,
        "stiffness": d.stiffness,
        "damping": d.damping,
        "passive": { "vertical": d.passive.vertical, "axial": d.passive.axial },
        "loaded": { "vertical": d.loaded.vertical, "axial": d.loaded.axial },
        "theta1": ends.theta1,
        "x1": ends.x1,
        "x_target": ends.x1 + 0.9 * (ends.x2 - ends.x1),
        "t_end": 1.0,
    });
    std::fs::write(path, serde_json::to_string_pretty(&model).expect("json")).expect("model file");
    ends.x2 - ends.x1
}

fn scipy(python: &str, model: &std::path::Path, budget: f64, rtols: &[f64]) -> (Vec<Run>, Vec<f64>) {
    if rtols.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut cmd = std::process::Command::new(python);
    cmd.arg("benchmarks/peers/scipy_dynamics.py").arg(model).arg(budget.to_string());
    cmd.args(rtols.iter().map(|r| format!("{r:e}")));
    cmd.env("OPENBLAS_NUM_THREADS", "1").env("OMP_NUM_THREADS", "1");
    let out = cmd.output().expect("the scipy peer runs (just bench-dynamics sets up its venv)");
    assert!(out.status.success(), "scipy peer failed: {}", String::from_utf8_lossy(&out.stderr));
    let (mut runs, mut stopped) = (Vec::new(), Vec::new());
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let p: PeerLine = serde_json::from_str(line).expect("one JSON object per line");
        if p.status == "ok" {
            runs.push(Run {
                rtol: p.rtol,
                time: p.time,
                t90: p.t90,
                delta_end: p.delta_end.unwrap_or(f64::NAN),
                steps: p.steps.unwrap_or(0),
                evaluations: p.nfev.unwrap_or(0),
            });
        } else {
            eprintln!("scipy N model {}: rtol {:e}: {} after {:.1} s", model.display(), p.rtol, p.status, p.time);
            stopped.push(p.rtol);
        }
    }
    (runs, stopped)
}

fn fmt_err(e: f64) -> String {
    if e.is_finite() {
        format!("{e:.1e}")
    } else {
        "no rise".into()
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let (mut python, mut budget, mut sizes) = ("benchmarks/peers/.venv/bin/python".to_string(), 60.0, Vec::new());
    while let Some(a) = args.next() {
        match a.as_str() {
            "--python" => python = args.next().expect("--python PATH"),
            "--budget" => budget = args.next().and_then(|v| v.parse().ok()).expect("--budget SECONDS"),
            _ => sizes.push(a.parse::<usize>().expect("N must be a positive integer")),
        }
    }
    if sizes.is_empty() {
        sizes = vec![5, 10, 20, 50, 100, 200, 500];
    }
    let dir = std::path::Path::new("target/bench-dynamics");
    std::fs::create_dir_all(dir).expect("target/bench-dynamics");
    let mut results: Vec<Size> = Vec::new();
    let mut out_of_budget: Vec<f64> = Vec::new();
    for &n in &sizes {
        let model = dir.join(format!("model-{n}.json"));
        let chain = Chain::new(n);
        let delta_inf = write_model(&chain, &model);
        let reference = ours(&chain, REFERENCE_RTOL).unwrap_or_else(|e| panic!("N = {n}: the reference run ended {e}"));
        let runs: Vec<Run> = OURS
            .iter()
            .filter_map(|&r| ours(&chain, r).map_err(|e| eprintln!("N = {n}, rtol {r:e}: ours ended {e}")).ok())
            .collect();
        let peer_rtols: Vec<f64> = SCIPY.iter().copied().filter(|r| !out_of_budget.iter().any(|s| *s >= *r)).collect();
        let (scipy_runs, stopped) = scipy(&python, &model, budget, &peer_rtols);
        let mut skipped: Vec<f64> = SCIPY.iter().copied().filter(|r| !peer_rtols.contains(r)).collect();
        skipped.extend(stopped.iter().copied());
        out_of_budget.extend(stopped);
        let size = Size { n, reference, delta_inf, ours: runs, scipy: scipy_runs, scipy_stopped: skipped };
        let m = |runs: &[Run]| size.matched(runs).map_or("not reached".to_string(), |r| format!("{:.4} s", r.time));
        eprintln!("N = {n}: ours {} · scipy {} at error ≤ {MATCHED:e}", m(&size.ours), m(&size.scipy));
        results.push(size);
    }
    let report = report(&results, budget);
    std::fs::write("benchmarks/DYNAMICS.md", &report).expect("benchmarks/DYNAMICS.md");
    print!("{report}");
    match figure(&results).to_svg() {
        Ok(svg) => std::fs::write("benchmarks/dynamics-work-precision.svg", svg).expect("svg"),
        Err(e) => eprintln!("plot: {}", e.0),
    }
    eprintln!("wrote benchmarks/DYNAMICS.md and benchmarks/dynamics-work-precision.svg");
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

fn report(results: &[Size], budget: f64) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Dynamics: work against precision, this workspace against scipy Radau\n\n\
         Written by `just bench-dynamics` (benchmarks/src/bin/dynamics_scaling.rs). The scaled step case of \
         `docs/PEERS.md` (1 s of response to a −400 N step), N links; both sides simulate the same model \
         file (`target/bench-dynamics/model-N.json`), scipy with its own numpy equations of motion \
         (benchmarks/peers/scipy_dynamics.py). Times are the integration alone, on one core \
         (`OPENBLAS_NUM_THREADS=1`); errors against the workspace at rtol {REFERENCE_RTOL:e}. scipy runs \
         stop after {budget} s.\n"
    );
    matched_section(&mut s, results);
    every_run_section(&mut s, results, budget);
    s
}

/// The table at matched accuracy and the cost exponents.
fn matched_section(s: &mut String, results: &[Size]) {
    let _ = writeln!(
        s,
        "## At matched accuracy (cheapest run with error ≤ {MATCHED:e}: max(|T_90 error| in s, |Δ(1 s) error|/Δ∞))\n"
    );
    let _ = writeln!(s, "| N | ours: time (rtol) | scipy Radau: time (rtol) | scipy / ours | reference T_90 (s) | cross-check: scipy's tightest run − reference |");
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    let mut ours_matched = Vec::new();
    for r in results {
        let (a, b) = (r.matched(&r.ours), r.matched(&r.scipy));
        let cell = |x: Option<&Run>| x.map_or("not reached".into(), |x| format!("{:.4} s ({:e})", x.time, x.rtol));
        let ratio = match (a, b) {
            (Some(a), Some(b)) => format!("{:.0}×", b.time / a.time),
            (Some(_), None) => "scipy did not reach it".into(),
            _ => "—".into(),
        };
        // The cross-check of the reference: scipy's tightest completed run.
        let tightest = r.scipy.iter().min_by(|a, b| a.rtol.total_cmp(&b.rtol));
        let cross = tightest.map_or("not run".into(), |c| format!("{:.1e} (rtol {:e})", r.error(c), c.rtol));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            r.n,
            cell(a),
            cell(b),
            ratio,
            r.reference.t90.map_or("—".into(), |t| format!("{t:.10}")),
            cross
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

/// Every run of both programs.
fn every_run_section(s: &mut String, results: &[Size], budget: f64) {
    let _ = writeln!(s, "\n## Every run\n");
    let _ =
        writeln!(s, "| N | method | rtol | time (s) | T_90 error (s) | Δ(1 s) error / Δ∞ | steps | f evaluations |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for r in results {
        for (name, runs) in [("ours (Radau IIA, O(N))", &r.ours), ("scipy Radau", &r.scipy)] {
            for x in runs.iter() {
                let _ = writeln!(
                    s,
                    "| {} | {name} | {:e} | {:.4} | {} | {:.1e} | {} | {} |",
                    r.n,
                    x.rtol,
                    x.time,
                    fmt_err(r.t90_error(x)),
                    r.delta_error(x),
                    x.steps,
                    x.evaluations
                );
            }
        }
        if !r.scipy_stopped.is_empty() {
            let list: Vec<String> = r.scipy_stopped.iter().map(|v| format!("{v:e}")).collect();
            let _ = writeln!(
                s,
                "| {} | scipy Radau | {} | over budget ({budget} s) or skipped | | | | |",
                r.n,
                list.join(", ")
            );
        }
    }
}

fn figure(results: &[Size]) -> Figure {
    let mut fig = Figure::new("Step response, 1 s: wall time against error (T_90 in s, Δ(1 s)/Δ∞)", 3);
    for r in results {
        let pts = |runs: &[Run]| -> Vec<(f64, f64)> {
            runs.iter().map(|x| (r.error(x).max(1e-16), x.time)).filter(|(e, _)| e.is_finite()).collect()
        };
        let panel = Panel::new(format!("N = {}", r.n), "error", "time (s)")
            .x_log()
            .y_log()
            .with(Series::line_markers("ours", pts(&r.ours)).colour(0))
            .with(Series::line_markers("scipy Radau", pts(&r.scipy)).colour(1));
        fig = fig.with(panel);
    }
    fig
}
