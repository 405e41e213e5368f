//! # spine-run: one run path from a case file to a typed result
//!
//! [`run_case`] checks a case file of any kind, runs its solver and returns a [`CaseResult`]: what
//! `result.json` holds, the files beside it, whether it is clean (exit code 0) or not (3), and the
//! summary a user reads. Worker processes for a multi-start ([`workers`]), shards of one for a
//! cluster ([`shard`]) and the all-or-nothing output folder ([`write`](mod@write)) are here too; the CLI and
//! the Python package only parse, call this and print. A figure case's runs are run here, and
//! drawn by the recipes a caller passes ([`FigureRecipes`]; the paper's are `spine-paper`'s).
//! Nothing here prints; only [`write`](mod@write) writes files.
//!
//! Further modules:
//!
//! * [`animation`]: Animations of the chain's motion: a looping GIF with, for each response, the
//!   chain at the frame's time (its displacements from the first instant magnified so that they can
//!   be seen), the path its end node has travelled, and the end displacement `X_{N+1} − L_x` drawn
//!   up to that time, with the time stamp in the title.
//! * [`claims`]: A claim of the paper, checked by the program: what the paper says, what is
//!   measured and the threshold it is held to (fixed before the run), the verdict and the numbers.
//! * [`confidence`]: A census to a stated confidence: seeded starts of eq. (33) in batches of
//!   `CONFIDENCE_BATCH` (`Batches`) until the Boender–Rinnooy Kan estimate gives P(a better optimum
//!   unseen) ≤ P.
//! * `design`: Kind `design`: eq. (33) with Ipopt from the case's start, and optionally from seeded
//!   multi-starts; also the eq. (33) run a figure or a dynamic case depends on.
//! * `design_summary`: The summary of a design case that a person reads (`spine design`): the
//!   multi-start's census, the solver's status, the optimum, its certificate and its warnings.
//! * `dynamics_summary`: The summary of a dynamic case that a person reads (`spine simulate`,
//!   `damping`, `periodic`): the design's origin, each response's rise, settling and drift, the
//!   damping designs and the periodic design, each number with its unit.
//! * [`kinds`](mod@kinds): Each kind's runner, one file per kind in `src/kinds/` (every file there is a module,
//!   declared by `automod`, so a new kind's runner needs no `mod` line): `equilibrium` (the passive
//!   and loaded equilibria of a given design), `twolink` (Sec. 3), `design` (eq. (33), then the
//!   sensitivities when asked), `dynamics` (`simulate`, `damping`, `periodic`: Sec. 5.2, eqs. (35),
//!   (37)) and `figure` (a figure's runs, drawn and checked together).
//! * `error`: Why a run could not give a result, with its cause.
//! * [`metrics`]: Measures of a static design that the paper's claims are about, each a plain
//!   function of the design and its start.
//! * [`option_values`]: The values of the options a run takes from the command line or from a
//!   Python call, each checked once (the CLI and flexspine call the same functions).
//! * `overrides`: Changes to a case from the command line or a Python call.
//! * `registry`: The registry of the workspace's kinds expanded into the one result enum and the
//!   one dispatch.
//! * `kind`: What a kind's runner and result provide (`RunKind`, `KindOutput`, `RunContext`).
//! * `recipes`: The recipes that draw a figure case's runs: what a recipe reads and what it makes.
//! * `progress`: What a long run reports while it works (a front end draws it; the library prints
//!   nothing).
//! * [`sensitivity`]: `spine sensitivity`: an eq. (33) optimum (one start, full space) and its
//!   derivatives with respect to the case's parameters (`spine_design::sensitivity`), with a CSV
//!   per parameter.
//! * [`sweep`]: `spine sweep`: eq. (33)'s optimum followed along one parameter of a design case
//!   (`spine_design::sweep`), with a census (multi-start) at every k-th point saying whether the
//!   followed optimum is still the best known.
//! * `sweep_census`: The census along a followed sweep: a multi-start at every k-th point says
//!   whether the followed optimum is still the best known, with the multi-start's completeness
//!   estimate.
//! * `sweep_figure`: The figure of a followed sweep: `J*` (followed and best known) and the design
//!   against the parameter, with the events marked.
//! * [`table`]: A table written as CSV beside `result.json`: typed columns written through the
//!   `csv` crate, read by the Python package column by column.
//! * [`text`]: Numbers for a person to read: a quantity with its unit and a precision that fits it,
//!   a list of values.
//! * `files`: The files a result writes beside `result.json` (CSV tables, figures).
//! * `output`: The values runs compute, below every runner: a run inside a figure kept as a value
//!   (`RunOutput`) that a recipe draws and checks, and the parts it holds (an eq. (33) run with
//!   what the figures need, the design and output of a dynamic run, the two-link study's result).
//! * `result`: The typed result of a case (`CaseResult`): what `result.json` holds, the files
//!   written beside it, and whether it is clean (exit code 0) or not (exit code 3).
//! * `study`: The C_K study of eq. (34): one design case solved for C_K over half-decades, with
//!   Ipopt's own scaling on and off, and the paper's statement "as the C_K is increased the
//!   stiffness variation between the nodes increases whereas the change in orientation of the links
//!   is less apparent" (Sec. 5.1) checked on the results.
//!
//! ```
//! // Any case file runs through one path: parse, check, run, a typed result.
//! let case = spine_case::Case::from_json(r#"{
//!   "kind": "twolink", "length": 0.5, "stiffness": 1000, "p_y": -10, "p_x": -400, "deltas": [-1e-4, -1e-5]
//! }"#).unwrap();
//! let result = spine_run::run_case(&case, &Default::default(), &spine_run::NoRecipes, &mut spine_run::quiet).unwrap();
//! assert!(result.is_clean()); // the exact θ0 was found for every δ
//! let json = result.to_json(); // what `spine case` writes to result.json
//! assert_eq!(json["study"]["rows"].as_array().unwrap().len(), 2);
//! ```
#![forbid(unsafe_code)]

