//! `spine`: run flexible-spine case files.
//!
//! Exit codes: 0 success; 2 bad input (nothing written); 3 the run finished but its result is not
//! clean — not a stable, converged equilibrium, a failed solver check, or stopped by
//! `--time-limit` (the result is still written, with its status; a time limit that left nothing
//! to report writes nothing); 130 interrupted (nothing written); 1 any other failure (for example the output folder cannot be
//! written). The command only parses arguments, calls `spine_run::run_case` and prints.
//!
//! Modules:
//!
//! * `args`: The command line: subcommands, their arguments, and the overrides they make to a case.
//! * `output`: Printing to stdout without a panic when the reader has gone (`spine … | head`), and
//!   the result folder through `spine_run::write` with its errors as exit codes.
//! * `parse`: The values of the command-line options: the text parsed, then checked by the same
//!   function that checks flexspine's keyword arguments (`spine_run::option_values`); clap prints
//!   the message with the option's name (exit code 2).
//! * `progress`: Progress of a long run on the terminal (stderr): one bar per stage, finished lines
//!   printed.
//! * `quotes`: `spine quotes`: the numbers the docs quote from the paper cases' runs, written from
//!   the results folder, or compared with it (`--check`, exit 3 on a drift).
//! * `report`: `spine report`: the figures' results gathered into `RESULTS/REPORT.md`, the
//!   self-contained `RESULTS/report.html` and the counts in `RESULTS/report.json`.
//! * `workers`: The worker processes of a run's multi-starts: `--jobs N`, this program started
//!   again as `spine worker`.
#![forbid(unsafe_code)]

mod args;
mod output;
mod parse;
mod progress;
mod quotes;
mod report;
mod workers;

use args::{Cli, Command, RunArgs};
use clap::Parser;
use std::process::ExitCode;

/// mimalloc for Rust's allocations; its `override` feature also makes it the process's `malloc`,
/// for Ipopt, MUMPS and our linear solver's shim (Cargo.toml says why).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// An error with its exit code: bad input (2), a time limit that left nothing to write (3),
/// interrupted (130) or any other failure (1).
pub enum Failure {
    Input(String),
    Other(String),
    /// The run ended without a clean result and nothing to write (its time limit passed first, or
    /// the eq. (33) design it rests on did not end clean): exit code 3.
    TimeLimit(String),
    Interrupted,
}

