//! `spine equilibrium`: θ1 and θ2 of a given design.

use crate::output::Output;
use crate::{Failure, Outcome};
use serde_json::{json, Value};
use spine_case::{EquilibriumCase, ValidEquilibrium};
use spine_model::energy::strain_energy;
use spine_model::kinematics::{link_lengths, node_positions};
use spine_solve::{solve_static, EquilibriumSolution};

fn nodes(lengths: &[f64], theta: &[f64]) -> Vec<[f64; 2]> {
    node_positions(lengths, theta).into_iter().map(|(x, y)| [x, y]).collect()
}

fn state_json(sol: &EquilibriumSolution, lengths: &[f64], valid: &ValidEquilibrium) -> Value {
    let d = &valid.problem.design;
    json!({
        "status": sol.status,
        "status_text": sol.status.describe(),
        "load_factor": sol.load_factor,
        "theta": sol.state.theta,
        "lambda": sol.state.lambda,
        "nodes": nodes(lengths, &sol.state.theta),
        "strain_energy": strain_energy(&sol.state.theta, &d.theta0, &d.stiffness),
        "residual_norm": sol.residual_norm,
        "constraint_violation": sol.constraint_violation,
        "tolerance_used": sol.tolerance_used,
        "stability": sol.stability,
        "continuation_steps": sol.stats.continuation_steps,
        "rejected_steps": sol.stats.rejected_steps,
        "newton_iterations": sol.stats.newton_iterations,
        "factorisations": sol.stats.factorisations,
        "general_factorisations": sol.stats.general_factorisations,
    })
}

fn summary_line(name: &str, sol: &EquilibriumSolution) -> String {
    let eig = sol.stability.min_eigenvalue.map_or("none (rigid)".to_string(), |e| format!("{e:.6e} N·m/rad"));
    format!(
        "{name:<8} {}\n         residual {:.2e} N·m, |Φ| {:.2e} m, smallest projected stiffness {eig}, {} steps / {} Newton iterations",
        sol.status.describe(),
        sol.residual_norm,
        sol.constraint_violation,
        sol.stats.continuation_steps,
        sol.stats.newton_iterations
    )
}

pub fn run(case: &EquilibriumCase, valid: &ValidEquilibrium, out: &Output) -> Result<Outcome, Failure> {
    let p = &valid.problem;
    let sol = solve_static(p, &valid.options);
    let lengths = link_lengths(&p.chain.spans, &p.design.theta0);
    let loaded = sol.loaded.as_ref();
    let result = json!({
        "kind": "equilibrium",
        "title": case.title,
        "n_links": p.chain.n_links(),
        "length_x": p.chain.length_x(),
        "link_lengths": lengths,
        "design": p.design,
        "unloaded": { "nodes": nodes(&lengths, &p.design.theta0) },
        "passive": state_json(&sol.passive, &lengths, valid),
        "loaded": loaded.map(|l| state_json(l, &lengths, valid)),
        "passive_end_displacement": sol.passive_end_displacement,
        "end_displacement": sol.end_displacement,
        "timings": {
            "passive_seconds": sol.passive.stats.time_seconds,
            "loaded_seconds": loaded.map(|l| l.stats.time_seconds),
        },
    });
    let path = out.write_json("result.json", result)?;
    println!("{} — {} links", if case.title.is_empty() { "equilibrium" } else { &case.title }, p.chain.n_links());
    println!("{}", summary_line("passive", &sol.passive));
    match loaded {
        Some(l) => println!("{}", summary_line("loaded", l)),
        None => println!("loaded   not attempted: the passive path did not reach its load"),
    }
    match sol.end_displacement {
        Some(d) => {
            println!("end displacement X(θ2) − L_x = {d:.9e} m (passive alone {:.9e} m)", sol.passive_end_displacement)
        }
        None => println!("end displacement: none (loaded path incomplete)"),
    }
    println!("wrote {}", path.display());
    let ok = sol.passive.status.is_stable() && loaded.is_some_and(|l| l.status.is_stable());
    Ok(if ok { Outcome::Success } else { Outcome::NotConverged })
}
