//! `spine`: run flexible-spine case files.
//!
//! Exit codes: 0 success; 2 bad input (nothing written); 3 the run finished but its result is not a
//! stable, converged equilibrium (the result is still written, with its status); 1 any other
//! failure (for example the output folder cannot be written).

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

mod design;
mod dynamics;
mod equilibrium;
mod figure;
mod output;
mod twolink;

#[derive(Parser)]
#[command(name = "spine", version, about = "Design and analysis of flexible spines (planar link chains with torsional springs)")]
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
}

#[derive(clap::Args)]
struct PeriodicArgs {
    #[command(flatten)]
    run: RunArgs,
    /// Search for eq. (37): `ga` (genetic algorithm) or `pattern` (pattern search); default: the case file's.
    #[arg(long, value_parser = ["ga", "pattern"])]
    method: Option<String>,
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
    /// Runs any case file by its `kind`.
    Case(RunArgs),
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut overrides = design::Overrides::default();
    let mut method = None;
    let (args, expect) = match &cli.command {
        Command::Equilibrium(a) => (a, Some("equilibrium")),
        Command::Twolink(a) => (a, Some("twolink")),
        Command::Design(a) => {
            overrides = design::Overrides {
                formulation: a.formulation.as_deref().map(|f| if f == "reduced" { spine_design::Formulation::Reduced } else { spine_design::Formulation::Full }),
                starts: a.starts,
                seed: a.seed,
            };
            (&a.run, Some("design"))
        }
        Command::Simulate(a) => (a, Some("simulate")),
        Command::Damping(a) => (a, Some("damping")),
        Command::Periodic(a) => {
            method = a.method.as_deref().map(|m| if m == "pattern" { spine_dynamics::SearchMethod::Pattern } else { spine_dynamics::SearchMethod::Ga });
            (&a.run, Some("periodic"))
        }
        Command::Case(a) => (a, None),
    };
    match run(args, expect, overrides, method) {
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
