//! `spine simulate`, `spine damping`, `spine periodic`: the dynamics of Sec. 5.2.

use crate::output::Output;
use crate::{Failure, Outcome};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{json, Value};
use spine_case::{DynamicsCase, DynamicsTask, ValidDynamics};
use spine_dynamics::response::Sample;
use spine_dynamics::{
    design_damping, design_periodic, periodic_response, step_response, DynamicProblem, DynamicsError, SearchMethod,
};
use spine_model::Design;

/// The design of the case: given, or found by eq. (33) first (which must end clean), and its
/// summary for `result.json`.
fn resolve_design(valid: &ValidDynamics) -> Result<(Design, Value), Failure> {
    let used = spine_paper::run::resolve_design(valid).map_err(|e| match e {
        spine_paper::RunError::Input(m) => Failure::Input(format!("static_design: {m}")),
        spine_paper::RunError::Failed(m) => Failure::Other(m),
    })?;
    let Some(s) = &used.static_design else {
        return Ok((used.design, json!("given")));
    };
    let r = &s.result;
    println!(
        "eq. (33) design: {} after {} iterations, J = {:.6e} J, δ = {:?} m, clean",
        r.solver.status, r.solver.iterations, r.objective, r.end_displacement
    );
    let summary = json!({
        "source": "eq. (33)",
        "status": r.solver.status,
        "iterations": r.solver.iterations,
        "objective": r.objective,
        "end_displacement": r.end_displacement,
        "delta_d": r.delta_d,
    });
    Ok((used.design, summary))
}

fn input_error(e: DynamicsError) -> Failure {
    Failure::Input(format!("design: {e}"))
}

fn write_csv(out: &Output, name: &str, samples: &[Sample]) -> Result<(), Failure> {
    out.write_text(name, &spine_paper::figures::samples_csv(samples))
}

/// Moves `time_seconds` (wall times) out of a result into the `timings` map.
fn take_time(value: &mut Value, key: &str, timings: &mut serde_json::Map<String, Value>) {
    if let Some(t) = value.as_object_mut().and_then(|m| m.remove("time_seconds")) {
        timings.insert(key.to_string(), t);
    }
}

