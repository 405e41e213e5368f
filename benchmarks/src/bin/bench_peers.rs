//! `just bench-peers`: eq. (33) on the scaled family of `../shared/PEERS.md`, solved by this
//! workspace and by CasADi + IPOPT (`benchmarks/peers/casadi_static.py`) from the same case file
//! and the same start point, one N at a time. Prints the comparison table and writes
//! `benchmarks/peers/results.json` (read by `bench_report` into `benchmarks/RESULTS.md`).
//!
//! Usage: `bench_peers PYTHON [N ...]` (default N: 5 10 20 50 100 200 1000). The case files and
//! start points go to `target/bench-peers/`.
//!
//! Where the two optima differ, our solver is started from CasADi's optimum (its design and both
//! states; barrier parameter 1e-9 and bound push 1e-10 so that Ipopt does not move away from the
//! active bounds first): staying there shows that CasADi's point is a KKT point of our NLP, so
//! the two programs solve the same problem and only their paths differ.

use serde_json::json;
use spine_benchmarks::peers::{self, CrossCheck, PeerRow, SolverRun};
use spine_case::{Case, ValidCase};
use spine_design::full_space::{FullSpaceNlp, Layout};
use spine_design::solve::{start_states, ExtraOption};
use spine_design::{solve_design, DesignResult, Formulation, SolverSettings};
use spine_model::{Design, State};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

fn run_of(r: &DesignResult, wall_seconds: f64) -> SolverRun {
    SolverRun {
        status: r.solver.status.clone(),
        converged: r.solver.optimal && r.is_clean(),
        iterations: r.solver.iterations,
        wall_seconds,
        objective: r.objective,
        constraint_violation: r.violations.as_ref().map_or(f64::NAN, |v| v.max),
        theta0: r.design.theta0.clone(),
        stiffness: r.design.stiffness.clone(),
    }
}

