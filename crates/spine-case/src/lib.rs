//! # spine-case: case files
//!
//! A case file is JSON with a `kind` that says what to run. Unknown fields are errors, every value
//! is checked, and every error names the field and what is allowed, so that a bad file never
//! reaches a solver. See `docs/case-format.md` for the full format.
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

mod case;
mod design_case;
mod dynamics_case;
mod dynamics_specs;
mod equilibrium_case;
mod error;
mod figure_case;
pub mod fuzz;
mod parameter;
mod parse;
mod per_item;
mod read;
mod specs;
mod twolink_case;

pub use case::{json_schema, Case, ValidCase, ValidRun, KINDS};
pub use design_case::{BoundsSpec, DesignCase, MultiStartSpec, StartSpec, ValidDesign, MAX_STARTS};
pub use dynamics_case::{
    DampingDesignSpec, DesignSource, DynamicsCase, DynamicsTask, PeriodicDesignSpec, StaticDesignSpec, ValidDynamics,
};
pub use equilibrium_case::{EquilibriumCase, ValidEquilibrium};
pub use error::CaseError;
pub use figure_case::{merge_patch, FigureCase, FigureRun, MergedRun, FIGURES, MAX_RUN_NAME};
pub use parameter::{canonical_parameter, LOAD_SCALE};
pub use parse::MAX_CASE_BYTES;
pub use per_item::PerItem;
pub use read::{read_text, ReadError};
pub use specs::{Assumption, ChainSpec, DesignSpec, GivenDesign, LoadSpec, Notes, MAX_LINKS};
pub use twolink_case::{TwoLinkCase, ValidTwoLink};
