//! # spine-run: one run path from a case file to a typed result
//!
//! [`run_case`] checks a case file of any kind, runs its solver and returns a [`CaseResult`]: what
//! `result.json` holds, the files beside it, whether it is clean (exit code 0) or not (3), and the
//! summary a user reads. Worker processes for a multi-start ([`workers`]), shards of one for a
//! cluster ([`shard`]) and the all-or-nothing output folder ([`write`]) are here too; the CLI and
//! the Python package only parse, call this and print. A figure case's runs are run here, and
//! drawn by the recipes a caller passes ([`FigureRecipes`]; the paper's are `spine-paper`'s).
//! Nothing here prints; only [`write`] writes files.
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
mod dynamics;
mod dynamics_summary;
mod equilibrium;
mod error;
mod figure;
mod files;
pub mod metrics;
mod output;
mod progress;
mod result;
mod run_case;
pub mod sensitivity;
pub mod shard;
pub mod study;
pub mod sweep;
mod sweep_census;
mod sweep_figure;
pub mod text;
mod twolink;
pub mod workers;
pub mod write;

pub use animation::{Animation, AnimationOptions, Track};
pub use claims::{Check, Claim};
pub use confidence::CONFIDENCE_BATCH;
pub use design::{run_design, run_design_case, BestDesign, DesignCaseResult, DesignOverrides, StaticDesign};
pub use dynamics::{
    dynamic_problem, resolve_design, run_dynamics, run_dynamics_case, DampingRun, DesignOrigin, DynamicOutput,
    DynamicsDesign, DynamicsOverrides, DynamicsResult, Eq33Summary, UsedDesign,
};
pub use equilibrium::{run_equilibrium, EquilibriumReport, EquilibriumResult, Unloaded};
pub use error::{MergeError, RunError};
pub use figure::{run_figure, FigureOutput, FigureRecipes, FigureResult, FigureRunResult, NamedRun, NoRecipes};
pub use files::{samples_csv, FileContent, OutputFile};
pub use output::{run, run_twolink, RunOutput};
pub use progress::{quiet, Progress};
pub use result::{with_timings, CaseResult, KindResult};
pub use run_case::{run_case, run_sensitivity, run_study, run_sweep, Overrides};
pub use twolink::{run_twolink_case, TwoLinkResult};
