//! The case enum made from the registry of case kinds ([`case_kinds!`](crate::case_kinds), in
//! `lib.rs`): [`Case`], a case file parsed by its `kind`.

use crate::error::CaseError;
use crate::figure_case::FigureCase;

/// Makes the case enum of a list of kinds (the list [`case_kinds!`] holds, or a test's own):
/// `Case` with one variant per kind, `KINDS`, `Case::from_json`, `Case::kind`, `Case::check`,
/// `Case::title`, `Case::to_json` and `json_schema()`. A kind's case type derives serde's
/// `Deserialize` and `Serialize` and schemars' `JsonSchema`, has a `title: String` field
/// (directly or through `Deref`) and a `validate(&self) -> Result<_, CaseError>`.
#[doc(hidden)]
#[macro_export]
macro_rules! define_cases {
    ($( $(#[$doc:meta])* $variant:ident($parsed:ty) = $name:literal, )+) => {
        /// A parsed case file, by kind.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Case {
            $( $(#[$doc])* $variant($parsed), )+
        }

        /// The kinds this program runs, in the registry's order.
        pub const KINDS: &[&str] = &[$($name),+];

        impl Case {
            /// Parses a case file. Errors name the field (`chain.links`, `design.theta0[2]`, …).
            pub fn from_json(text: &str) -> Result<Self, $crate::CaseError> {
                let (kind, rest) = $crate::__private::split_kind(text, KINDS)?;
                match kind.as_str() {
                    $( $name => $crate::__private::parse(rest).map(Case::$variant), )+
                    _ => Err($crate::CaseError::invalid(
                        "kind",
                        format!("unknown kind {kind:?}; one of {}", KINDS.join(", ")),
                    )),
                }
            }

            /// The case's kind as written in the file.
            pub fn kind(&self) -> &'static str {
                match self {
                    $( Self::$variant(_) => $name, )+
                }
            }

            /// Checks every value; errors name the field. (Each runner checks its case again
            /// into the typed value its solver takes: `DesignCase::validate` and so on.)
            pub fn check(&self) -> Result<(), $crate::CaseError> {
                match self {
                    $( Self::$variant(c) => c.validate().map(drop), )+
                }
            }

            /// The case's title (empty when the file gives none).
            pub fn title(&self) -> &str {
                match self {
                    $( Self::$variant(c) => &c.title, )+
                }
            }

            /// The case as a case file's JSON object (`"kind"` first, then every field, defaults
            /// written out): [`Case::from_json`] of its text gives the same case back.
            pub fn to_json(&self) -> $crate::__private::serde_json::Value {
                let fields = match self {
                    // Invariant: stated in the message; serde_json fails only on maps with non-string keys.
                    $( Self::$variant(c) => $crate::__private::serde_json::to_value(c), )+
                }
                .expect("case files serialise: their maps have string keys");
                $crate::__private::with_kind(self.kind(), fields)
            }
        }

        /// The JSON Schema (draft 2020-12) of a case file, generated from the types the parser
        /// reads: one alternative per kind, each the kind's fields with `"kind"` fixed to its
        /// name. Shipped as `docs/case.schema.json` (a test keeps the two equal); editors use it
        /// to check and complete case files. Ranges that depend on other fields (one entry per
        /// link, `Σ a_i tan θ0_i = 0`) are left to [`Case::check`].
        pub fn json_schema() -> $crate::__private::serde_json::Value {
            use $crate::__private::schemars;
            let mut generator = schemars::SchemaGenerator::default();
            let alternatives = vec![$(
                $crate::__private::kind_schema(<$parsed as schemars::JsonSchema>::json_schema(&mut generator), $name)
            ),+];
            $crate::__private::schema_of(&generator, KINDS, alternatives)
        }
    };
}

crate::case_kinds!(crate::define_cases);

/// The kind and the rest of a case file's JSON object.
#[doc(hidden)]
pub fn split_kind(text: &str, kinds: &[&str]) -> Result<(String, serde_json::Value), CaseError> {
    crate::parse::check_text(text)?;
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| CaseError::parse("case file", format!("not valid JSON: {e}")))?;
    let serde_json::Value::Object(mut map) = value else {
        return Err(CaseError::parse("case file", "must be a JSON object"));
    };
    match map.remove("kind") {
        Some(serde_json::Value::String(k)) => Ok((k, serde_json::Value::Object(map))),
        Some(_) => Err(CaseError::invalid("kind", format!("must be a string, one of {}", kinds.join(", ")))),
        None => Err(CaseError::invalid("kind", format!("missing; one of {}", kinds.join(", ")))),
    }
}

/// A case's fields as a case file's object, `"kind"` first.
#[doc(hidden)]
pub fn with_kind(kind: &str, fields: serde_json::Value) -> serde_json::Value {
    let mut object = serde_json::Map::new();
    object.insert("kind".into(), serde_json::Value::String(kind.into()));
    if let serde_json::Value::Object(map) = fields {
        object.extend(map);
    }
    serde_json::Value::Object(object)
}

/// The schema of a case file from its kinds' alternatives.
#[doc(hidden)]
pub fn schema_of(
    generator: &schemars::SchemaGenerator,
    kinds: &[&str],
    alternatives: Vec<serde_json::Value>,
) -> serde_json::Value {
    let definitions: serde_json::Map<String, serde_json::Value> =
        generator.definitions().iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    serde_json::json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "Flexible spine case file",
        "description": "A case file of the flexible-spine workspace (docs/case-format.md): a JSON object whose \"kind\" says what to run.",
        "type": "object",
        "required": ["kind"],
        "properties": { "kind": { "enum": kinds } },
        "oneOf": alternatives,
        "$defs": definitions,
    })
}

/// The schema of one kind's fields with `"kind": name` added (required, fixed).
#[doc(hidden)]
pub fn kind_schema(schema: schemars::Schema, name: &str) -> serde_json::Value {
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

/// A run of a figure with its case merged, parsed and checked.
#[derive(Clone, Debug)]
pub struct ValidRun {
    pub name: String,
    pub label: String,
    pub case: Case,
}

impl FigureCase {
    /// Checks the recipe name and every run: the merged case must parse and validate for its kind.
    /// Errors name the run: `runs[1].chain.links: …`.
    pub fn validate(&self) -> Result<Vec<ValidRun>, CaseError> {
        let mut runs = Vec::new();
        for (i, run) in self.merged_runs()?.into_iter().enumerate() {
            let at = format!("runs[{i}]");
            // Invariant: a `serde_json::Value` always serialises.
            let text = serde_json::to_string(&run.case).expect("JSON values serialise");
            let case = Case::from_json(&text).map_err(|e| e.under(&format!("{at}.case")))?;
            if matches!(case, Case::Figure(_)) {
                return Err(CaseError::invalid(format!("{at}.case.kind"), "a figure's run cannot be a figure"));
            }
            case.check().map_err(|e| e.under(&format!("{at}.case")))?;
            if let Case::Design(d) = &case {
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
            runs.push(ValidRun { name: run.name, label: run.label, case });
        }
        Ok(runs)
    }
}
