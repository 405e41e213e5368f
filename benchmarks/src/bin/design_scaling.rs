//! `just bench-design`: eq. (33) on the scaled family of `docs/PEERS.md` for growing N, full
//! space and (where affordable) reduced space: Ipopt status, iterations, wall time, time per
//! iteration and the optimum J. Each configuration runs `REPEATS` times and reports the fastest
//! (machines here are shared and noisy).
//!
//! Usage: `design_scaling [--refine=off|auto|FROM[:FACTOR]] [--springs=auto|log|linear] [--repeats=R] [--peers] [N ...]`
//! (default N: 5 10 20 50 100 200 500 1000; default refine: the solver's default, "auto"; FROM: a
//! ladder from FROM links, factor FACTOR or 2). `--peers` solves `bench_peers`' case files instead
//! (its tolerances, 1e-8 and 1e-9 s²), with its ladder under `--refine=auto`; the full space only. `--ipopt=NAME=VALUE`
//! (repeatable) adds an Ipopt option to every solve, as the case file's `solver.ipopt_options`;
//! `--warm=FIELD=VALUE` (repeatable) sets a field of `solver.warm_start` (a JSON value: a number,
//! true/false, null, or an object such as `--warm='barrier={"mu":3e-3,"exponent":2}'`);
//! `--springs=auto|log|linear` sets `solver.spring_variables`.
//!
//! With a ladder, each N also reports its work in iterations of the finest level's size (`Σ m ·
//! iterations(m) / N` over the levels of `m` links) and its longest level from 400 links, and a
//! run over several sizes sums them up: the levels' iteration counts are a chaotic function of
//! rounding (benchmarks/analysis.md), so options are compared on that sum over many sizes.
#![forbid(unsafe_code)]

use spine_benchmarks::{cli, peers};
use spine_design::fixtures::{arch_start, scaled_family};
use spine_design::refine::{Refine, RefineMode, WarmStart};
use spine_design::settings::ExtraOption;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{Formulation, SolverSettings};

/// Largest N for the reduced space: its finite-difference Hessian costs 2(2N + 1) equilibrium
/// solves per iteration and a dense (2N + 1)² block.
const REDUCED_MAX_N: usize = 100;

/// Eq. (33)'s scaling table (full and reduced space) on the scaled family.
#[derive(clap::Parser)]
struct Args {
    /// Mesh sequencing: `off`, `auto` or `FROM[:FACTOR]`.
    #[arg(long, value_parser = |text: &str| text.parse::<Refine>().map_err(|e| e.to_string()))]
    refine: Option<Refine>,
    /// The springs as Ipopt sees them: auto, log or linear.
    #[arg(long, value_parser = springs)]
    springs: Option<spine_design::settings::SpringVariables>,
    /// Timed solves per size (at least 1).
    #[arg(long, default_value_t = 3, value_parser = cli::runs)]
    repeats: usize,
    /// The peers' cases (benchmarks/peers) instead of the scaled family's arch start.
    #[arg(long = "peers")]
    peers_cases: bool,
    /// An Ipopt option NAME=VALUE (a number or a string), repeatable.
    #[arg(long = "ipopt", value_parser = ipopt_option)]
    extra: Vec<(String, ExtraOption)>,
    /// A field of `solver.warm_start` FIELD=VALUE (JSON), repeatable.
    #[arg(long = "warm", value_parser = warm_field)]
    warm: Vec<(String, serde_json::Value)>,
    /// Chain sizes (links, at least 2); 5 to 1000 when none is given.
    #[arg(value_parser = cli::links)]
    sizes: Vec<usize>,
}

fn springs(form: &str) -> Result<spine_design::settings::SpringVariables, String> {
    serde_json::from_value(serde_json::json!(form)).map_err(|_| format!("auto, log or linear, got {form:?}"))
}

