//! `just bench-dynamics`: work against precision of the step response, this workspace against
//! scipy's Radau and CasADi's SUNDIALS integrators (IDAS and CVODES) on the same chains, side by
//! side in one run.
//!
//! The chains are the scaled step case of `docs/PEERS.md`
//! ([`spine_dynamics::fixtures::peer_step_problem`]: 1 s of response to a −400 N step). For each
//! `N`, the model (lengths, masses, springs, dampers, link loads, the passive equilibrium `θ1` and
//! the rise target) is written to `target/bench-dynamics/model-N.json`; the workspace simulates it
//! with its default integrator (Radau IIA, `O(N)` Newton matrices) and
//! `benchmarks/peers/scipy_dynamics.py` with scipy's `solve_ivp(method="Radau")` (its own equations
//! of motion in numpy, finite-difference Jacobian) and `benchmarks/peers/casadi_dynamics.py` with
//! CasADi's `integrator("idas")` (the index-1 DAE) and `integrator("cvodes")` (the ODE with the
//! bordered system solved inside), exact Jacobians by CasADi's AD, T_90 by root finding on the
//! integrator's output (their construction timed apart), each over a ladder of tolerances
//! (`atol = rtol/100`). Errors are against a tight reference: the workspace at rtol 1e-10 (its
//! own T_90 error below 1e-12 s: it moves by 6e-13 s at N = 10 from rtol 1e-10 to 1e-11; from rtol
//! 1e-11 on, `atol = rtol/100` on the angular velocities is below the round-off of the stages,
//! Newton stalls and the steps shrink, at N = 50 to a stop),
//! cross-checked against scipy's tightest completed run (scipy's rtol stops at 1e-9: below it the
//! finite-difference Jacobian stalls its steps, 39 s and 11 017 steps at N = 5 for rtol 1e-9 in one
//! trial, over two minutes at 1e-10).
//!
//! Reported per run: wall time of the integration alone (the fastest of repeated runs, repeated
//! until they take `REPEAT_SECONDS` together or `MAX_REPEATS` times, for ours and for CasADi's
//! integrators alike: a single millisecond run varies by ±30 % on a shared machine; statics
//! excluded on both sides), `|T_90 − T_90^ref|` (s), `|Δ(1 s) − Δ^ref(1 s)| / |Δ∞|`, steps and
//! right-hand-side evaluations. A run's error is the larger of its `T_90` error (s) and its `Δ(1 s)`
//! error relative to `Δ∞` (from N = 200 the chain rises after 1 s: the `Δ(1 s)` error alone). At
//! matched accuracy, each side's cost is its cheapest run with an error at most `MATCHED` (1e-8);
//! the ratios are each peer's over ours, and "best peer" the fastest of the three. The cost exponent `p` (time ∝ N^p, at matched accuracy and at
//! fixed tolerances) is the least-squares slope over N ≥ 10.
//!
//! Writes `benchmarks/DYNAMICS.md` (tables) and `benchmarks/dynamics-work-precision.svg`
//! (log–log time against that error, one panel per N).
//!
//! Modules: [`peers`] (the peer programs and how they are run), [`report`] (DYNAMICS.md and the
//! figure).
//!
//! Usage: `dynamics_scaling [--python PATH] [--budget SECONDS] [N ...]` (default N: 5 10 20 50 100
//! 200 500; peer runs are stopped after `--budget` seconds each, default 60, and skipped at the
//! tolerances where the previous N already ran out of budget).
#![forbid(unsafe_code)]

mod peers;
mod report;

use peers::{run_peer, PeerRuns, PEERS};
use spine_dynamics::fixtures::peer_step_problem;
use spine_dynamics::response::{simulate_step, StaticEnds};
use spine_dynamics::{Dynamics, Forcing, Options, StepSettings};

/// Runs are repeated until they take this long together (s) …
const REPEAT_SECONDS: f64 = 0.3;
/// … or this many times; the fastest counts.
const MAX_REPEATS: usize = 30;
pub(crate) const MATCHED: f64 = 1e-8;
const OURS: [f64; 6] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
const PEER_RTOLS: [f64; 6] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
pub(crate) const REFERENCE_RTOL: f64 = 1e-10;

/// One run of either side.
#[derive(Clone, Debug)]
pub(crate) struct Run {
    rtol: f64,
    time: f64,
    t90: Option<f64>,
    delta_end: f64,
    steps: usize,
    evaluations: usize,
    /// Building the integrator (CasADi: expressions and their derivatives), s; not in `time`.
    construction: Option<f64>,
}

