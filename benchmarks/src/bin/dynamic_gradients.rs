//! `just bench-gradients`: eq. (37)'s constraint gradients by the discrete adjoint against forward
//! sensitivities, and eq. (37) by gradients against the genetic algorithm, side by side in one run.
//!
//! * **Per gradient**: the periodic fixture chain of N links
//!   (`spine_dynamics::fixtures::periodic_problem`) under 0.4 s pulses, 3 periods: a plain run
//!   that keeps its steps, the adjoint sweeps of both constraint minima, and a run with forward
//!   sensitivities (N + 1 columns); the fastest of `REPEATS` each, and the largest difference of
//!   the two gradients.
//! * **Per design**: eq. (37) by gradients (Ipopt) with the adjoint and with forward
//!   sensitivities, and by the GA (the case's settings), on the same chain and band (δ_d 20 %
//!   beyond the start's minimum), one run each, wall time on this machine's cores (rayon's pool:
//!   the GA's evaluations and the adjoint's two sweeps run side by side).
//!
//! Writes the section "Gradients of eq. (37)" of `benchmarks/DYNAMICS.md` (replacing it; the rest
//! of the file is `just bench-dynamics`').
//!
//! * **Eq. (35)**: the rise time's `dT_90/dC` by the adjoint and by forward sensitivities.
//!
//! Usage: `dynamic_gradients [--sweeps-only] [--paper-only] [--gradient-sizes=7,20,50] [--rise-sizes=5,10,20]
//! [--design-sizes=7,50]`.
#![forbid(unsafe_code)]

use spine_dynamic_design::periodic_gradient::{eq37_point, eq37_values};
use spine_dynamic_design::periodic_settings::{GradientStart, Sensitivities};
use spine_dynamic_design::{design_periodic, PeriodicDesignSettings, SearchMethod};
use spine_dynamics::fixtures::periodic_problem;
use spine_dynamics::response::rise_time_by;
use spine_dynamics::{periodic_response, DynamicProblem, Forcing};
use std::fmt::Write;
use std::time::Instant;

const REPEATS: usize = 3;
use spine_benchmarks::cli;
use spine_benchmarks::GRADIENTS_SECTION as SECTION;