fn ipopt_option(option: &str) -> Result<(String, ExtraOption), String> {
    let (name, value) = cli::name_value(option, "--ipopt")?;
    let number = value.parse().map(ExtraOption::Int).or_else(|_| value.parse().map(ExtraOption::Num));
    Ok((name.to_string(), number.unwrap_or_else(|_| ExtraOption::Str(value.to_string()))))
}

fn warm_field(field: &str) -> Result<(String, serde_json::Value), String> {
    let (name, text) = cli::name_value(field, "--warm")?;
    let value = serde_json::from_str(text).map_err(|_| {
        format!("{name}: the value must be JSON (a number, true/false, null or an object), got {text:?}")
    })?;
    let pair = (name.to_string(), value);
    with_warm(SolverSettings::default().warm_start, std::slice::from_ref(&pair))?;
    Ok(pair)
}

/// `warm_start` with the `--warm` fields set, or which field or value is not allowed.
fn with_warm(warm_start: WarmStart, fields: &[(String, serde_json::Value)]) -> Result<WarmStart, String> {
    let mut value = serde_json::to_value(warm_start).map_err(|e| e.to_string())?;
    for (name, field) in fields {
        let Some(slot) = value.get_mut(name) else {
            let names: Vec<&String> = value.as_object().map(|o| o.keys().collect()).unwrap_or_default();
            return Err(format!("--warm: solver.warm_start has no field {name:?} (allowed: {names:?})"));
        };
        *slot = field.clone();
    }
    serde_json::from_value(value).map_err(|e| format!("--warm: {e}"))
}