pub fn run(
    case: &DynamicsCase,
    valid: &ValidDynamics,
    kind: &str,
    method: Option<SearchMethod>,
    out: &Output,
) -> Result<Outcome, Failure> {
    let (design, design_source) = resolve_design(valid)?;
    let problem = DynamicProblem {
        chain: valid.chain.clone(),
        design: design.clone(),
        damping: valid.damping.clone(),
        passive: valid.passive.clone(),
        actuation: valid.actuation.clone(),
    };
    let title = if case.title.is_empty() { kind.to_string() } else { case.title.clone() };
    println!("{title} — {} links", valid.chain.n_links());
    let mut timings = serde_json::Map::new();
    let mut result = json!({
        "kind": kind,
        "title": title,
        "design": { "theta0": design.theta0, "stiffness": design.stiffness, "source": design_source },
        "damping": valid.damping,
        "forcing": valid.forcing,
    });
    let ok = match &valid.task {
        DynamicsTask::Simulate if valid.forcing.period().is_none() => {
            let r = step_response(&problem, &valid.step, false).map_err(input_error)?;
            write_csv(out, "response.csv", &r.samples)?;
            let mut v = serde_json::to_value(&r).expect("serialises");
            take_time(&mut v, "integration_seconds", &mut timings);
            result["step_response"] = v;
            println!(
                "static ends: θ1 {} (X − L_x = {:.6e} m), θ2 {} (X − L_x = {:.6e} m)",
                r.ends.passive_status, r.ends.passive_displacement, r.ends.loaded_status, r.ends.loaded_displacement
            );
            println!(
                "integration: {:?}, {} steps ({} rejected), {} f-evaluations, {} Jacobians, {:.3} s",
                r.outcome,
                r.stats.accepted_steps,
                r.stats.rejected_steps,
                r.stats.rhs_evaluations,
                r.stats.jacobian_evaluations,
                r.time_seconds
            );
            println!(
                "Δ∞ = {:.6e} m; T_{:.0} = {} ; τ = ln(10)/T_90 = {}",
                r.delta_inf,
                100.0 * valid.step.rise_fraction,
                r.rise_time.map_or("not reached".into(), |t| format!("{t:.6} s")),
                r.tau_from_rise_time.map_or("—".into(), |t| format!("{t:.4} 1/s"))
            );
            println!(
                "first-order fit Δ∞(1 − e^(−τt)): τ = {:.4} 1/s, RMS error {:.2} % of Δ∞ (max {:.2} %)",
                r.fit.tau,
                100.0 * r.fit.rms_error,
                100.0 * r.fit.max_error
            );
            println!(
                "settled in θ2: {} (|Δ(t_end) − Δ∞| = {:.2e} of Δ∞, max |θ − θ2| = {:.2e} rad)",
                if r.settled { "yes" } else { "NO" },
                r.settle_error,
                r.final_state_gap
            );
            println!("constraint drift: |Φ| ≤ {:.1e} m, |Φ̇| ≤ {:.1e} m/s at steps; {:.1e} m, {:.1e} m/s on the dense output; largest projection {:.1e}", r.drift.max_constraint, r.drift.max_constraint_rate, r.drift.max_constraint_dense, r.drift.max_constraint_rate_dense, r.drift.max_projection);
            r.settled && r.rise_time.is_some()
        }
        DynamicsTask::Simulate => {
            let r = periodic_response(&problem, valid.forcing.clone(), None, &valid.periodic).map_err(input_error)?;
            write_csv(out, "response.csv", &r.samples)?;
            let mut v = serde_json::to_value(&r).expect("serialises");
            take_time(&mut v, "integration_seconds", &mut timings);
            result["periodic_response"] = v;
            print_periodic(&r);
            r.settled
        }
        DynamicsTask::Damping { targets, settings } => {
            let mut designs = Vec::new();
            let mut all_ok = true;
            println!(
                "{:>8} {:>10} {:>12} {:>10} {:>5}  dampers C (N·m·s/rad)",
                "T_d (s)", "status", "T_90 (s)", "error", "iter"
            );
            for &target in targets {
                let r = design_damping(&problem, target, settings).map_err(input_error)?;
                write_csv(out, &format!("response_T{target}.csv"), &r.response.samples)?;
                let periodic = if valid.forcing.period().is_some() {
                    let p = spine_paper::run::dynamic_problem(valid, &design, &r.damping);
                    let pr =
                        periodic_response(&p, valid.forcing.clone(), None, &valid.periodic).map_err(input_error)?;
                    write_csv(out, &format!("periodic_T{target}.csv"), &pr.samples)?;
                    print_periodic(&pr);
                    all_ok &= pr.settled;
                    let mut v = serde_json::to_value(&pr).expect("serialises");
                    take_time(&mut v, &format!("periodic_T{target}_seconds"), &mut timings);
                    v
                } else {
                    Value::Null
                };
                let err = r.rise_time_error.unwrap_or(f64::INFINITY);
                println!(
                    "{target:>8} {:>10} {:>12} {:>9.2e} {:>5}  {:?}",
                    if r.converged { "converged" } else { "FAILED" },
                    r.rise_time.map_or("—".into(), |t| format!("{t:.6}")),
                    err,
                    r.iterations,
                    r.damping.iter().map(|c| (c * 1e3).round() / 1e3).collect::<Vec<_>>()
                );
                all_ok &= r.converged && err <= 5e-3;
                let mut v = serde_json::to_value(&r).expect("serialises");
                take_time(&mut v, &format!("design_T{target}_seconds"), &mut timings);
                if let Some(resp) = v.get_mut("response") {
                    take_time(resp, &format!("response_T{target}_seconds"), &mut timings);
                }
                v["periodic_response"] = periodic;
                designs.push(v);
            }
            result["damping_designs"] = Value::Array(designs);
            all_ok
        }
        DynamicsTask::Periodic { delta_d, method: case_method, settings } => {
            let method = method.unwrap_or(*case_method);
            let bar = ProgressBar::new(match method {
                SearchMethod::Ga => settings.ga.generations as u64,
                SearchMethod::Pattern => settings.pattern.max_evaluations as u64,
            });
            bar.set_style(
                ProgressStyle::with_template("eq. (37) {msg} {bar:40} {pos}/{len} [{elapsed_precise}]")
                    .expect("valid template"),
            );
            bar.set_message(format!("{method:?}"));
            let r = design_periodic(&problem, valid.forcing.clone(), *delta_d, method, settings, &mut |p| {
                bar.set_position(match method {
                    SearchMethod::Ga => p.iteration as u64,
                    SearchMethod::Pattern => p.evaluations as u64,
                })
            })
            .map_err(input_error)?;
            bar.finish_and_clear();
            write_csv(out, "response.csv", &r.response.samples)?;
            println!(
                "eq. (37) by {:?}: {:?} after {} iterations, {} evaluations; {}",
                method,
                r.search.status,
                r.search.iterations,
                r.search.evaluations,
                if r.feasible { "feasible" } else { "NOT feasible" }
            );
            println!(
                "U(θ1) = {:.6e} J (start {:.6e} J, violation {:.2e})",
                r.objective, r.start.objective, r.start.violation
            );
            println!(
                "min_t (X − L_x) = {:.6e} m against δ_d = {:.6e} m ({:.2} % off)",
                r.min_end_displacement,
                r.delta_d,
                100.0 * r.relative_error
            );
            println!("K (N·m/rad) = {:?}", r.stiffness.iter().map(|k| (k * 10.0).round() / 10.0).collect::<Vec<_>>());
            print_periodic(&r.response);
            let mut v = serde_json::to_value(&r).expect("serialises");
            take_time(&mut v, "design_seconds", &mut timings);
            if let Some(resp) = v.get_mut("response") {
                take_time(resp, "response_seconds", &mut timings);
            }
            result["periodic_design"] = v;
            r.feasible && r.response.settled
        }
    };
    result["timings"] = Value::Object(timings);
    let path = out.write_json("result.json", result)?;
    println!("wrote {}", path.display());
    Ok(if ok { Outcome::Success } else { Outcome::NotConverged })
}

fn print_periodic(r: &spine_dynamics::PeriodicResponse) {
    let opt = |v: Option<f64>| v.map_or("not reached".to_string(), |t| format!("{t:.4} s"));
    println!(
        "periodic response: {} after {} periods (last two differ by {:.1e} of the swing), period {:.4} s",
        if r.settled { "settled" } else { "NOT settled" },
        r.periods_run,
        r.period_change,
        r.period
    );
    println!(
        "last period: min X − L_x = {:.6e} m ({:.4} s after onset), max {:.6e} m; reach (90 %) {} (paper: about 0.5 s), return (90 %) {} (paper: about 0.25 s)",
        r.min_end_displacement, r.time_of_minimum, r.max_end_displacement, opt(r.reach_time), opt(r.return_time)
    );
    println!(
        "constraint drift: |Φ| ≤ {:.1e} m at steps, {:.1e} m on the dense output",
        r.drift.max_constraint, r.drift.max_constraint_dense
    );
}