/// Seconds a run has after Ctrl-C or SIGTERM to stop at its own next check (Ipopt's iteration,
/// the next start) before the process exits anyway; output is staged, so exiting writes nothing.
const GRACE_SECONDS: u64 = 3;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if matches!(e.kind(), clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) if e.kind() == clap::error::ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            eprintln!("error: a command is needed: spine equilibrium|twolink|design|merge|simulate|damping|periodic|case|study|sensitivity|sweep|report|quotes … (see --help)");
            return ExitCode::from(2);
        }
        // One line a person can act on (clap's first line, the value shortened and escaped),
        // not the usage block.
        Err(e) => {
            let text = e.render().to_string();
            let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("error: bad arguments");
            let first = first.strip_prefix("error: ").unwrap_or(first);
            eprintln!("error: {} (see --help)", spine_check::shown_within(first, 300));
            return ExitCode::from(2);
        }
    };
    let _ = ctrlc::set_handler(|| {
        spine_stop::request_interrupt();
        std::thread::sleep(std::time::Duration::from_secs(GRACE_SECONDS));
        eprintln!("error: interrupted: nothing written");
        std::process::exit(130);
    });
    let done = match &cli.command {
        Command::Equilibrium(a) => run(a, Some("equilibrium"), Default::default(), Mode::Case),
        Command::Twolink(a) => run(a, Some("twolink"), Default::default(), Mode::Case),
        Command::Design(a) if a.check => a.overrides().and_then(|o| check_design(&a.run, o, a.shard, a.batch)),
        Command::Design(a) => a.overrides().and_then(|o| match (a.shard, a.batch) {
            (Some(spec), batch) => shard(&a.run, o, spec, batch),
            (None, Some(_)) => Err(Failure::Input(BATCH_WITHOUT_SHARD.into())),
            (None, None) => run(&a.run, Some("design"), o, Mode::Case),
        }),
        Command::Merge(a) => merge(a),
        Command::Simulate(a) => run(&a.run, Some("simulate"), a.overrides(), Mode::Case),
        Command::Damping(a) => run(&a.run, Some("damping"), a.overrides(), Mode::Case),
        Command::Periodic(a) => run(&a.run, Some("periodic"), a.overrides(), Mode::Case),
        Command::Case(a) => a.overrides().and_then(|o| run(&a.dynamic.run, None, o, Mode::Case)),
        Command::Study(a) => a.values().and_then(|v| run(&a.run, None, a.overrides()?, Mode::Study(v))),
        Command::Sensitivity(a) => run(&a.run, None, a.overrides(), Mode::Sensitivity(&a.params)),
        Command::Sweep(a) => run(&a.run, Some("design"), a.overrides(), Mode::Sweep(a)),
        Command::Report(a) => report::run(a),
        Command::Quotes(a) => quotes::run(a),
        Command::Worker(a) => worker(a),
    };
    match done {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(3),
        Err(Failure::Input(msg)) => {
            eprintln!("error: {}", one_line(&msg));
            ExitCode::from(2)
        }
        Err(Failure::Other(msg)) => {
            eprintln!("error: {}", one_line(&msg));
            ExitCode::from(1)
        }
        Err(Failure::TimeLimit(msg)) => {
            eprintln!("error: {}", one_line(&msg));
            ExitCode::from(3)
        }
        Err(Failure::Interrupted) => {
            eprintln!("error: interrupted: nothing written");
            ExitCode::from(130)
        }
    }
}

/// An error message on one line a terminal shows as written: control characters escaped, at
/// most 1000 characters (every message is built to be shorter; this is the last guard).
fn one_line(msg: &str) -> String {
    spine_check::shown_within(&spine_check::short_numbers(msg.trim_end()), 1000)
}

/// Reads and parses a case file (refusing an oversized one before reading it): its text and case.
fn read_case(file: &std::path::Path) -> Result<(String, spine_case::Case), Failure> {
    let path = spine_check::shown_within(&file.display().to_string(), 200);
    let text = spine_case::read_text(file, "case file", spine_case::MAX_CASE_BYTES)
        .map_err(|e| Failure::Input(e.to_string()))?;
    let case = spine_case::Case::from_json(&text).map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    Ok((text, case))
}

/// `--batch` given without `--shard`.
const BATCH_WITHOUT_SHARD: &str =
    "--batch: only with --shard K/N (one shard of one batch of a census to a stated confidence)";

/// A design run's case path, its checked `--out` folder and the case file's text (a shard carries
/// it verbatim), in that order: the output folder is checked before any work.
fn shard_input(args: &RunArgs) -> Result<(String, output::Output, String), Failure> {
    let out = output::Output::new(&args.out, args.deterministic);
    out.check(&[&args.case])?;
    let (text, _) = read_case(&args.case)?;
    Ok((args.case.display().to_string(), out, text))
}

/// `spine design --check`: what the run (or the shard, with `--shard`) would check before its
/// first solve, and nothing more; prints what it would run.
fn check_design(
    args: &RunArgs,
    overrides: spine_run::Overrides,
    spec: Option<spine_run::shard::ShardSpec>,
    batch: Option<usize>,
) -> Result<bool, Failure> {
    let (path, _, text) = shard_input(args)?;
    let what = match (spec, batch) {
        (Some(spec), batch) => {
            let starts =
                spine_run::shard::check_shard(&text, &overrides.design, spec, batch).map_err(|e| failure(&path, e))?;
            let of = batch.map(|b| format!(" of batch {b}")).unwrap_or_default();
            format!("shard {}/{}{of} would solve {starts} start(s)", spec.index, spec.count)
        }
        (None, Some(_)) => return Err(Failure::Input(BATCH_WITHOUT_SHARD.into())),
        (None, None) => {
            spine_run::shard::check_design(&text, &overrides.design).map_err(|e| failure(&path, e))?;
            "it would run".to_string()
        }
    };
    output::say(&format!("checked {path}: a design case; {what}; nothing written\n"));
    Ok(true)
}

