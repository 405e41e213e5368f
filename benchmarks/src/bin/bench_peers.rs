//! `just bench-peers`: eq. (33) on the scaled family of `docs/PEERS.md`, solved by this
//! workspace and by CasADi + IPOPT (`benchmarks/peers/casadi_static.py`) from the same case file
//! and the same start point, one N at a time. Prints the comparison table and writes
//! `benchmarks/peers/results.json` (read by `bench_report` into `benchmarks/RESULTS.md`).
//!
//! Usage: `bench_peers PYTHON [N ...]` (default N: 5 10 20 50 100 200 500 1000). The case files
//! and start points go to `target/bench-peers/`.
//!
//! Built against Debian's Ipopt (the default), it runs ours cold and refined (mesh sequencing,
//! [`peers::bench_ladder`]) and CasADi cold, and writes the rows. Built against Ipopt 3.14
//! (`just ipopt314 build`), it runs ours cold and refined on that backend and adds them to the
//! rows already in `benchmarks/peers/results.json`. With `--casadi-refined` it runs CasADi through
//! the same ladder as ours (see [`casadi_refined`]) and adds that to the rows.
//!
//! Where the two optima differ, our solver is started from CasADi's optimum (its design and both
//! states; barrier parameter 1e-9 and bound push 1e-10 so that Ipopt does not move away from the
//! active bounds first): staying there shows that CasADi's point is a KKT point of our NLP, so
//! the two programs solve the same problem and only their paths differ.
#![forbid(unsafe_code)]

use serde_json::json;
use spine_benchmarks::cli;
use spine_benchmarks::peers::{self, CrossCheck, LevelRun, PeerRow, SolverRun};
use spine_design::full_space::FullSpaceNlp;
use spine_design::refine::{Refine, RefineMode};
use spine_design::settings::SolverPreset;
use spine_design::settings::{ExtraOption, LinearSolver};
use spine_design::solve::Solver;
use spine_design::start_point::FullSpaceStart;
use spine_design::{DesignResult, Formulation, SolverSettings};
use spine_model::{Design, State};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The allocator `spine` ships with (mimalloc, the whole process's `malloc`), so that ours is
/// timed as a user runs it; CasADi runs in its own Python process with its own allocator.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn run_of(r: &DesignResult, wall_seconds: f64) -> SolverRun {
    SolverRun {
        status: r.solver.status.to_string(),
        converged: r.solver.optimal && r.is_clean(),
        warnings: if r.solver.optimal { r.warnings.iter().map(ToString::to_string).collect() } else { Vec::new() },
        iterations: r.solver.iterations,
        wall_seconds,
        objective: r.objective,
        constraint_violation: r.violations.as_ref().map_or(f64::NAN, |v| v.constraint_rows()),
        theta0: r.design.theta0.clone(),
        stiffness: r.design.stiffness.clone(),
        ipopt_version: r.solver.ipopt_version.clone(),
        levels: r.refinement.as_ref().map_or(Vec::new(), |rf| {
            rf.levels
                .iter()
                .map(|l| LevelRun {
                    links: l.links,
                    status: l.status.to_string(),
                    iterations: l.iterations,
                    wall_seconds: l.wall_seconds,
                })
                .collect()
        }),
    }
}

/// Ours on the case, cold (`refine` off) or with the bench ladder.
fn ours(valid: &spine_case::ValidDesign, n: usize, refined: bool) -> Option<SolverRun> {
    ours_with(valid, n, refined, None)
}

/// [`ours`], with `linear_solver` set to `linear_solver` when given.
fn ours_with(
    valid: &spine_case::ValidDesign,
    n: usize,
    refined: bool,
    linear_solver: Option<LinearSolver>,
) -> Option<SolverRun> {
    let mut settings = valid.settings.clone();
    if let Some(solver) = linear_solver {
        settings.linear_solver = solver;
    }
    if refined {
        settings.refine = Refine::Ladder(peers::bench_ladder(n)?);
    } else {
        settings.refine = Refine::Mode(RefineMode::Off);
    }
    let clock = Instant::now();
    let r = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
        .solve(&valid.problem, &valid.start, &mut |_| true)
        .expect("valid problem");
    let run = run_of(&r, clock.elapsed().as_secs_f64());
    eprintln!(
        "N = {n}: ours {}{} ({}) {} in {:.3} s ({} iterations{}), J = {:.9e}",
        if refined { "refined" } else { "cold" },
        linear_solver.map_or(String::new(), |s| format!(", linear_solver {}", s.ipopt().name())),
        run.ipopt_version,
        run.status,
        run.wall_seconds,
        run.iterations,
        if refined { format!("; levels {}", run.ladder()) } else { String::new() },
        run.objective
    );
    Some(run)
}