fn main() {
    let Args { refine, springs, repeats, peers_cases, extra, warm, sizes } = <Args as clap::Parser>::parse();
    let mut settings = SolverSettings::default();
    if let Some(refine) = refine {
        settings.refine = refine;
    }
    let sizes = if sizes.is_empty() { vec![5, 10, 20, 50, 100, 200, 500, 1000] } else { sizes };
    let mut ladders: Vec<(usize, LadderWork)> = Vec::new();
    println!("| N | formulation | status | iterations | wall time (s) | time per iteration (ms) | J (J) | clean |");
    println!("|---|---|---|---|---|---|---|---|");
    for &n in &sizes {
        let (problem, start, settings) = if peers_cases {
            let valid = peers::scaled_family_design(n);
            let mut case_settings = valid.settings.clone();
            case_settings.refine = match settings.refine {
                Refine::Mode(RefineMode::Auto) => {
                    peers::bench_ladder(n).map_or(Refine::Mode(RefineMode::Off), Refine::Ladder)
                }
                other => other,
            };
            (valid.problem, valid.start, case_settings)
        } else {
            let s = n as f64 / 10.0;
            (scaled_family(n), arch_start(n, 0.3, 1e3 * s * s), settings.clone())
        };
        let mut settings = settings;
        if let Some(springs) = springs {
            settings.spring_variables = springs;
        }
        settings.ipopt_options.extend(extra.iter().cloned());
        settings.warm_start = with_warm(settings.warm_start, &warm)
            .unwrap_or_else(|message| cli::usage_error(message, "design_scaling --help"));
        for formulation in [Formulation::Full, Formulation::Reduced] {
            if peers_cases && formulation == Formulation::Reduced {
                continue;
            }
            if formulation == Formulation::Reduced && n > REDUCED_MAX_N {
                println!("| {n} | reduced | skipped (N > {REDUCED_MAX_N}) | | | | | |");
                continue;
            }
            let mut best: Option<(f64, spine_design::DesignResult)> = None;
            for _ in 0..repeats {
                let clock = std::time::Instant::now();
                let r = Solver::new(SolverPreset::Exact, formulation, &settings)
                    .solve(&problem, &start, &mut |_| true)
                    .unwrap_or_else(|e| {
                        eprintln!("error: N = {n}: {e}");
                        std::process::exit(1)
                    });
                let t = clock.elapsed().as_secs_f64();
                if best.as_ref().is_none_or(|(bt, _)| t < *bt) {
                    best = Some((t, r));
                }
            }
            let (t, r) = best.expect("at least one repeat");
            let per_iteration = 1e3 * r.solver.ipopt_seconds / r.solver.iterations.max(1) as f64;
            if let Some(refinement) = &r.refinement {
                for l in &refinement.levels {
                    eprintln!(
                        "  N = {n} level {}: {:?} {} after {} iterations ({} restarts), J = {:.9e}, {:.3} s (start {:.3} s)",
                        l.links, l.start, l.status, l.iterations, l.restarts, l.objective, l.wall_seconds, l.start_seconds
                    );
                }
                let work = LadderWork::of(n, refinement.levels.iter().map(|l| (l.links, l.iterations)));
                eprintln!(
                    "  N = {n} ladder work: {:.0} iterations of the finest level's size (sum of links x iterations / N), longest level from {LONG_LEVEL_FROM} links {} iterations",
                    work.finest_equivalent, work.longest
                );
                ladders.push((n, work));
            }
            if let Some(c) = &r.certificate {
                eprintln!(
                    "  N = {n} certificate: {:?}, {} free, {} active rows, {} weakly active, inertia {:?}",
                    c.status, c.free_variables, c.active_rows, c.weakly_active, c.reduced_kkt_inertia
                );
            }
            for e in &r.escapes {
                eprintln!(
                    "  N = {n} left J = {:.9e} ({:?}) by {} to J = {:.9e}",
                    e.objective,
                    e.status,
                    e.how.name(),
                    e.reached
                );
            }
            println!(
                "| {n} | {} | {} | {} | {t:.4} | {per_iteration:.3} | {:.9e} | {} |",
                formulation.name(),
                r.solver.status,
                r.solver.iterations,
                r.objective,
                if r.is_clean() { "yes" } else { "no" }
            );
        }
    }
    if ladders.len() > 1 {
        let mut works: Vec<f64> = ladders.iter().map(|(_, w)| w.finest_equivalent).collect();
        works.sort_by(f64::total_cmp);
        let (n_longest, longest) =
            ladders.iter().map(|(n, w)| (*n, w.longest)).max_by_key(|&(_, l)| l).expect("two or more ladders");
        eprintln!(
            "ladder work over {} sizes: total {:.0}, median {:.0}, largest {:.0}; longest level from {LONG_LEVEL_FROM} links {longest} iterations (N = {n_longest})",
            ladders.len(),
            works.iter().sum::<f64>(),
            works[works.len() / 2],
            works[works.len() - 1]
        );
    }
}

/// Levels from this many links count for [`LadderWork::longest`] (issue 50's table: no level of
/// any N in 500 … 10⁴ above 150 iterations).
const LONG_LEVEL_FROM: usize = 400;

/// What a ladder cost, in a unit that does not depend on the machine's speed: an iteration of a
/// level of `m` links costs about `m / N` of the finest level's (every part of an iteration is
/// O(m)). The iteration counts of the scaled family's levels are a chaotic function of rounding
/// (benchmarks/analysis.md), so an Ipopt option or a change of path is judged on this sum over
/// many sizes, not on one N.
struct LadderWork {
    /// `Σ m · iterations(m) / N` over the levels.
    finest_equivalent: f64,
    /// The most iterations of a level of at least [`LONG_LEVEL_FROM`] links.
    longest: usize,
}

impl LadderWork {
    /// From each level's links and iterations.
    fn of(n: usize, levels: impl Iterator<Item = (usize, usize)> + Clone) -> Self {
        LadderWork {
            finest_equivalent: levels.clone().map(|(m, its)| (m * its) as f64).sum::<f64>() / n as f64,
            longest: levels.filter(|&(m, _)| m >= LONG_LEVEL_FROM).map(|(_, its)| its).max().unwrap_or(0),
        }
    }
}
