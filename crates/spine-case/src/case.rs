//! The dispatcher: a case file by its `kind`, parsed ([`Case`]) and checked ([`ValidCase`]).

use crate::design_case::{DesignCase, ValidDesign};
use crate::dynamics_case::{DynamicsCase, ValidDynamics};
use crate::equilibrium_case::{EquilibriumCase, ValidEquilibrium};
use crate::figure_case::FigureCase;
use crate::parse::parse;
use crate::twolink_case::{TwoLinkCase, ValidTwoLink};
use crate::CaseError;

/// The registry of case kinds: each kind's name as a case file writes it, its variant and its
/// parsed type, written once. It makes [`Case`], [`KINDS`], the parser's dispatch and
/// [`Case::kind`]; adding a kind is one line here, its case module, its run module in `spine-run`,
/// its section in `docs/case-format.md` and a paper case (a test checks the last two).
macro_rules! case_kinds {
    ($( $(#[$doc:meta])* $variant:ident($parsed:ty) = $name:literal, )+) => {
        /// A parsed case file, by kind.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Case {
            $( $(#[$doc])* $variant($parsed), )+
        }

        /// The kinds this program runs, in the registry's order.
        pub const KINDS: &[&str] = &[$($name),+];

        impl Case {
            /// The case of kind `kind` from the rest of the file, or `None` for an unknown kind.
            fn parse_kind(kind: &str, rest: serde_json::Value) -> Option<Result<Self, CaseError>> {
                match kind {
                    $( $name => Some(parse(rest).map(Case::$variant)), )+
                    _ => None,
                }
            }

            /// The case's kind as written in the file.
            pub fn kind(&self) -> &'static str {
                match self {
                    $( Self::$variant(_) => $name, )+
                }
            }

            /// The case as a case file's JSON object (`"kind"` first, then every field, defaults
            /// written out): [`Case::from_json`] of its text gives the same case back.
            pub fn to_json(&self) -> serde_json::Value {
                let fields = match self {
                    $( Self::$variant(c) => serde_json::to_value(c), )+
                }
                .expect("case files serialise: their maps have string keys");
                let mut object = serde_json::Map::new();
                object.insert("kind".into(), serde_json::Value::String(self.kind().into()));
                if let serde_json::Value::Object(map) = fields {
                    object.extend(map);
                }
                serde_json::Value::Object(object)
            }
        }

        /// The JSON Schema (draft 2020-12) of a case file, generated from the types the parser
        /// reads: one alternative per kind, each the kind's fields with `"kind"` fixed to its
        /// name. Shipped as `docs/case.schema.json` (a test keeps the two equal); editors use it
        /// to check and complete case files. Ranges that depend on other fields (one entry per
        /// link, `Σ a_i tan θ0_i = 0`) are left to [`Case::validate`].
        pub fn json_schema() -> serde_json::Value {
            let mut generator = schemars::SchemaGenerator::default();
            let alternatives = vec![$( kind_schema(<$parsed as schemars::JsonSchema>::json_schema(&mut generator), $name) ),+];
            let definitions: serde_json::Map<String, serde_json::Value> =
                generator.definitions().iter().map(|(k, v)| (k.clone(), v.clone())).collect();
            serde_json::json!({
                "$schema": "https://json-schema.org/draft/2020-12/schema",
                "title": "Flexible spine case file",
                "description": "A case file of the flexible-spine workspace (docs/case-format.md): a JSON object whose \"kind\" says what to run.",
                "type": "object",
                "required": ["kind"],
                "properties": { "kind": { "enum": KINDS } },
                "oneOf": alternatives,
                "$defs": definitions,
            })
        }
    };
}

/// The schema of one kind's fields with `"kind": name` added (required, fixed).
fn kind_schema(schema: schemars::Schema, name: &str) -> serde_json::Value {
    let mut value = schema.to_value();
    if let serde_json::Value::Object(map) = &mut value {
        map.insert("title".into(), serde_json::Value::String(format!("\"kind\": \"{name}\"")));
        let properties = map.entry("properties").or_insert_with(|| serde_json::json!({}));
        if let serde_json::Value::Object(p) = properties {
            p.insert("kind".into(), serde_json::json!({ "const": name }));
        }
        let required = map.entry("required").or_insert_with(|| serde_json::json!([]));
        if let serde_json::Value::Array(r) = required {
            r.insert(0, serde_json::Value::String("kind".into()));
        }
    }
    value
}

case_kinds! {
    /// `"kind": "equilibrium"`: the passive and loaded equilibria of a given design.
    Equilibrium(EquilibriumCase) = "equilibrium",
    /// `"kind": "twolink"`: the two-link analysis of Sec. 3.
    Twolink(TwoLinkCase) = "twolink",
    /// `"kind": "design"`: the static design problem, eq. (33).
    Design(DesignCase) = "design",
    /// `"kind": "simulate"`: a step or periodic response (Sec. 5.2).
    Simulate(DynamicsCase) = "simulate",
    /// `"kind": "damping"`: the damping design, eq. (35).
    Damping(DynamicsCase) = "damping",
    /// `"kind": "periodic"`: the periodic-load design, eq. (37).
    Periodic(DynamicsCase) = "periodic",
    /// `"kind": "figure"`: a figure of the paper, several runs drawn and checked together.
    Figure(FigureCase) = "figure",
}

/// A checked case, ready for a solver.
// One value per run: boxing the large variants would buy nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum ValidCase {
    Equilibrium(ValidEquilibrium),
    Twolink(ValidTwoLink),
    Design(ValidDesign),
    /// Kinds `simulate`, `damping`, `periodic` (the task says which).
    Dynamics(ValidDynamics),
    Figure(Vec<ValidRun>),
}

impl Case {
    /// Parses a case file. Errors name the field (`chain.links`, `design.theta0[2]`, …).
    pub fn from_json(text: &str) -> Result<Self, CaseError> {
        crate::parse::check_text(text)?;
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| CaseError::parse("case file", format!("not valid JSON: {e}")))?;
        let serde_json::Value::Object(mut map) = value else {
            return Err(CaseError::parse("case file", "must be a JSON object"));
        };
        let kind = match map.remove("kind") {
            Some(serde_json::Value::String(k)) => k,
            Some(_) => {
                return Err(CaseError::invalid("kind", format!("must be a string, one of {}", KINDS.join(", "))))
            }
            None => return Err(CaseError::invalid("kind", format!("missing; one of {}", KINDS.join(", ")))),
        };
        Self::parse_kind(&kind, serde_json::Value::Object(map)).unwrap_or_else(|| {
            Err(CaseError::invalid("kind", format!("unknown kind {kind:?}; one of {}", KINDS.join(", "))))
        })
    }

    /// Checks every value; errors name the field.
    pub fn validate(&self) -> Result<ValidCase, CaseError> {
        Ok(match self {
            Self::Equilibrium(c) => ValidCase::Equilibrium(c.validate()?),
            Self::Twolink(c) => ValidCase::Twolink(c.validate()?),
            Self::Design(c) => ValidCase::Design(c.validate()?),
            Self::Simulate(c) | Self::Damping(c) | Self::Periodic(c) => ValidCase::Dynamics(c.validate(self.kind())?),
            Self::Figure(c) => ValidCase::Figure(c.validate()?),
        })
    }

    /// The case's title (empty when the file gives none).
    pub fn title(&self) -> &str {
        match self {
            Self::Equilibrium(c) => &c.title,
            Self::Twolink(c) => &c.title,
            Self::Design(c) => &c.title,
            Self::Simulate(c) | Self::Damping(c) | Self::Periodic(c) => &c.title,
            Self::Figure(c) => &c.title,
        }
    }
}

