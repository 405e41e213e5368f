//! # spine-case: case files
//!
//! A case file is JSON with a `kind` that says what to run. Unknown fields are errors, every value
//! is checked, and every error names the field and what is allowed, so that a bad file never
//! reaches a solver. See `docs/case-format.md` for the full format.
//!
//! Further modules:
//!
//! * `continuum_case`: `"kind": "continuum"`: eq. (33) for one physical rod at a ladder of `N`.
//! * `design_case`: `"kind": "design"`: the static design problem of eq. (33).
//! * `dynamic_kinds`: The three dynamic kinds (`simulate`, `damping`, `periodic`): one case
//!   format, a case type per kind that knows its task.
//! * `dynamics_case`: `"kind": "simulate" | "damping" | "periodic"`: the dynamics of Sec. 5.2 — a
//!   step or periodic response, the damping design of eq. (35), the periodic-load design of eq.
//!   (37).
//! * `dynamics_checks`: The checks of a dynamic case's settings that do not depend on its kind:
//!   the step response's, a periodic response's and a periodic forcing against the response.
//! * `dynamics_specs`: The sections of a dynamic case that set up a design: eq. (33) first
//!   (`static_design`), eq. (35) (`damping_design`), eq. (37) (`periodic_design`).
//! * `equilibrium_case`: `"kind": "equilibrium"`: the passive and loaded equilibria of a given
//!   design.
//! * `figure_case`: `"kind": "figure"`: one figure of the paper, made of several runs (panels).
//! * [`fuzz`]: The body of the fuzz targets, shared by `fuzz/` (cargo-fuzz, nightly) and the stable
//!   fuzz tests (`tests/cases.rs` in process, `crates/spine-cli/tests/adversarial.rs` through the
//!   binary), and the seeded generator of mutated case files they use.
//! * `parameter`: Numeric fields of a design case as parameters of eq. (33), named by their field
//!   path: `delta_d`, `loads.p_x`, `loads.p_y`, `loads.p_y[3]` (node 3; a single number in the file
//!   is expanded to one per node), `stiffness_scale`, `chain.length_x`, `chain.masses`,
//!   `bounds.stiffness_max[2]`, …, and `loads.scale`, a factor on the transverse load vector (value
//!   1).
//! * `parse`: Parsing JSON into a case type with the path of the failing field in the error.
//! * `per_item`: A value given once for all entries, or once per entry.
//! * `read`: Reading an input file with a size bound that holds for every kind of file: regular
//!   files, devices (`/dev/zero`), pipes and FIFOs, whose size the file system does not know.
//! * `specs`: The parts of a case file that several kinds share (notes, chain, given design, loads,
//!   the continuation options) and the validators of single values.
//! * `twolink_case`: `"kind": "twolink"`: the two-link analysis of Sec. 3.
//! * `case`: The case enum made from the registry of case kinds (`case_kinds!`, in `lib.rs`):
//!   `Case`, a case file parsed by its `kind`.
//! * `error`: Errors in case files.
//! * `objective_spec`: A design case's criterion (field `objective`): the paper's strain energy by
//!   default, or one of the built-ins of `spine_design::Objective`.
//! * `tangent`: The rates of eq. (33)'s problem along a parameter of a design case
//!   (`DesignCase::parameter_tangent`): which of the problem's numbers the case's validation moves
//!   when the field changes, and how fast.
//!
//! ```
//! let text = r#"{
//!   "kind": "equilibrium",
//!   "chain": { "links": 2, "length_x": 1.0 },
//!   "design": { "theta0": [0.2, -0.2], "stiffness": [0, 100, 0] },
//!   "loads": { "p_y": [0, -10, 0], "p_x": -50 }
//! }"#;
//! let case = spine_case::Case::from_json(text).unwrap();
//! assert!(matches!(case, spine_case::Case::Equilibrium(_)));
//! ```
#![forbid(unsafe_code)]