fn fastest<T>(mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..REPEATS {
        let clock = Instant::now();
        let r = f();
        best = best.min(clock.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

/// Eq. (37)'s gradients by the discrete adjoint against forward sensitivities, and eq. (35)'s.
#[derive(clap::Parser)]
struct Args {
    /// The per-gradient rows alone (no rise or design rows, nothing written).
    #[arg(long)]
    sweeps_only: bool,
    /// The periodic7 rows alone, printed (nothing written).
    #[arg(long)]
    paper_only: bool,
    /// Sizes of the per-gradient rows (links, at least 2).
    #[arg(long, value_delimiter = ',', default_values_t = [7, 20, 50], value_parser = cli::links)]
    gradient_sizes: Vec<usize>,
    /// Sizes of eq. (35)'s rows.
    #[arg(long, value_delimiter = ',', default_values_t = [5, 10, 20], value_parser = cli::links)]
    rise_sizes: Vec<usize>,
    /// Sizes of the per-design rows.
    #[arg(long, value_delimiter = ',', default_values_t = [7, 50], value_parser = cli::links)]
    design_sizes: Vec<usize>,
}

fn forcing() -> Forcing {
    Forcing::PulseTrain { period: 0.4, duty: 0.5, delay: 0.0 }
}

fn with_sensitivities(settings: &PeriodicDesignSettings, s: Sensitivities) -> PeriodicDesignSettings {
    let mut out = settings.clone();
    out.gradient.sensitivities = s;
    out
}

/// The per-gradient table's row for N links.
fn gradient_row(n: usize, sweeps_only: bool) -> Option<String> {
    let p = periodic_problem(n);
    let settings = PeriodicDesignSettings::default();
    let k = p.design.stiffness.clone();
    let periods = 3;
    let (plain, point) = fastest(|| eq37_values(&p, &forcing(), &k, -0.01, &settings, periods).expect("a run"));
    if sweeps_only {
        for _ in 0..20 {
            assert!(point.clone().constraint_gradients());
        }
        return None;
    }
    let (sweep, adjoint) = fastest(|| {
        let mut q = point.clone();
        assert!(q.constraint_gradients());
        q
    });
    let forward_settings = with_sensitivities(&settings, Sensitivities::Forward);
    let (forward_time, forward) =
        fastest(|| eq37_point(&p, &forcing(), &k, -0.01, &forward_settings, periods).expect("a run"));
    let scale = forward.minima[0].gradient.iter().fold(0.0f64, |m, g| m.max(g.abs()));
    let difference = adjoint
        .minima
        .iter()
        .zip(&forward.minima)
        .flat_map(|(a, f)| a.gradient.iter().zip(&f.gradient).map(|(x, y)| (x - y).abs()))
        .fold(0.0f64, f64::max)
        / scale;
    Some(format!(
        "| {n} | {} | {} | {plain:.4} | {sweep:.4} | {:.2} | {forward_time:.4} | {:.1} | {:.1} | {difference:.1e} |",
        k.len(),
        point.response.stats.accepted_steps,
        sweep / plain,
        forward_time / plain,
        forward_time / (plain + sweep),
    ))
}

/// Eq. (35)'s rise time alone, with its gradient by the adjoint and by forward sensitivities.
fn rise_row(n: usize) -> String {
    let p = spine_dynamics::fixtures::arch_problem(n, 30.0);
    let ends = p.static_ends(&Default::default()).expect("stable ends");
    let d = p.dynamics(Forcing::Step);
    let settings = spine_dynamic_design::DampingSettings::default().step;
    let (plain, _) = fastest(|| rise_time_by(&d, &ends, &settings, None));
    let (adjoint, (_, a)) = fastest(|| rise_time_by(&d, &ends, &settings, Some(Sensitivities::Adjoint)));
    let (forward, (_, f)) = fastest(|| rise_time_by(&d, &ends, &settings, Some(Sensitivities::Forward)));
    let (Some(a), Some(f)) = (a, f) else {
        return format!("| {n} | {} | no rise within the step settings' span | | | | | |", n + 1);
    };
    let scale = f.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let difference = a.iter().zip(&f).map(|(x, y)| (x - y).abs()).fold(0.0f64, f64::max) / scale;
    format!(
        "| {n} | {} | {plain:.4} | {adjoint:.4} | {:.2} | {forward:.4} | {:.1} | {difference:.1e} |",
        n + 1,
        adjoint / plain,
        forward / plain
    )
}

/// One eq. (37) design: wall time, status, Ipopt iterations (or GA generations), simulations,
/// adjoint sweeps and U.
fn design_row(p: &DynamicProblem, delta_d: f64, method: SearchMethod, settings: &PeriodicDesignSettings) -> String {
    let clock = Instant::now();
    let d = design_periodic(p, forcing(), delta_d, method, settings, &mut |_| {}).expect("a design");
    let time = clock.elapsed().as_secs_f64();
    let (what, iterations, sweeps) = match (&d.gradient, &d.search) {
        (Some(g), _) => (format!("gradient, {:?}", g.sensitivities).to_lowercase(), g.iterations, g.adjoint_sweeps),
        (None, Some(s)) => ("GA".to_string(), s.iterations, 0),
        _ => ("?".to_string(), 0, 0),
    };
    format!(
        "| {} | {what} | {time:.2} | {} | {iterations} | {} | {sweeps} | {:.6} | {:.1e} |",
        p.design.stiffness.len() - 1,
        d.status(),
        d.simulations,
        d.objective,
        d.relative_error
    )
}

/// `paper-cases/periodic7.json` (Fig. 10's setting) by the GA, by gradients with the adjoint and
/// by gradients with forward sensitivities, each through the one run path of the CLI, timed in
/// this run: the rows of the "same run" comparison.
fn paper_case_rows() -> String {
    let text = std::fs::read_to_string("paper-cases/periodic7.json").expect("paper-cases/periodic7.json");
    let mut out = String::from("\n### `paper-cases/periodic7.json` (Fig. 10's setting: 7 links, δ_d = −0.05 m), the whole run as `spine periodic` runs it\n\n| method | wall time (s) | U (J) | simulations |\n|---|---|---|---|\n");
    for (method, sensitivities) in [("ga", "adjoint"), ("gradient", "adjoint"), ("gradient", "forward")] {
        let mut value: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        value["periodic_design"]["method"] = method.into();
        value["periodic_design"]["settings"]["gradient"] = serde_json::json!({ "sensitivities": sensitivities });
        let case = spine_case::Case::from_json(&value.to_string()).expect("a valid case");
        let clock = Instant::now();
        let result =
            spine_run::run_case(&case, &Default::default(), &spine_run::NoRecipes, &mut |_| {}).expect("a run");
        let time = clock.elapsed().as_secs_f64();
        let json = result.to_json();
        let design = &json["periodic_design"];
        let name = if method == "ga" { "GA (two threads)".to_string() } else { format!("gradient, {sensitivities}") };
        let row = format!(
            "| {name} | {time:.2} | {:.6} | {} |",
            design["objective"].as_f64().unwrap_or(f64::NAN),
            design["simulations"]
        );
        println!("{row}");
        out.push_str(&row);
        out.push('\n');
    }
    out
}

fn main() {
    let args = <Args as clap::Parser>::parse();
    let sweeps_only = args.sweeps_only;
    if args.paper_only {
        paper_case_rows();
        return;
    }
    let mut text = format!("{SECTION}\n\nWritten by `just bench-gradients` (benchmarks/src/bin/dynamic_gradients.rs), one run on {} core(s) (rayon's pool). The periodic fixture chain (`periodic_problem(N)`: arch of amplitude 0.3 rad over 1 m, K = 2000 N·m/rad, 0.5 kg links, −20 N per node, −1500 N pulses of period 0.4 s and duty 0.5, dampers 20 N·m·s/rad), integrator rtol 1e-6 (eq. (37)'s default).\n\n", rayon::current_num_threads());
    text.push_str("### Per gradient (3 periods; fastest of 3)\n\nThe adjoint sweeps are the two constraint minima's, side by side on the pool; `sweeps / plain` is their wall time over the plain run's (the run the values need anyway).\n\n| N | springs | steps (3 periods) | plain run (s) | adjoint sweeps (s) | sweeps / plain | forward run (s) | forward / plain | forward / (plain + sweeps) | largest gradient difference (relative) |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for &n in &args.gradient_sizes {
        if let Some(row) = gradient_row(n, sweeps_only) {
            println!("{row}");
            text.push_str(&row);
            text.push('\n');
        }
    }
    if sweeps_only {
        return;
    }
    text.push_str("\n### Eq. (35)'s `dT_90/dC` per gradient (the 5-link-style arch of `arch_problem(N, 30)` under the step, run stopped at the rise; fastest of 3)\n\n| N | dampers | rise time, plain (s) | with the adjoint sweep (s) | adjoint / plain | with forward sensitivities (s) | forward / plain | largest gradient difference (relative) |\n|---|---|---|---|---|---|---|---|\n");
    for &n in &args.rise_sizes {
        let row = rise_row(n);
        println!("{row}");
        writeln!(text, "{row}").expect("string");
    }
    text.push_str("\n### Per design (eq. (37) from the uniform start that meets δ_d; δ_d = 1.2 × the start springs' minimum; one run each)\n\n| N | method | wall time (s) | status | iterations | simulations | adjoint sweeps | U (J) | relative error of the equality |\n|---|---|---|---|---|---|---|---|---|\n");
    for &n in &args.design_sizes {
        let p = periodic_problem(n);
        let settings = PeriodicDesignSettings::default();
        let start = periodic_response(&p, forcing(), None, &settings.response).expect("a start response");
        let delta_d = 1.2 * start.min_end_displacement;
        let mut times = Vec::new();
        for s in [Sensitivities::Adjoint, Sensitivities::Forward] {
            let mut settings = with_sensitivities(&settings, s);
            settings.gradient.start = GradientStart::Uniform;
            let clock = Instant::now();
            let row = design_row(&p, delta_d, SearchMethod::Gradient, &settings);
            times.push(clock.elapsed().as_secs_f64());
            println!("{row}");
            writeln!(text, "{row}").expect("string");
        }
        let row = design_row(&p, delta_d, SearchMethod::Ga, &settings);
        println!("{row}");
        writeln!(text, "{row}").expect("string");
        writeln!(text, "| {n} | forward / adjoint wall time | {:.1}× | | | | | | |", times[1] / times[0])
            .expect("string");
    }
    text.push_str(&paper_case_rows());
    let path = "benchmarks/DYNAMICS.md";
    let old = std::fs::read_to_string(path).unwrap_or_default();
    let kept = old.find(SECTION).map_or(old.as_str(), |i| &old[..i]).trim_end();
    let out = format!("{kept}\n\n{text}");
    let tmp = format!("{path}.tmp");
    std::fs::write(&tmp, out).expect("write");
    std::fs::rename(&tmp, path).expect("rename");
    eprintln!("wrote {path}");
}