fn write(path: &Path, value: &serde_json::Value) {
    std::fs::write(path, serde_json::to_string_pretty(value).expect("JSON")).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

fn casadi(python: &str, case: &Path, start: &Path, out: &Path) -> Result<(SolverRun, State, State), String> {
    let status = Command::new(python)
        .arg("benchmarks/peers/casadi_static.py")
        .args([case, start, out])
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .status()
        .map_err(|e| format!("could not run {python}: {e}"))?;
    if !status.success() {
        return Err(format!("casadi_static.py exited with {status}"));
    }
    let text = std::fs::read_to_string(out).map_err(|e| e.to_string())?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let floats = |k: &str| -> Vec<f64> { v[k].as_array().map(|a| a.iter().filter_map(|x| x.as_f64()).collect()).unwrap_or_default() };
    let run = SolverRun {
        status: v["status"].as_str().unwrap_or("unknown").into(),
        converged: v["converged"].as_bool().unwrap_or(false),
        iterations: v["iterations"].as_u64().unwrap_or(0) as usize,
        wall_seconds: v["wall_seconds"].as_f64().unwrap_or(f64::NAN),
        objective: v["objective"].as_f64().unwrap_or(f64::NAN),
        constraint_violation: v["constraint_violation"].as_f64().unwrap_or(f64::NAN),
        theta0: floats("theta0"),
        stiffness: floats("stiffness"),
    };
    let passive = State { theta: floats("theta1"), lambda: v["lambda1"].as_f64().unwrap_or(0.0) };
    let loaded = State { theta: floats("theta2"), lambda: v["lambda2"].as_f64().unwrap_or(0.0) };
    Ok((run, passive, loaded))
}

fn main() {
    let mut args = std::env::args().skip(1);
    let python = args.next().expect("usage: bench_peers PYTHON [N ...]");
    let sizes: Vec<usize> = args.map(|a| a.parse().expect("N must be a positive integer")).collect();
    let sizes = if sizes.is_empty() { vec![5, 10, 20, 50, 100, 200, 1000] } else { sizes };
    let dir = PathBuf::from("target/bench-peers");
    std::fs::create_dir_all(&dir).expect("target/bench-peers");
    let mut rows = Vec::new();
    for n in sizes {
        let case_path = dir.join(format!("scaled-{n}.json"));
        let case_value = peers::scaled_family_case(n);
        write(&case_path, &case_value);
        let case = Case::from_json(&case_value.to_string()).and_then(|c| c.validate()).expect("the generated case is valid");
        let ValidCase::Design(valid) = case else { unreachable!("a design case") };
        let (problem, settings) = (&valid.problem, &valid.settings);

        // The exact start point of our full space, handed to the peer.
        let (projected, _) = problem.project_start(&valid.start);
        let (passive, loaded) = start_states(problem, &projected, &settings.continuation, &mut Vec::new());
        let x0 = FullSpaceNlp::new(problem, &projected, &passive, &loaded).start;
        let layout = Layout { n };
        let start_path = dir.join(format!("start-{n}.json"));
        write(
            &start_path,
            &json!({
                "theta0": x0[..n],
                "k": x0[n..2 * n + 1],
                "theta1": passive.theta, "lambda1": passive.lambda,
                "theta2": loaded.theta, "lambda2": loaded.lambda,
                "heights": (1..n).map(|j| x0[layout.height(j).unwrap()]).collect::<Vec<_>>(),
            }),
        );

        let clock = Instant::now();
        let ours = solve_design(problem, &valid.start, Formulation::Full, settings, &mut |_| true).expect("valid problem");
        let ours = run_of(&ours, clock.elapsed().as_secs_f64());
        eprintln!("N = {n}: ours {} in {:.3} s ({} iterations), J = {:.9e}", ours.status, ours.wall_seconds, ours.iterations, ours.objective);

        let out_path = dir.join(format!("casadi-{n}.json"));
        let (casadi_run, casadi_error, cross_check) = match casadi(&python, &case_path, &start_path, &out_path) {
            Ok((run, passive, loaded)) => {
                eprintln!("N = {n}: CasADi {} in {:.3} s ({} iterations), J = {:.9e}", run.status, run.wall_seconds, run.iterations, run.objective);
                let differs = (run.objective - ours.objective).abs() > peers::SAME_OPTIMUM * run.objective.abs();
                let check = (differs && run.converged).then(|| cross_check(problem, settings, &run, &passive, &loaded));
                (Some(run), None, check)
            }
            Err(e) => {
                eprintln!("N = {n}: CasADi: {e}");
                (None, Some(e), None)
            }
        };
        rows.push(PeerRow { n, case: case_path.display().to_string(), ours, casadi: casadi_run, casadi_error, cross_check });
    }
    println!("{}", peers::table(&rows));
    let results = Path::new("benchmarks/peers/results.json");
    std::fs::write(results, serde_json::to_string_pretty(&rows).expect("JSON") + "\n").expect("benchmarks/peers/results.json");
    eprintln!("wrote {}", results.display());
}

/// Our solver from CasADi's optimum (see the module docs).
fn cross_check(problem: &spine_design::DesignProblem, settings: &SolverSettings, run: &SolverRun, passive: &State, loaded: &State) -> CrossCheck {
    let design = Design { theta0: run.theta0.clone(), stiffness: run.stiffness.clone() };
    let mut warm = settings.clone();
    for (k, v) in [("mu_init", 1e-9), ("bound_push", 1e-10), ("bound_frac", 1e-10)] {
        warm.ipopt_options.insert(k.into(), ExtraOption::Num(v));
    }
    let mut nlp = FullSpaceNlp::new(problem, &design, passive, loaded);
    let solution = spine_ipopt::solve(&mut nlp, &warm.ipopt()).expect("valid options");
    CrossCheck {
        status: solution.status.to_string(),
        converged: solution.status.is_optimal(),
        iterations: solution.iterations,
        objective: solution.objective,
    }
}
