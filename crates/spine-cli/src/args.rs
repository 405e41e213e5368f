//! The command line: subcommands, their arguments, and the overrides they make to a case.

use crate::parse::{
    parse_batch, parse_census, parse_confidence, parse_every, parse_formulation, parse_frame_width, parse_frames,
    parse_jobs, parse_magnify, parse_method, parse_starts, parse_time_limit,
};
use crate::workers::workers;
use clap::{Parser, Subcommand};
use spine_design::Formulation;
use spine_dynamic_design::SearchMethod;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "spine",
    version,
    about = "Design and analysis of flexible spines (planar link chains with torsional springs)"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(clap::Args)]
pub struct RunArgs {
    /// The case file (JSON).
    pub case: PathBuf,
    /// Output folder; `result.json` is written there.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Leave timings out of `result.json`, so the same input gives the same bytes.
    #[arg(long)]
    pub deterministic: bool,
    /// Wall-clock limit of the run, in seconds (0 < SECONDS ≤ 1e6). When it passes, the solvers
    /// stop at their next check and the result reached so far is written, marked
    /// `"stopped": "time_limit"` (exit code 3).
    #[arg(long, value_name = "SECONDS", value_parser = parse_time_limit, allow_hyphen_values = true)]
    pub time_limit: Option<std::time::Duration>,
}

/// Animation of a dynamic run (figure cases fig9–fig11 always write one; these set its options).
#[derive(clap::Args)]
pub struct AnimateArgs {
    /// Also write `animation.gif`: the chain moving (displacements magnified when small, the
    /// factor in the panel title), the path of its end node, the time stamp, and the end
    /// displacement up to that time. Implied by the options below.
    #[arg(long)]
    pub animate: bool,
    /// Frames of the animation, equally spaced in time (2..=600; default 100).
    #[arg(long, value_name = "N", value_parser = parse_frames)]
    pub frames: Option<usize>,
    /// Width of the animation in pixels (320..=1920; default 800).
    #[arg(long, value_name = "PX", value_parser = parse_frame_width)]
    pub frame_width: Option<u32>,
    /// Factor on the displacements drawn (> 0, ≤ 1e6; default: a round number that makes the
    /// largest one 15 % of the chain's extent, or 1).
    #[arg(long, value_name = "FACTOR", value_parser = parse_magnify, allow_hyphen_values = true)]
    pub magnify: Option<f64>,
}

impl AnimateArgs {
    /// The animation options, when any animation flag is given.
    pub fn options(&self) -> Option<spine_run::AnimationOptions> {
        let given = self.animate || self.frames.is_some() || self.frame_width.is_some() || self.magnify.is_some();
        given.then(|| {
            let d = spine_run::AnimationOptions::default();
            spine_run::AnimationOptions {
                frames: self.frames.unwrap_or(d.frames),
                width: self.frame_width.unwrap_or(d.width),
                magnification: self.magnify.or(d.magnification),
            }
        })
    }
}

/// A run whose motion can be animated (`simulate`, `damping`, `case`).
#[derive(clap::Args)]
pub struct DynamicArgs {
    #[command(flatten)]
    pub run: RunArgs,
    #[command(flatten)]
    pub animate: AnimateArgs,
}

impl DynamicArgs {
    pub fn overrides(&self) -> spine_run::Overrides {
        spine_run::Overrides { animation: self.animate.options(), ..Default::default() }
    }
}

/// `spine case`: any case file by its kind.
#[derive(clap::Args)]
pub struct CaseArgs {
    #[command(flatten)]
    pub dynamic: DynamicArgs,
    /// Worker processes for the seeded starts of a design case's or a figure's multi-starts,
    /// 1..=256 (default: the number of cores; 1: this process). The same bytes either way.
    #[arg(long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
}

impl CaseArgs {
    /// The overrides, with worker processes for the multi-starts: `--jobs`, or one per core.
    pub fn overrides(&self) -> Result<spine_run::Overrides, crate::Failure> {
        let workers = workers(self.jobs, &self.dynamic.run.case, &Default::default())?;
        Ok(spine_run::Overrides { workers, ..self.dynamic.overrides() })
    }
}

