//! `spine`: run flexible-spine case files.
//!
//! Exit codes: 0 success; 2 bad input (nothing written); 3 the run finished but its result is not a
//! stable, converged equilibrium (the result is still written, with its status); 1 any other
//! failure (for example the output folder cannot be written).
#![forbid(unsafe_code)]

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

mod design;
mod dynamics;
mod equilibrium;
mod figure;
mod output;
mod study;
mod twolink;

#[derive(Parser)]
#[command(
    name = "spine",
    version,
    about = "Design and analysis of flexible spines (planar link chains with torsional springs)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct RunArgs {
    /// The case file (JSON).
    case: PathBuf,
    /// Output folder; `result.json` is written there.
    #[arg(long, default_value = "results")]
    out: PathBuf,
    /// Leave timings out of `result.json`, so the same input gives the same bytes.
    #[arg(long)]
    deterministic: bool,
}

#[derive(clap::Args)]
struct DesignArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Formulation of eq. (33): `full` (simultaneous, exact sparse Hessian) or `reduced`
    /// (equilibria by continuation, adjoint gradients); default: the case file's.
    #[arg(long, value_parser = ["full", "reduced"])]
    formulation: Option<String>,
    /// Extra seeded feasible starts (multi-start); default: the case file's.
    #[arg(long)]
    starts: Option<usize>,
    /// Seed of the multi-start; default: the case file's.
    #[arg(long)]
    seed: Option<u64>,
    /// Mesh sequencing of the full space: `off`, `auto` (from 100 links: 50, 100, 200, … links),
    /// `FROM` or `FROM:FACTOR`; default: the case file's `solver.refine`.
    #[arg(long)]
    refine: Option<spine_design::refine::Refine>,
}

#[derive(clap::Args)]
struct PeriodicArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Search for eq. (37): `ga` (genetic algorithm) or `pattern` (pattern search); default: the case file's.
    #[arg(long, value_parser = ["ga", "pattern"])]
    method: Option<String>,
}

#[derive(clap::Args)]
struct StudyArgs {
    /// The study: `ck` (eq. (34): C_K over half-decades, Ipopt scaling on and off).
    #[arg(value_parser = ["ck"])]
    study: String,
    #[command(flatten)]
    run: RunArgs,
    /// The C_K values; default 1 to 10⁴ in half-decades.
    #[arg(long, value_delimiter = ',')]
    values: Option<Vec<f64>>,
}

#[derive(clap::Args)]
struct ReportArgs {
    /// The results folder: one sub-folder per case with its `result.json`.
    #[arg(long, default_value = "results")]
    results: PathBuf,
    /// The cases in reading order (names of sub-folders).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "twolink,fig3,fig4,fig5,fig6,fig7,fig8,fig9,fig10,fig11,fig12,study-ck"
    )]
    cases: Vec<String>,
    /// The errata table to include.
    #[arg(long, default_value = "docs/errata.md")]
    errata: PathBuf,
}

#[derive(Subcommand)]
enum Command {
    /// Passive (θ1) and loaded (θ2) equilibria of a given design, with stability.
    Equilibrium(RunArgs),
    /// The two-link analysis of Sec. 3: closed forms beside the exact solution.
    Twolink(RunArgs),
    /// The static design problem of eq. (33) with Ipopt (optionally multi-start).
    Design(DesignArgs),
    /// Step or periodic response (Sec. 5.2): `response.csv` and `result.json` with T_90, Δ∞, τ, fit error, drift.
    Simulate(RunArgs),
    /// The damping design of eq. (35): dampers for each target rise time.
    Damping(RunArgs),
    /// The periodic-load design of eq. (37) by a genetic algorithm or a pattern search.
    Periodic(PeriodicArgs),
    /// Runs any case file by its `kind` (a `figure` case: its runs, plots, tables and checked claims).
    Case(RunArgs),
    /// A parameter study on a design case (`ck`: the C_K study of eq. (34)).
    Study(StudyArgs),
    /// Gathers the figures' results into `RESULTS/REPORT.md`.
    Report(ReportArgs),
}

/// How a command ended.
pub enum Outcome {
    Success,
    NotConverged,
}

/// An error with its exit code.
pub enum Failure {
    Input(String),
    Other(String),
}

