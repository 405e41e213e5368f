//! # spine-paper: the paper's figures, computed, drawn and checked
//!
//! A figure case (`"kind": "figure"`, see `docs/case-format.md`) lists runs; [`run`] computes each
//! one, a recipe in [`figures`] turns the results into panels (SVG and PNG through `spine-plot`),
//! CSV tables of the plotted data and [`Claim`]s — the paper's statements, each measured and given
//! PASS or FAIL with its numbers. [`study`] is the C_K study of eq. (34) and [`report`] gathers
//! every figure's claims into `results/REPORT.md`.
//!
//! ```
//! // Any case file runs through one path: parse, check, run, a typed result.
//! let case = spine_case::Case::from_json(r#"{
//!   "kind": "twolink", "length": 0.5, "stiffness": 1000, "p_y": -10, "p_x": -400, "deltas": [-1e-4, -1e-5]
//! }"#).unwrap();
//! let result = spine_paper::run_case(&case, &Default::default(), &mut spine_paper::run::quiet).unwrap();
//! assert!(result.is_clean()); // the exact θ0 was found for every δ
//! let json = result.to_json(); // what `spine case` writes to result.json
//! assert_eq!(json["study"]["rows"].as_array().unwrap().len(), 2);
//! ```
#![forbid(unsafe_code)]

pub mod animation;
pub mod claims;
pub mod figures;
pub mod metrics;
pub mod report;
pub mod run;
pub mod study;
pub mod write;

pub use animation::{Animation, AnimationOptions, Track};
pub use claims::{Check, Claim};
pub use figures::{recipe, FigureOutput, NamedRun};
pub use run::{run_case, run_study, CaseResult, Overrides, RunError, RunOutput};