#[derive(clap::Args)]
pub struct DesignArgs {
    #[command(flatten)]
    pub run: RunArgs,
    /// Formulation of eq. (33): `full` (simultaneous, exact sparse Hessian) or `reduced`
    /// (equilibria by continuation, adjoint gradients); default: the case file's.
    #[arg(long, value_parser = parse_formulation)]
    pub formulation: Option<Formulation>,
    /// Extra seeded feasible starts (multi-start), at most 100000; default: the case file's.
    #[arg(long, value_parser = parse_starts)]
    pub starts: Option<usize>,
    /// Seed of the multi-start; default: the case file's.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Run the census to a stated confidence: seeded starts in batches of 100 until
    /// P(a better optimum unseen) ≤ P (0 < P < 1; Boender–Rinnooy Kan), at most `--starts` of
    /// them (0 or absent: 100000); exit 3 when the cap or a time limit ends it first. Default: the
    /// case file's `multistart.confidence`.
    #[arg(long, value_name = "P", value_parser = parse_confidence, allow_hyphen_values = true)]
    pub confidence: Option<f64>,
    /// Mesh sequencing of the full space: `off`, `auto` (from 100 links: 50, 100, 200, … links),
    /// `FROM` or `FROM:FACTOR`; default: the case file's `solver.refine`.
    #[arg(long)]
    pub refine: Option<spine_design::refine::Refine>,
    /// Worker processes for the seeded starts of a multi-start, 1..=256 (default: the number of
    /// cores; 1 solves them all in this process). The census is the same, byte for byte.
    #[arg(long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
    /// Solve only the K-th of N shares of the starts (start i belongs to shard i mod N + 1) and
    /// write `DIR/shard.json`; `spine merge` combines the N shards into the single run's result.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<spine_run::shard::ShardSpec>,
    /// With `--confidence` and `--shard`: the batch whose starts the shard takes (B: seeded starts
    /// 100(B−1)+1..=100B, batch 1 also start 0); `spine merge` of batches 1..=B says whether the
    /// census is done or which batch is next (scripts/slurm/census.sh).
    #[arg(long, value_name = "B", value_parser = parse_batch)]
    pub batch: Option<usize>,
    /// Add the derivatives of the reported optimum with respect to the case's parameters
    /// (`sensitivity` in `result.json`, as `spine sensitivity` computes them).
    #[arg(long)]
    pub sensitivity: bool,
    /// Check the case, the options and `--out` as the run (or `--shard`) would; solve and write
    /// nothing (exit 0, or 2 with why). scripts/slurm/census.sh asks it before it submits.
    #[arg(long)]
    pub check: bool,
}

#[derive(clap::Args)]
pub struct MergeArgs {
    /// The shards: folders holding `shard.json` (or the files themselves), one per shard.
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Output folder; `result.json` is written there, as the single run writes it.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Leave timings out of `result.json`, so the same input gives the same bytes.
    #[arg(long)]
    pub deterministic: bool,
}

/// A worker process of `spine design --jobs N` (started by it, not by hand): checks CASE with the
/// overrides, then answers each start design read from standard input (one JSON line) with the
/// unchecked eq. (33) run (one JSON line).
#[derive(clap::Args)]
pub struct WorkerArgs {
    pub case: PathBuf,
    /// The parent's design overrides, as JSON.
    #[arg(long)]
    pub overrides: String,
    /// CASE is a figure: solve its run NAME (a design run).
    #[arg(long, value_name = "NAME")]
    pub run: Option<String>,
}

#[derive(clap::Args)]
pub struct PeriodicArgs {
    #[command(flatten)]
    pub run: RunArgs,
    /// Method for eq. (37): `ga`, `pattern` (search) or `gradient` (Ipopt); default: the case file's.
    #[arg(long, value_parser = parse_method)]
    pub method: Option<SearchMethod>,
    #[command(flatten)]
    pub animate: AnimateArgs,
}