fn exit(result: Result<Outcome, Failure>) -> ExitCode {
    match result {
        Ok(Outcome::Success) => ExitCode::SUCCESS,
        Ok(Outcome::NotConverged) => ExitCode::from(3),
        Err(Failure::Input(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
        Err(Failure::Other(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(1)
        }
    }
}

fn study(a: &StudyArgs) -> Result<Outcome, Failure> {
    let path = a.run.case.display().to_string();
    let text = std::fs::read_to_string(&a.run.case).map_err(|e| Failure::Input(format!("{path}: cannot read: {e}")))?;
    let case = spine_case::Case::from_json(&text).map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    let spine_case::Case::Design(c) = case else {
        return Err(Failure::Input(format!(
            "{path}: kind: the C_K study runs a \"design\" case, the file is \"{}\"",
            case.kind()
        )));
    };
    let valid = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    let values = a.values.clone().unwrap_or_else(spine_paper::study::half_decades);
    if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(Failure::Input(format!("--values: every C_K must be finite and > 0, got {v}")));
    }
    study::run(&c, &valid, &values, &output::Output::new(&a.run.out, a.run.deterministic))
}

fn report(a: &ReportArgs) -> Result<Outcome, Failure> {
    let errata = std::fs::read_to_string(&a.errata)
        .map_err(|e| Failure::Input(format!("{}: cannot read: {e}", a.errata.display())))?;
    let mut results = Vec::new();
    let mut missing = Vec::new();
    for name in &a.cases {
        let file = a.results.join(name).join("result.json");
        match std::fs::read_to_string(&file).ok().and_then(|t| serde_json::from_str(&t).ok()) {
            Some(value) => results.push(spine_paper::report::CaseResult { name: name.clone(), value }),
            None => missing.push(name.clone()),
        }
    }
    let text = spine_paper::report::report(&results, &errata, &missing);
    output::Output::new(&a.results, false).write_text("REPORT.md", &text)?;
    println!("wrote {} ({} cases, {} missing)", a.results.join("REPORT.md").display(), results.len(), missing.len());
    Ok(if missing.is_empty() { Outcome::Success } else { Outcome::NotConverged })
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut overrides = design::Overrides::default();
    let mut method = None;
    let (args, expect) = match &cli.command {
        Command::Equilibrium(a) => (a, Some("equilibrium")),
        Command::Twolink(a) => (a, Some("twolink")),
        Command::Design(a) => {
            overrides = design::Overrides {
                formulation: a.formulation.as_deref().map(|f| {
                    if f == "reduced" {
                        spine_design::Formulation::Reduced
                    } else {
                        spine_design::Formulation::Full
                    }
                }),
                starts: a.starts,
                seed: a.seed,
                refine: a.refine,
            };
            (&a.run, Some("design"))
        }
        Command::Simulate(a) => (a, Some("simulate")),
        Command::Damping(a) => (a, Some("damping")),
        Command::Periodic(a) => {
            method = a.method.as_deref().map(|m| {
                if m == "pattern" {
                    spine_dynamics::SearchMethod::Pattern
                } else {
                    spine_dynamics::SearchMethod::Ga
                }
            });
            (&a.run, Some("periodic"))
        }
        Command::Case(a) => (a, None),
        Command::Study(a) => return exit(study(a)),
        Command::Report(a) => return exit(report(a)),
    };
    exit(run(args, expect, overrides, method))
}

fn run(
    args: &RunArgs,
    expect: Option<&str>,
    overrides: design::Overrides,
    method: Option<spine_dynamics::SearchMethod>,
) -> Result<Outcome, Failure> {
    let path = args.case.display().to_string();
    let text = std::fs::read_to_string(&args.case).map_err(|e| Failure::Input(format!("{path}: cannot read: {e}")))?;
    let case = spine_case::Case::from_json(&text).map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    if let Some(kind) = expect {
        if case.kind() != kind {
            return Err(Failure::Input(format!(
                "{path}: kind: this command runs \"{kind}\" cases, the file is \"{}\" (use `spine case`)",
                case.kind()
            )));
        }
    }
    let out = output::Output::new(&args.out, args.deterministic);
    let case_kind = case.kind();
    match case {
        spine_case::Case::Equilibrium(c) => {
            let valid = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            equilibrium::run(&c, &valid, &out)
        }
        spine_case::Case::Twolink(c) => {
            let valid = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            twolink::run(&c, &valid, &out)
        }
        spine_case::Case::Design(c) => {
            let valid = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            design::run(&c, &valid, overrides, &out)
        }
        spine_case::Case::Simulate(c) | spine_case::Case::Damping(c) | spine_case::Case::Periodic(c) => {
            let kind = expect.unwrap_or(case_kind);
            let valid = c.validate(kind).map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            dynamics::run(&c, &valid, kind, method, &out)
        }
        spine_case::Case::Figure(c) => {
            let runs = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            figure::run(&c, &runs, &out)
        }
    }
}
