//! `spine case FIGURE.json`: every run of a figure case, then its plots, tables and checked claims.

use crate::output::Output;
use crate::{Failure, Outcome};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Map, Value};
use spine_case::{FigureCase, ValidRun};
use spine_paper::{recipe, Check, NamedRun, RunError, RunOutput};

/// Moves every `*_seconds` entry (wall times) of `value` into `timings`, keyed by its path, so that
/// `--deterministic` output has none.
pub fn split_timings(value: &mut Value, path: &str, timings: &mut Map<String, Value>) {
    match value {
        Value::Object(map) => {
            let keys: Vec<String> = map.keys().filter(|k| k.ends_with("_seconds")).cloned().collect();
            for k in keys {
                if let Some(v) = map.remove(&k) {
                    timings.insert(format!("{path}{k}"), v);
                }
            }
            for (k, v) in map.iter_mut() {
                split_timings(v, &format!("{path}{k}."), timings);
            }
        }
        Value::Array(items) => {
            for (i, v) in items.iter_mut().enumerate() {
                split_timings(v, &format!("{path}{i}."), timings);
            }
        }
        _ => {}
    }
}

pub fn run(case: &FigureCase, runs: &[ValidRun], out: &Output) -> Result<Outcome, Failure> {
    let title = if case.title.is_empty() { case.figure.clone() } else { case.title.clone() };
    println!("{title} ({} runs)", runs.len());
    let mut outputs: Vec<RunOutput> = Vec::new();
    let mut timings = Map::new();
    let clock = std::time::Instant::now();
    for (k, r) in runs.iter().enumerate() {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("  {msg} {bar:30} {pos}/{len} [{elapsed_precise}]").expect("valid template"),
        );
        bar.set_message(format!("run {} ({})", r.name, r.case.kind()));
        let started = std::time::Instant::now();
        let output = spine_paper::run::run(&r.valid, &mut |done, total| {
            bar.set_length(total as u64);
            bar.set_position(done as u64);
        })
        .map_err(|e| match e {
            RunError::Input(m) => Failure::Input(format!("runs[{k}] ({}): {m}", r.name)),
            RunError::Failed(m) => Failure::Other(format!("runs[{k}] ({}): {m}", r.name)),
        })?;
        bar.finish_and_clear();
        let seconds = started.elapsed().as_secs_f64();
        println!("  run {} ({}) done in {seconds:.2} s", r.name, r.case.kind());
        timings.insert(format!("run_{}_seconds", r.name), json!(seconds));
        outputs.push(output);
    }
    let named: Vec<NamedRun<'_>> =
        runs.iter().zip(&outputs).map(|(r, o)| NamedRun { name: &r.name, label: &r.label, output: o }).collect();
    let made = recipe(&case.figure, &title, &named).map_err(|m| Failure::Input(format!("{}: {m}", case.figure)))?;

    let mut files = Vec::new();
    for (name, text) in &made.tables {
        out.write_text(name, text)?;
        files.push(name.clone());
    }
    for (stem, fig) in &made.figures {
        out.write_figure(stem, fig)?;
        files.push(format!("{stem}.svg"));
        files.push(format!("{stem}.png"));
    }
    let mut run_values = Vec::new();
    for (r, o) in runs.iter().zip(&outputs) {
        let mut v = serde_json::to_value(o).expect("results serialise");
        split_timings(&mut v, &format!("{}.", r.name), &mut timings);
        run_values.push(json!({ "name": r.name, "label": r.label, "kind": r.case.kind(), "result": v }));
    }
    timings.insert("total_seconds".into(), json!(clock.elapsed().as_secs_f64()));
    let passed = made.claims.iter().filter(|c| c.pass).count();
    let result = json!({
        "kind": "figure",
        "figure": case.figure,
        "title": title,
        "notes": case.notes,
        "claims": made.claims,
        "claims_passed": passed,
        "claims_total": made.claims.len(),
        "summary": made.summary,
        "files": files,
        "runs": run_values,
        "timings": timings,
    });
    let path = out.write_json("result.json", result)?;
    println!("claims ({passed} of {} PASS):", made.claims.len());
    for c in &made.claims {
        println!("  {c}");
    }
    println!("wrote {} and {} files beside it", path.display(), files.len());
    let solver_ok = made.claims.iter().all(|c| c.pass || c.check != Check::Solver);
    if !solver_ok {
        println!("a solver check FAILED: this figure is not a valid reproduction (see the claims above)");
    }
    Ok(if solver_ok { Outcome::Success } else { Outcome::NotConverged })
}
