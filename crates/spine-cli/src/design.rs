//! `spine design`: eq. (33) with Ipopt, in the full or the reduced space, from the case's start
//! and optionally from seeded multi-starts.

use crate::output::Output;
use crate::{Failure, Outcome};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};
use spine_case::{DesignCase, ValidDesign};
use spine_design::multistart::{cluster, feasible_starts};
use spine_design::{solve_design, DesignResult, Formulation};

/// Command-line overrides of a design case.
#[derive(Clone, Copy, Debug, Default)]
pub struct Overrides {
    pub formulation: Option<Formulation>,
    pub starts: Option<usize>,
    pub seed: Option<u64>,
    pub refine: Option<spine_design::refine::Refine>,
}

/// The result as JSON with its timings moved under `timings` (dropped by `--deterministic`):
/// Ipopt's and the evaluations' under their own names, every other `*_seconds` by its path.
fn result_json(result: &DesignResult) -> (Value, Value) {
    let mut value = serde_json::to_value(result).expect("results serialise");
    let solver = value.get_mut("solver").and_then(Value::as_object_mut).expect("solver report");
    let mut timings = serde_json::Map::new();
    for key in ["ipopt_seconds", "evaluation_seconds"] {
        timings.insert(key.into(), solver.remove(key).unwrap_or(Value::Null));
    }
    crate::figure::split_timings(&mut value, "", &mut timings);
    (value, Value::Object(timings))
}

fn run_one(
    valid: &ValidDesign,
    formulation: Formulation,
    start: &spine_model::Design,
) -> Result<DesignResult, Failure> {
    solve_design(&valid.problem, start, formulation, &valid.settings, &mut |_| true)
        .map_err(|e| Failure::Input(format!("solver: {e}")))
}

fn print_summary(title: &str, r: &DesignResult) {
    println!("{title} — {} links, {} space, C_K = {}", r.design.theta0.len(), r.formulation.name(), r.stiffness_scale);
    println!(
        "Ipopt: {} after {} iterations ({:.3} s, {:.3} s in evaluations)",
        r.solver.status, r.solver.iterations, r.solver.ipopt_seconds, r.solver.evaluation_seconds
    );
    if let Some(refinement) = &r.refinement {
        for l in &refinement.levels {
            println!(
                "  level {:>5} links ({:?} start): {} after {} iterations, J = {:.10e} J",
                l.links, l.start, l.status, l.iterations, l.objective
            );
        }
    }
    println!("J = U(θ1) = {:.10e} J", r.objective);
    if let Some(v) = &r.violations {
        println!(
            "largest constraint violation {:.2e} (equilibria {:.1e} / {:.1e} N·m, end {:.1e} m)",
            v.max, v.passive_equilibrium, v.loaded_equilibrium, v.end_displacement
        );
    }
    match r.end_displacement {
        Some(d) => println!("end displacement X(θ2) − L_x = {d:.9e} m (target δ_d = {:.9e} m)", r.delta_d),
        None => println!("end displacement: none"),
    }
    for (name, s) in [("θ1 passive", &r.passive), ("θ2 loaded", &r.loaded)] {
        if let Some(s) = s {
            let eig = s.stability.min_eigenvalue.map_or("none".into(), |e| format!("{e:.4e}"));
            println!(
                "{name:<11} {} (smallest reduced-Hessian eigenvalue {eig} N·m/rad)",
                if s.stability.stable { "stable" } else { "UNSTABLE" }
            );
        }
    }
    println!("θ0 (rad) = {:?}", r.design.theta0.iter().map(|t| (t * 1e6).round() / 1e6).collect::<Vec<_>>());
    println!("K (N·m/rad) = {:?}", r.design.stiffness.iter().map(|k| (k * 1e3).round() / 1e3).collect::<Vec<_>>());
    for note in &r.start_notes {
        println!("start: {note}");
    }
    for w in &r.warnings {
        println!("WARNING: {w}");
    }
}

pub fn run(case: &DesignCase, valid: &ValidDesign, overrides: Overrides, out: &Output) -> Result<Outcome, Failure> {
    let mut valid = valid.clone();
    if let Some(refine) = overrides.refine {
        valid.settings.refine = refine;
    }
    let valid = &valid;
    let formulation = overrides.formulation.unwrap_or(valid.formulation);
    let starts = overrides.starts.unwrap_or(valid.multistart.starts);
    let seed = overrides.seed.unwrap_or(valid.multistart.seed);
    let main = run_one(valid, formulation, &valid.start)?;
    let (mut result, timings) = result_json(&main);

    let mut multistart = Value::Null;
    if starts > 0 {
        let designs = feasible_starts(&valid.problem, starts, seed);
        let bar = ProgressBar::new(starts as u64);
        bar.set_style(
            ProgressStyle::with_template("multi-start {bar:40} {pos}/{len} [{elapsed_precise}]")
                .expect("valid template"),
        );
        let mut results = vec![main.clone()];
        for d in &designs {
            results.push(run_one(valid, formulation, d)?);
            bar.inc(1);
        }
        bar.finish_and_clear();
        let summary = cluster(&results, seed);
        println!(
            "multi-start: {} runs (the case's start and {starts} seeded starts, seed {seed}), {} converged, {} distinct optima",
            summary.starts, summary.converged, summary.optima.len()
        );
        for (k, o) in summary.optima.iter().enumerate() {
            println!(
                "  optimum {k}: J = {:.10e} J, reached by {} run(s){}",
                o.objective,
                o.count,
                if o.clean { "" } else { " (not clean: see warnings of its runs)" }
            );
        }
        multistart = serde_json::to_value(&summary).expect("summary serialises");
    }
    let title = if case.title.is_empty() { "design" } else { &case.title };
    if let Value::Object(map) = &mut result {
        map.insert("kind".into(), json!("design"));
        map.insert("title".into(), json!(title));
        map.insert("multistart".into(), multistart);
        map.insert("timings".into(), timings);
    }
    let path = out.write_json("result.json", result)?;
    print_summary(title, &main);
    println!("wrote {}", path.display());
    Ok(if main.is_clean() { Outcome::Success } else { Outcome::NotConverged })
}