/// The rows of an earlier run, which the 3.14 and CasADi-ladder runs add to.
fn read_rows(results: &Path) -> Vec<PeerRow> {
    let text = std::fs::read_to_string(results)
        .expect("run bench_peers on the default backend first: benchmarks/peers/results.json");
    serde_json::from_str(&text).expect("benchmarks/peers/results.json")
}

/// Prints the table and writes the rows.
fn write_rows(results: &Path, rows: &[PeerRow]) {
    println!("{}", peers::table(rows));
    std::fs::write(results, serde_json::to_string_pretty(rows).expect("JSON") + "\n")
        .expect("benchmarks/peers/results.json");
    eprintln!("wrote {}", results.display());
}

fn write(path: &Path, value: &serde_json::Value) {
    std::fs::write(path, serde_json::to_string_pretty(value).expect("JSON"))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

fn casadi(python: &str, case: &Path, start: &Path, out: &Path) -> Result<(SolverRun, State, State), String> {
    let v = peers::run_script(python, "casadi_static.py", &[case, start, out], out)?;
    let floats = |k: &str| -> Vec<f64> {
        v[k].as_array().map(|a| a.iter().filter_map(|x| x.as_f64()).collect()).unwrap_or_default()
    };
    let run = SolverRun {
        status: v["status"].as_str().unwrap_or("unknown").into(),
        converged: v["converged"].as_bool().unwrap_or(false),
        iterations: v["iterations"].as_u64().unwrap_or(0) as usize,
        wall_seconds: v["wall_seconds"].as_f64().unwrap_or(f64::NAN),
        objective: v["objective"].as_f64().unwrap_or(f64::NAN),
        constraint_violation: v["constraint_violation"].as_f64().unwrap_or(f64::NAN),
        theta0: floats("theta0"),
        stiffness: floats("stiffness"),
        ipopt_version: v["ipopt_version"].as_str().unwrap_or("CasADi").into(),
        levels: Vec::new(),
        warnings: Vec::new(),
    };
    let passive = State { theta: floats("theta1"), lambda: v["lambda1"].as_f64().unwrap_or(0.0) };
    let loaded = State { theta: floats("theta2"), lambda: v["lambda2"].as_f64().unwrap_or(0.0) };
    Ok((run, passive, loaded))
}

/// Eq. (33) by this workspace beside CasADi + IPOPT and scipy on the same cases, one run.
#[derive(clap::Parser)]
struct Args {
    /// The Python interpreter with CasADi and scipy (benchmarks/peers/.venv/bin/python).
    python: String,
    /// Add CasADi's rows through the same refinement ladder as ours.
    #[arg(long = "casadi-refined")]
    casadi_ladder: bool,
    /// Chain sizes (links, at least 2); 5 to 1000 when none is given.
    #[arg(value_parser = cli::links)]
    sizes: Vec<usize>,
}

fn main() {
    let Args { python, casadi_ladder, sizes } = <Args as clap::Parser>::parse();
    let sizes = if sizes.is_empty() { vec![5, 10, 20, 50, 100, 200, 500, 1000] } else { sizes };
    let dir = PathBuf::from("target/bench-peers");
    std::fs::create_dir_all(&dir).expect("target/bench-peers");
    let results = Path::new("benchmarks/peers/results.json");
    if casadi_ladder {
        add_casadi_refined(&python, &sizes, &dir, results);
    } else if spine_ipopt::IPOPT_VERSION.starts_with("3.14") {
        add_ipopt314(&sizes, results);
    } else {
        let rows: Vec<PeerRow> = sizes.iter().map(|&n| measure(&python, n, &dir)).collect();
        write_rows(results, &rows);
    }
}

/// `--casadi-refined`: CasADi through our ladder, added to the rows in `results`.
fn add_casadi_refined(python: &str, sizes: &[usize], dir: &Path, results: &Path) {
    let mut rows = read_rows(results);
    for &n in sizes {
        let Some(row) = rows.iter_mut().find(|r| r.n == n) else { continue };
        match casadi_refined(python, n, dir) {
            Ok(run) => {
                eprintln!(
                    "N = {n}: CasADi refined {} in {:.3} s; levels {}",
                    run.status,
                    run.wall_seconds,
                    run.ladder()
                );
                row.casadi_refined = Some(run);
            }
            Err(e) => eprintln!("N = {n}: CasADi refined: {e}"),
        }
    }
    write_rows(results, &rows);
}

/// Built against Ipopt 3.14: our cold and refined runs, added to the rows in `results`.
fn add_ipopt314(sizes: &[usize], results: &Path) {
    let mut rows = read_rows(results);
    for &n in sizes {
        let Some(row) = rows.iter_mut().find(|r| r.n == n) else {
            eprintln!("N = {n}: no row from the default backend; skipped");
            continue;
        };
        let valid = peers::scaled_family_design(n);
        row.ipopt314 = ours(&valid, n, false);
        row.ipopt314_refined = ours(&valid, n, true).or_else(|| row.ipopt314.clone());
    }
    write_rows(results, &rows);
}

/// One row on the default backend: ours cold, refined and with our factorisation, and CasADi cold
/// from the same case file and start point.
fn measure(python: &str, n: usize, dir: &Path) -> PeerRow {
    let case_path = dir.join(format!("scaled-{n}.json"));
    let case_value = peers::scaled_family_case(n);
    write(&case_path, &case_value);
    let valid = peers::scaled_family_design(n);
    let (problem, settings) = (&valid.problem, &valid.settings);

    // The exact start point of our full space, handed to the peer.
    let start = FullSpaceStart::new(problem, &valid.start, &settings.continuation);
    let start_path = dir.join(format!("start-{n}.json"));
    write(&start_path, &serde_json::to_value(&start).expect("JSON"));

    let cold = ours(&valid, n, false).expect("a cold run");
    let ours_refined = ours(&valid, n, true).or_else(|| Some(cold.clone()));
    let ours_mumps = ours_with(&valid, n, false, Some(LinearSolver::Mumps));
    let ours = cold;

    let out_path = dir.join(format!("casadi-{n}.json"));
    let (casadi_run, casadi_error, cross_check) = match casadi(python, &case_path, &start_path, &out_path) {
        Ok((run, passive, loaded)) => {
            eprintln!(
                "N = {n}: CasADi {} in {:.3} s ({} iterations), J = {:.9e}",
                run.status, run.wall_seconds, run.iterations, run.objective
            );
            let differs = (run.objective - ours.objective).abs() > peers::SAME_OPTIMUM * run.objective.abs();
            let check = (differs && run.converged).then(|| cross_check(problem, settings, &run, &passive, &loaded));
            (Some(run), None, check)
        }
        Err(e) => {
            eprintln!("N = {n}: CasADi: {e}");
            (None, Some(e), None)
        }
    };
    PeerRow {
        n,
        case: case_path.display().to_string(),
        ours,
        casadi: casadi_run,
        casadi_error,
        cross_check,
        ours_refined,
        ipopt314: None,
        ipopt314_refined: None,
        casadi_refined: None,
        ours_mumps,
    }
}

/// Our solver from CasADi's optimum (see the module docs).
fn cross_check(
    problem: &spine_design::DesignProblem,
    settings: &SolverSettings,
    run: &SolverRun,
    passive: &State,
    loaded: &State,
) -> CrossCheck {
    let design = Design { theta0: run.theta0.clone(), stiffness: run.stiffness.clone() };
    let mut warm = settings.clone();
    for (k, v) in [("mu_init", 1e-9), ("bound_push", 1e-10), ("bound_frac", 1e-10)] {
        warm.ipopt_options.insert(k.into(), ExtraOption::Num(v));
    }
    let states = settings.state_variables.resolve(problem, settings.smaller_tolerance());
    let mut nlp = FullSpaceNlp::new(problem, states, &design, passive, loaded);
    let solution = spine_ipopt::solve(&mut nlp, &warm.ipopt()).expect("valid options");
    CrossCheck {
        status: solution.status.to_string(),
        converged: solution.status.is_optimal(),
        iterations: solution.iterations,
        objective: solution.objective,
    }
}

/// A coarse level of the ladder as a case file for the peer script (its lumped loads and scaled
/// stiffness bounds per node), with the warm-start options of our warm levels.
fn level_case(
    level: &spine_design::DesignProblem,
    template: &spine_design::SolverSettings,
    start: &Design,
    warm: bool,
    coarse: bool,
) -> serde_json::Value {
    let m = level.n_links();
    assert!(
        level.structure.passive.p_x.iter().all(|v| *v == 0.0)
            && level.structure.actuation.p_y.iter().all(|v| *v == 0.0)
    );
    assert!(level.structure.actuation.p_x[..m].iter().all(|v| *v == 0.0), "axial load at the end only");
    let w = &template.warm_start;
    // Coarse levels to the warm start's coarse tolerance, as in our own refined runs.
    let tolerance = if coarse { template.coarse_tolerance() } else { template.tolerance };
    let mut solver =
        json!({ "tolerance": tolerance, "constraint_tolerance": template.constraint_tolerance, "refine": "off" });
    if warm {
        solver["ipopt_options"] =
            json!({ "mu_init": w.mu_init, "bound_push": w.bound_push, "bound_frac": w.bound_frac });
    }
    let b = &level.bounds;
    json!({
        "kind": "design",
        "title": format!("ladder level, {m} links"),
        "chain": { "links": m, "spans": level.structure.chain.spans, "masses": level.structure.chain.masses, "gravity": level.structure.chain.gravity },
        "loads": { "p_y": level.structure.passive.p_y, "p_x": level.structure.actuation.p_x[m], "self_weight": false },
        "delta_d": level.delta_d,
        "stiffness_scale": level.stiffness_scale,
        "bounds": { "theta0_max": b.theta0_max, "relative_angle_max": b.relative_angle_max, "stiffness_min": b.stiffness_min, "stiffness_max": b.stiffness_max, "height_min": b.height_min, "height_max": b.height_max },
        "start": { "theta0": start.theta0, "stiffness": start.stiffness },
        "formulation": "full",
        "solver": solver
    })
}

/// CasADi through our ladder ([`peers::bench_ladder`]): the coarsest level cold from the case's
/// start restricted to it, every finer level from our prolongation of CasADi's previous optimum
/// (`refine::prepare_level`, as in our own refined runs) with the same warm-start
/// options. Wall time: CasADi's solver calls plus the prolongations.
fn casadi_refined(python: &str, n: usize, dir: &Path) -> Result<SolverRun, String> {
    use spine_design::refine;
    let ladder = peers::bench_ladder(n).ok_or("no ladder below 10 links")?;
    let valid = peers::scaled_family_design(n);
    let (problem, settings) = (&valid.problem, &valid.settings);
    let (start, _) = problem.project_start(&valid.start);
    let mut previous: Option<(spine_design::DesignProblem, Design, (State, State))> = None;
    let (mut total, mut levels) = (0.0, Vec::new());
    for &m in &ladder.levels(n) {
        let clock = Instant::now();
        let previous_level = previous.as_ref().map(|(p, d, s)| (p, d, s));
        let restore = settings.warm_start.restore_end_displacement;
        let setup =
            refine::prepare_level(problem, m, previous_level, &start, restore, &settings.continuation, &mut Vec::new());
        let level = setup.problem(problem);
        let case_path = dir.join(format!("ladder-{n}-{m}.json"));
        let start_path = dir.join(format!("ladder-start-{n}-{m}.json"));
        let out_path = dir.join(format!("ladder-casadi-{n}-{m}.json"));
        write(&case_path, &level_case(level, settings, &setup.design, previous.is_some(), m < n));
        let (passive, loaded) = &setup.states;
        let start = FullSpaceStart::from_states(level, &setup.design, passive, loaded);
        write(&start_path, &serde_json::to_value(&start).expect("JSON"));
        let preparation = clock.elapsed().as_secs_f64();
        let (run, passive, loaded) = casadi(python, &case_path, &start_path, &out_path)?;
        total += preparation + run.wall_seconds;
        levels.push(LevelRun {
            links: m,
            status: if run.converged { "solve_succeeded".into() } else { run.status.clone() },
            iterations: run.iterations,
            wall_seconds: run.wall_seconds,
        });
        if m == n {
            return Ok(SolverRun { wall_seconds: total, levels, ..run });
        }
        if !(run.converged || run.status.to_lowercase().contains("acceptable")) {
            return Err(format!("level {m} ended {}", run.status));
        }
        previous = Some((
            level.clone(),
            Design { theta0: run.theta0.clone(), stiffness: run.stiffness.clone() },
            (passive, loaded),
        ));
    }
    Err("empty ladder".into())
}