#[derive(clap::Args)]
pub struct StudyArgs {
    /// The study: `ck` (eq. (34): C_K over half-decades, Ipopt scaling on and off).
    #[arg(value_parser = ["ck"])]
    pub study: String,
    #[command(flatten)]
    pub run: RunArgs,
    /// The C_K values; default 1 to 10⁴ in half-decades.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub values: Option<Vec<f64>>,
    /// Worker processes for the study's eq. (33) solves, 1..=256 (default: the cores); same rows.
    #[arg(long, value_name = "N", value_parser = parse_jobs)]
    pub jobs: Option<usize>,
}

#[derive(clap::Args)]
pub struct SensitivityArgs {
    #[command(flatten)]
    pub run: RunArgs,
    /// A parameter: the case file's field path (`delta_d`, `loads.p_x`, `loads.p_y[3]`,
    /// `stiffness_scale`, `chain.length_x`, `bounds.stiffness_max`, …) or `loads.scale` (a factor on
    /// the transverse loads); repeat for several; default: all of them.
    #[arg(long = "param", value_name = "NAME")]
    pub params: Vec<String>,
    /// Extra seeded feasible starts before the optimum is differentiated, at most 100000 (0: only
    /// the case's own start); default: the case file's `multistart.starts`.
    #[arg(long, value_parser = parse_starts)]
    pub starts: Option<usize>,
}

impl SensitivityArgs {
    /// The overrides: the number of seeded starts.
    pub fn overrides(&self) -> spine_run::Overrides {
        let mut overrides = spine_run::Overrides::default();
        overrides.design.starts = self.starts;
        overrides
    }
}

#[derive(clap::Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub run: RunArgs,
    /// The swept parameter: a case file field path as for `spine sensitivity` (`loads.p_y`,
    /// `delta_d`, `stiffness_scale`, …).
    #[arg(long = "param", value_name = "NAME")]
    pub param: String,
    /// The parameter's first value (the optimum found there is followed).
    #[arg(long, allow_hyphen_values = true)]
    pub from: f64,
    /// The parameter's last value.
    #[arg(long, allow_hyphen_values = true)]
    pub to: f64,
    /// Reported points, equally spaced from --from to --to (rows of sweep.csv), 2..=100000.
    #[arg(long, default_value_t = 21)]
    pub points: usize,
    /// A census at every --census-every-th point: a multi-start of this many seeded starts says
    /// whether the followed optimum is still the best known.
    #[arg(long, value_name = "STARTS", value_parser = parse_census)]
    pub census: Option<usize>,
    /// The census's spacing in points (1: every point).
    #[arg(long, value_name = "K", default_value_t = 5, value_parser = parse_every)]
    pub census_every: usize,
    /// Extra seeded starts of the design run at --from, whose best optimum is followed (0: the
    /// case's own start); default: the case file's `multistart.starts`.
    #[arg(long, value_parser = parse_starts)]
    pub starts: Option<usize>,
}

impl SweepArgs {
    /// The overrides: the number of seeded starts at the sweep's first value.
    pub fn overrides(&self) -> spine_run::Overrides {
        let mut overrides = spine_run::Overrides::default();
        overrides.design.starts = self.starts;
        overrides
    }

    /// The sweep's settings (validated by the run, which names the flag at fault).
    pub fn settings(&self) -> spine_design::sweep::settings::SweepSettings {
        spine_design::sweep::settings::SweepSettings::new(self.from, self.to, self.points)
    }

    /// The census plan, when asked for.
    pub fn census(&self) -> Option<spine_run::sweep::CensusPlan> {
        self.census.map(|starts| spine_run::sweep::CensusPlan { starts, every: self.census_every })
    }
}

#[derive(clap::Args)]
pub struct ReportArgs {
    /// The results folder: one sub-folder per case with its `result.json`.
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// The cases in reading order (names of sub-folders).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "twolink,fig3,fig4,fig5,fig6,fig7,fig8,fig9,fig10,fig11,fig12,study-ck"
    )]
    pub cases: Vec<String>,
    /// The errata table to include.
    #[arg(long, default_value = "docs/errata.md")]
    pub errata: PathBuf,
}

