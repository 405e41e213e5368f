//! # spine-paper: the paper's figures, computed, drawn and checked
//!
//! A figure case (`"kind": "figure"`, see `docs/case-format.md`) lists runs; [`run`] computes each
//! one, a recipe in [`figures`] turns the results into panels (SVG and PNG through `spine-plot`),
//! CSV tables of the plotted data and [`Claim`]s — the paper's statements, each measured and given
//! PASS or FAIL with its numbers. [`study`] is the C_K study of eq. (34) and [`report`] gathers
//! every figure's claims into `results/REPORT.md`.
#![forbid(unsafe_code)]

pub mod claims;
pub mod figures;
pub mod metrics;
pub mod report;
pub mod run;
pub mod study;

pub use claims::{Check, Claim};
pub use figures::{recipe, FigureOutput, NamedRun};
pub use run::{run_case, run_study, CaseResult, Overrides, RunError, RunOutput};
