//! # spine-paper: the paper's figures, drawn and checked, and the reproduction report
//!
//! A figure case (`"kind": "figure"`, see `docs/case-format.md`) lists runs; `spine-run` computes
//! each one, and a recipe in [`figures`] turns the results into panels (SVG, PNG and PDF through
//! `spine-plot`), CSV tables of the plotted data and [`Claim`](spine_run::Claim)s — the paper's
//! statements, each measured and given PASS or FAIL with its numbers. [`PaperFigures`] hands the
//! recipes to the run path; [`report`] gathers every figure's claims into `results/REPORT.md` and
//! `results/report.html`, and `claim_text` writes one claim for both (verdict, knife-edge branches); [`counts`] gives them
//! one count (the paper's statements apart from the solver checks); [`quotes`] writes the
//! numbers the docs quote from the runs (markers in the markdown, checked for drift).
//!
//! ```
//! // Fig. "twolink" (Sec. 3) from a figure case: its runs through spine-run, its panels and claims here.
//! let case = spine_case::Case::from_json(r#"{
//!   "kind": "figure", "figure": "twolink",
//!   "runs": [{ "name": "exact", "case": {
//!     "kind": "twolink", "length": 0.5, "stiffness": 1000, "p_y": -10, "p_x": -400,
//!     "deltas": [-1e-3, -1e-4, -1e-5, -1e-6] } }]
//! }"#).unwrap();
//! let result = spine_run::run_case(&case, &Default::default(), &spine_paper::PaperFigures, &mut spine_run::quiet).unwrap();
//! let json = result.to_json();
//! assert!(json["claims_total"].as_u64().unwrap() > 0); // each claim PASS or FAIL with its numbers
//! ```
#![forbid(unsafe_code)]

mod claim_text;
pub mod counts;
pub mod figures;
pub mod quotes;
pub mod report;

pub use figures::PaperFigures;