pub(crate) struct Size {
    n: usize,
    reference: Run,
    delta_inf: f64,
    ours: Vec<Run>,
    /// In the order of [`PEERS`].
    peers: Vec<PeerRuns>,
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
    let mut total = 0.0;
    for _ in 0..MAX_REPEATS {
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
            construction: None,
        };
        total += run.time;
        let slow = run.time > 1.0 || total >= REPEAT_SECONDS;
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

/// The dynamics of eq. (38) by our integrators beside CasADi's and scipy's, one run.
#[derive(clap::Parser)]
struct Args {
    /// The Python interpreter with CasADi and scipy.
    #[arg(long, default_value = "benchmarks/peers/.venv/bin/python")]
    python: String,
    /// A peer's time budget per run, s (a positive number).
    #[arg(long, default_value_t = 60.0, value_parser = positive_seconds)]
    budget: f64,
    /// Chain sizes (links, at least 2); 5 to 500 when none is given.
    #[arg(value_parser = spine_benchmarks::cli::links)]
    sizes: Vec<usize>,
}

/// A budget in seconds: a positive finite number.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(s) if s > 0.0 && s.is_finite() => Ok(s),
        _ => Err(format!("a positive number of seconds, got {text:?}")),
    }
}

fn main() {
    let Args { python, budget, mut sizes } = <Args as clap::Parser>::parse();
    if sizes.is_empty() {
        sizes = vec![5, 10, 20, 50, 100, 200, 500];
    }
    let dir = std::path::Path::new("target/bench-dynamics");
    std::fs::create_dir_all(dir).expect("target/bench-dynamics");
    let mut results: Vec<Size> = Vec::new();
    let mut out_of_budget: Vec<Vec<f64>> = vec![Vec::new(); PEERS.len()];
    for &n in &sizes {
        let model = dir.join(format!("model-{n}.json"));
        let chain = Chain::new(n);
        let delta_inf = write_model(&chain, &model);
        let reference = ours(&chain, REFERENCE_RTOL).unwrap_or_else(|e| panic!("N = {n}: the reference run ended {e}"));
        let runs: Vec<Run> = OURS
            .iter()
            .filter_map(|&r| ours(&chain, r).map_err(|e| eprintln!("N = {n}, rtol {r:e}: ours ended {e}")).ok())
            .collect();
        let peers: Vec<PeerRuns> = PEERS
            .iter()
            .zip(out_of_budget.iter_mut())
            .map(|(peer, out)| {
                let rtols: Vec<f64> = PEER_RTOLS.iter().copied().filter(|r| !out.iter().any(|s| *s >= *r)).collect();
                let (runs, stopped, over_budget) = run_peer(peer, &python, &model, budget, &rtols);
                let mut skipped: Vec<f64> = PEER_RTOLS.iter().copied().filter(|r| !rtols.contains(r)).collect();
                skipped.extend(stopped);
                out.extend(over_budget);
                PeerRuns { runs, stopped: skipped }
            })
            .collect();
        let size = Size { n, reference, delta_inf, ours: runs, peers };
        let m = |runs: &[Run]| size.matched(runs).map_or("not reached".to_string(), |r| format!("{:.4} s", r.time));
        let peer_cells: Vec<String> =
            PEERS.iter().zip(&size.peers).map(|(p, r)| format!("{} {}", p.name, m(&r.runs))).collect();
        eprintln!("N = {n}: ours {} · {} at error ≤ {MATCHED:e}", m(&size.ours), peer_cells.join(" · "));
        results.push(size);
    }
    let text = report::report(&results, budget);
    // `just bench-gradients`' section stays.
    let old = std::fs::read_to_string("benchmarks/DYNAMICS.md").unwrap_or_default();
    let whole = spine_benchmarks::keep_section(&text, &old, spine_benchmarks::GRADIENTS_SECTION);
    std::fs::write("benchmarks/DYNAMICS.md", &whole).expect("benchmarks/DYNAMICS.md");
    print!("{text}");
    match report::figure(&results).to_svg() {
        Ok(svg) => std::fs::write("benchmarks/dynamics-work-precision.svg", svg).expect("svg"),
        Err(e) => eprintln!("{e}"),
    }
    eprintln!("wrote benchmarks/DYNAMICS.md and benchmarks/dynamics-work-precision.svg");
}