#[derive(clap::Args)]
pub struct QuotesArgs {
    /// The results folder (`just paper`'s): a `result.json` per case folder, and `report.json`.
    #[arg(long, default_value = "results")]
    pub results: PathBuf,
    /// Compare the quotes with the runs and exit 3 where one drifted; write nothing.
    #[arg(long)]
    pub check: bool,
    /// The docs that quote the runs.
    #[arg(default_values = ["README.md", "docs/findings.md", "docs/errata.md", "docs/contributing.md"])]
    pub files: Vec<PathBuf>,
}

#[derive(Subcommand)]
pub enum Command {
    /// Passive (θ1) and loaded (θ2) equilibria of a given design, with stability.
    Equilibrium(RunArgs),
    /// The two-link analysis of Sec. 3: closed forms beside the exact solution.
    Twolink(RunArgs),
    /// The static design problem of eq. (33) with Ipopt (optionally multi-start).
    Design(DesignArgs),
    /// Step or periodic response (Sec. 5.2): `response.csv` and `result.json` with T_90, Δ∞, τ, fit error, drift.
    Simulate(DynamicArgs),
    /// The damping design of eq. (35): dampers for each target rise time.
    Damping(DynamicArgs),
    /// The periodic-load design of eq. (37) by a genetic algorithm or a pattern search.
    Periodic(PeriodicArgs),
    /// Runs any case file by its `kind` (a `figure` case: its runs, plots, tables and checked claims).
    Case(CaseArgs),
    /// A parameter study on a design case (`ck`: the C_K study of eq. (34)).
    Study(StudyArgs),
    /// Eq. (33) on a design case, then the derivatives of its optimum (θ0*, K*, θ1*, θ2*, λ*, J*)
    /// with respect to the case's parameters, with the conditions they rest on.
    Sensitivity(SensitivityArgs),
    /// Eq. (33)'s optimum followed along one parameter of a design case (predictor: the
    /// sensitivities; corrector: warm-started Ipopt), with the events on the way and an optional
    /// multi-start census: sweep.csv, result.json and a figure.
    Sweep(SweepArgs),
    /// Combines the shards of a multi-start (`spine design … --shard K/N`) into its `result.json`.
    Merge(MergeArgs),
    #[command(hide = true)]
    Worker(WorkerArgs),
    /// Gathers the figures' results into `RESULTS/REPORT.md` and `RESULTS/report.html` (one self-contained page).
    Report(ReportArgs),
    /// Writes the numbers the docs quote (`<!--q SOURCE PATH | FORMAT-->…<!--/q-->`) from the runs.
    Quotes(QuotesArgs),
}

impl DesignArgs {
    /// The overrides, with worker processes for a multi-start: `--jobs`, or one per core.
    pub fn overrides(&self) -> Result<spine_run::Overrides, crate::Failure> {
        let mut overrides = self.design_overrides();
        overrides.workers = workers(self.jobs, &self.run.case, &overrides.design)?;
        Ok(overrides)
    }

    fn design_overrides(&self) -> spine_run::Overrides {
        let design = spine_run::DesignOverrides {
            formulation: self.formulation,
            starts: self.starts,
            seed: self.seed,
            confidence: self.confidence,
            refine: self.refine,
            sensitivity: self.sensitivity,
        }
        .with_confidence_cap();
        spine_run::Overrides { design, ..Default::default() }
    }
}

impl PeriodicArgs {
    pub fn overrides(&self) -> spine_run::Overrides {
        let method = self.method;
        spine_run::Overrides {
            dynamics: spine_run::DynamicsOverrides { method },
            animation: self.animate.options(),
            ..Default::default()
        }
    }
}

impl StudyArgs {
    /// The overrides: worker processes for the study's solves.
    pub fn overrides(&self) -> Result<spine_run::Overrides, crate::Failure> {
        let workers = workers(self.jobs, &self.run.case, &Default::default())?;
        Ok(spine_run::Overrides { workers, ..Default::default() })
    }

    /// The C_K values of `spine study ck` (default: half-decades from 1 to 10⁴).
    pub fn values(&self) -> Result<Vec<f64>, crate::Failure> {
        let values = self.values.clone().unwrap_or_else(spine_run::study::half_decades);
        match values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            Some(v) => Err(crate::Failure::Input(format!(
                "--values: every C_K must be finite and > 0, got {}",
                spine_check::short(*v)
            ))),
            None => Ok(values),
        }
    }
}