/// `spine design --shard K/N`: the K-th share of a multi-start's starts, written to
/// `DIR/shard.json` (exit 3 when a time limit left it incomplete: `spine merge` refuses it).
fn shard(
    args: &RunArgs,
    overrides: spine_run::Overrides,
    spec: spine_run::shard::ShardSpec,
    batch: Option<usize>,
) -> Result<bool, Failure> {
    let (path, out, text) = shard_input(args)?;
    let mut bars = progress::Bars::default();
    let (shard, _) = spine_stop::with_time_limit(args.time_limit, || {
        spine_run::shard::run_shard(&text, &overrides.design, spec, batch, overrides.workers.as_ref(), &mut |p| {
            bars.report(p)
        })
    });
    bars.clear();
    let shard = shard.map_err(|e| failure(&path, e))?;
    let json = serde_json::to_string(&shard).expect("shards serialise") + "\n";
    out.write_files(&[("shard.json", json.as_bytes())])?;
    output::say(&format!(
        "shard {}/{}{}: {} runs{}; wrote {}\n",
        spec.index,
        spec.count,
        batch.map(|b| format!(" of batch {b}")).unwrap_or_default(),
        shard.runs.len(),
        if shard.complete { "" } else { " (INCOMPLETE: stopped early; merge will refuse it)" },
        args.out.join("shard.json").display()
    ));
    Ok(shard.complete)
}

/// `spine merge DIR…`: the shards' runs checked and combined into the single run's result.
fn merge(a: &args::MergeArgs) -> Result<bool, Failure> {
    let files: Vec<_> = a.shards.iter().map(|d| if d.is_dir() { d.join("shard.json") } else { d.clone() }).collect();
    let out = output::Output::new(&a.out, a.deterministic);
    out.check(&files.iter().map(|f| f.as_path()).collect::<Vec<_>>())?;
    let mut shards = Vec::new();
    for file in &files {
        let name = spine_check::shown_within(&file.display().to_string(), 200);
        let text = spine_case::read_text(file, "shard", spine_run::shard::MAX_SHARD_BYTES)
            .map_err(|e| Failure::Input(e.to_string()))?;
        let shard = spine_run::shard::Shard::from_text(&text)
            .map_err(|e| Failure::Input(format!("{name}: not a shard: {e}")))?;
        shards.push(shard);
    }
    let merged = spine_run::shard::merge(shards).map_err(|e| failure("merge", e))?;
    let (path, _) = out.write_result(&merged.result)?;
    output::say(&format!("{}wrote {}\n", merged.result, path.display()));
    if !merged.unused_batches.is_empty() {
        output::say(&format!(
            "NOTE: the census reached its target before batch {}: not merged (the single run would not have run them)\n",
            spine_run::text::joined(&merged.unused_batches)
        ));
    }
    if let Some(b) = merged.next_batch {
        // One line a driver reads (scripts/slurm/census.sh): the census goes on with batch b.
        output::say(&format!("next batch: {b}\n"));
    }
    Ok(merged.result.is_clean())
}

/// A run's error as its exit code.
fn failure(path: &str, e: spine_run::RunError) -> Failure {
    if e.is_interrupted() {
        Failure::Interrupted
    } else if e.is_time_limit() || e.is_not_clean() {
        Failure::TimeLimit(format!("{path}: {e}"))
    } else if e.is_input() {
        Failure::Input(format!("{path}: {e}"))
    } else {
        Failure::Other(format!("{path}: {e}"))
    }
}