/// A run of a figure with its case merged, parsed and checked.
#[derive(Clone, Debug)]
pub struct ValidRun {
    pub name: String,
    pub label: String,
    pub case: Case,
    pub valid: ValidCase,
}

impl FigureCase {
    /// Checks the recipe name and every run: the merged case must parse and validate for its kind.
    /// Errors name the run: `runs[1].chain.links: …`.
    pub fn validate(&self) -> Result<Vec<ValidRun>, CaseError> {
        let mut runs = Vec::new();
        for (i, run) in self.merged_runs()?.into_iter().enumerate() {
            let at = format!("runs[{i}]");
            let text = serde_json::to_string(&run.case).expect("JSON values serialise");
            let case = Case::from_json(&text).map_err(|e| e.under(&format!("{at}.case")))?;
            if matches!(case, Case::Figure(_)) {
                return Err(CaseError::invalid(format!("{at}.case.kind"), "a figure's run cannot be a figure"));
            }
            let valid = case.validate().map_err(|e| e.under(&format!("{at}.case")))?;
            if let ValidCase::Design(d) = &valid {
                if d.multistart.starts > 0 && d.multistart.confidence.is_none() {
                    // A figure draws a run against its own start; a multi-start's best optimum
                    // comes from another start. Refused rather than silently run from one start
                    // (with `confidence`, the census's best is drawn beside it and `starts` caps it).
                    return Err(CaseError::invalid(
                        format!("{at}.case.multistart.starts"),
                        format!(
                            "a figure draws each design run from its own start: 0 or leave it out (got {}); run multi-starts with `spine design`, or give `multistart.confidence` to draw the best optimum of a census beside it",
                            d.multistart.starts
                        ),
                    ));
                }
            }
            runs.push(ValidRun { name: run.name, label: run.label, case, valid });
        }
        Ok(runs)
    }
}