pub mod animation;
pub mod claims;
pub mod confidence;
mod design;
mod design_summary;
mod dynamics_summary;
mod error;
mod files;
mod kind;
/// Each kind's runner, one file per kind: every file in `src/kinds/` is a module of its own.
pub mod kinds {
    automod::dir!(pub "src/kinds");
}
pub mod metrics;
pub mod option_values;
mod output;
mod overrides;
mod progress;
mod recipes;
mod registry;
mod result;
mod run_case;
pub mod sensitivity;
pub mod shard;
pub mod study;
pub mod sweep;
mod sweep_census;
mod sweep_figure;
pub mod table;
pub mod text;
pub mod workers;
pub mod write;

pub use animation::{Animation, AnimationOptions, Track};
pub use claims::{BranchOf, BranchVerdict, Check, Claim};
pub use confidence::CONFIDENCE_BATCH;
pub use design::{run_design, run_design_case, DesignCaseResult};
pub use error::{MergeError, RunError, WorkerError};
pub use files::{samples_table, FileContent, OutputFile};
pub use kind::{FigureRun, KindOutput, RunContext, RunKind};
pub use kinds::dynamics::{
    dynamic_problem, resolve_design, run_dynamics, run_dynamics_case, DampingRun, DesignOrigin, DynamicsDesign,
    DynamicsResult, Eq33Summary,
};
pub use kinds::equilibrium::{run_equilibrium, EquilibriumReport, EquilibriumResult, Unloaded};
pub use kinds::figure::{run_figure, FigureResult, FigureRunResult};
pub use kinds::twolink::run_twolink_case;
pub use output::{
    BestDesign, DynamicOutput, DynamicsRun, InFigure, RunOutput, StaticDesign, TwoLinkResult, UsedDesign,
};
pub use overrides::{DesignOverrides, DynamicsOverrides, Overrides};
pub use progress::{quiet, Progress};
pub use recipes::{FigureOutput, FigureRecipes, NamedRun, NoRecipes};
pub use registry::{figure_kinds, in_figure, moves, run_kind, KindResult};
pub use result::{with_timings, CaseResult};
pub use run_case::{run_case, run_sensitivity, run_study, run_sweep};
pub use table::{Cells, Column, Table};