/// `spine worker`: a worker process of `spine design --jobs N`, answering start designs on its
/// standard input until it closes.
fn worker(a: &args::WorkerArgs) -> Result<bool, Failure> {
    let path = a.case.display().to_string();
    let (_, case) = read_case(&a.case)?;
    let case = match (case, &a.run) {
        (case, None) => case,
        (spine_case::Case::Figure(f), Some(name)) => {
            let runs = f.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
            let run = runs.into_iter().find(|r| &r.name == name);
            run.ok_or_else(|| Failure::Input(format!("{path}: --run: the figure has no run {name:?}")))?.case
        }
        (_, Some(_)) => return Err(Failure::Input(format!("{path}: --run: only a figure case has runs"))),
    };
    let spine_case::Case::Design(c) = case else {
        return Err(Failure::Input(format!(
            "{path}: kind: a worker solves \"design\" cases (or a figure's design run)"
        )));
    };
    let overrides: spine_run::DesignOverrides =
        serde_json::from_str(&a.overrides).map_err(|e| Failure::Input(format!("--overrides: {e}")))?;
    let mut valid = c.validate().map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    overrides.apply(&mut valid).map_err(|e| Failure::Input(format!("{path}: {e}")))?;
    let (input, output) = (std::io::stdin().lock(), std::io::stdout().lock());
    spine_run::workers::serve(&valid, input, output).map_err(|e| Failure::Other(format!("worker: {e}")))?;
    Ok(true)
}

/// What [`run`] does with the case.
enum Mode<'a> {
    /// Runs it by its kind.
    Case,
    /// The C_K study over these values.
    Study(Vec<f64>),
    /// The sensitivities of its optimum to these parameters (empty: all).
    Sensitivity(&'a [String]),
    /// The optimum followed along a parameter.
    Sweep(&'a args::SweepArgs),
}

/// Reads and runs one case (of kind `expect` when given) as `mode` says, writes its results and
/// prints its summary. `Ok(clean)`.
fn run(
    args: &RunArgs,
    expect: Option<&str>,
    mut overrides: spine_run::Overrides,
    mode: Mode<'_>,
) -> Result<bool, Failure> {
    overrides.time_limit = args.time_limit;
    let path = args.case.display().to_string();
    let out = output::Output::new(&args.out, args.deterministic);
    out.check(&[&args.case])?;
    let (_, case) = read_case(&args.case)?;
    if let Some(kind) = expect.filter(|k| *k != case.kind()) {
        let msg = format!(
            "{path}: kind: this command runs \"{kind}\" cases, the file is \"{}\" (use `spine case`)",
            case.kind()
        );
        return Err(Failure::Input(msg));
    }
    let mut bars = progress::Bars::default();
    let result = match &mode {
        Mode::Study(values) => spine_run::run_study(&case, &overrides, values, &mut |p| bars.report(p)),
        Mode::Sensitivity(names) => spine_run::run_sensitivity(&case, &overrides, names, &mut |p| bars.report(p)),
        Mode::Sweep(a) => {
            spine_run::run_sweep(&case, &overrides, &a.param, a.settings(), a.census(), &mut |p| bars.report(p))
        }
        Mode::Case => spine_run::run_case(&case, &overrides, &spine_paper::PaperFigures, &mut |p| bars.report(p)),
    };
    bars.clear();
    let result = result.map_err(|e| failure(&path, e))?;
    if spine_stop::interrupt_requested() {
        return Err(Failure::Interrupted);
    }
    let (path, files) = out.write_result(&result)?;
    let beside = match files {
        0 => String::new(),
        1 => " and 1 file beside it".to_string(),
        n => format!(" and {n} files beside it"),
    };
    output::say(&format!("{result}wrote {}{beside}\n", path.display()));
    // Why it exits 3, where the result says so in a field of its own (`not_clean`).
    for reason in result.result.not_clean_reasons() {
        eprintln!("not clean: {}", one_line(&reason));
    }
    Ok(result.is_clean())
}