/// The registry of case kinds, written once: each kind's variant, its case type and its name
/// as a case file writes it. It hands the list to the macro `$then` (a path): [`define_cases!`]
/// makes [`Case`] from it here, and `spine-run` makes its result enum and its one dispatch from
/// the same list. Adding a kind is one line here (docs/case-format.md, "Adding a kind").
#[macro_export]
macro_rules! case_kinds {
    ($($then:tt)+) => {
        $($then)+! {
            /// `"kind": "equilibrium"`: the passive and loaded equilibria of a given design.
            Equilibrium($crate::EquilibriumCase) = "equilibrium",
            /// `"kind": "twolink"`: the two-link analysis of Sec. 3.
            Twolink($crate::TwoLinkCase) = "twolink",
            /// `"kind": "design"`: the static design problem, eq. (33).
            Design($crate::DesignCase) = "design",
            /// `"kind": "simulate"`: a step or periodic response (Sec. 5.2).
            Simulate($crate::SimulateCase) = "simulate",
            /// `"kind": "damping"`: the damping design, eq. (35).
            Damping($crate::DampingCase) = "damping",
            /// `"kind": "periodic"`: the periodic-load design, eq. (37).
            Periodic($crate::PeriodicCase) = "periodic",
            /// `"kind": "figure"`: a figure of the paper, several runs drawn and checked together.
            Figure($crate::FigureCase) = "figure",
            /// `"kind": "continuum"`: eq. (33) for one rod at a ladder of `N` (`N → ∞`).
            Continuum($crate::ContinuumCase) = "continuum",
        }
    };
}

mod case;
mod continuum_case;
mod design_case;
mod dynamic_kinds;
mod dynamics_case;
mod dynamics_checks;
mod dynamics_specs;
mod equilibrium_case;
mod error;
mod figure_case;
pub mod fuzz;
mod objective_spec;
mod parameter;
mod parse;
mod per_item;
mod read;
mod specs;
mod tangent;
mod twolink_case;

pub use case::{json_schema, Case, ValidRun, KINDS};
pub use continuum_case::{ContinuumCase, ValidContinuum};
pub use design_case::{check_confidence, BoundsSpec, DesignCase, MultiStartSpec, StartSpec, ValidDesign, MAX_STARTS};
pub use dynamic_kinds::{DampingCase, PeriodicCase, SimulateCase};
pub use dynamics_case::{
    DampingDesignSpec, DesignSource, DynamicKind, DynamicsCase, DynamicsTask, PeriodicDesignSpec, StaticDesignSpec,
    ValidDynamics,
};
pub use equilibrium_case::{EquilibriumCase, ValidEquilibrium};
pub use error::CaseError;
pub use figure_case::{merge_patch, FigureCase, FigureRun, MergedRun, FIGURES, MAX_RUN_NAME};
pub use objective_spec::{
    check_formulation, ComplianceSpec, ConstraintsSpec, ObjectiveSpec, PeakMomentSpec, MAX_EXPONENT,
};
pub use parameter::{canonical_parameter, LOAD_SCALE, PHYSICS};
pub use parse::{from_json_text, MAX_CASE_BYTES};
pub use per_item::PerItem;
pub use read::{read_text, ReadError};
pub use specs::{
    check_runs_memory, run_bytes, Assumption, ChainSpec, DesignSpec, GivenDesign, LoadSpec, Notes, MAX_LINKS,
};
pub use spine_check::FieldError;
pub use twolink_case::{TwoLinkCase, ValidTwoLink};

/// What the macros [`case_kinds!`] and [`define_cases!`] expand to needs, for a crate that
/// instantiates them (spine-run's result enum, a test's own registry).
#[doc(hidden)]
pub mod __private {
    pub use crate::case::{kind_schema, schema_of, split_kind, with_kind};
    pub use crate::parse::parse;
    pub use schemars;
    pub use serde_json;
}
