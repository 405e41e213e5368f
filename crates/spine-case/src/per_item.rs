//! A value given once for all entries, or once per entry.

use crate::error::CaseError;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

/// `5.0` (the same for every entry) or `[1.0, 2.0, …]` (one per entry).
#[derive(Clone, Debug, PartialEq)]
pub enum PerItem {
    Uniform(f64),
    Each(Vec<f64>),
}

impl Default for PerItem {
    fn default() -> Self {
        Self::Uniform(0.0)
    }
}

impl PerItem {
    /// Expands to `count` values, checking the length and that every value is finite.
    /// `what` names the entries in the error ("one per link").
    pub fn expand(&self, field: &str, count: usize, what: &str) -> Result<Vec<f64>, CaseError> {
        let values = match self {
            Self::Uniform(v) => vec![*v; count],
            Self::Each(v) if v.len() == count => v.clone(),
            Self::Each(v) => {
                return Err(CaseError::invalid(field, format!("expected {count} entries ({what}), got {}", v.len())))
            }
        };
        check_finite(field, &values)?;
        Ok(values)
    }
}

/// Every value finite, or an error naming the first bad entry.
pub(crate) fn check_finite(field: &str, values: &[f64]) -> Result<(), CaseError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(CaseError::invalid(format!("{field}[{i}]"), "must be a finite number")),
        None => Ok(()),
    }
}

impl<'de> Deserialize<'de> for PerItem {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = PerItem;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number (the same for every entry) or an array of numbers (one per entry)")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<PerItem, E> {
                Ok(PerItem::Uniform(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<PerItem, E> {
                Ok(PerItem::Uniform(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<PerItem, E> {
                Ok(PerItem::Uniform(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PerItem, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 20));
                while let Some(v) = seq.next_element::<f64>()? {
                    out.push(v);
                }
                Ok(PerItem::Each(out))
            }
        }
        d.deserialize_any(V)
    }
}

impl Serialize for PerItem {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Uniform(v) => s.serialize_f64(*v),
            Self::Each(v) => v.serialize(s),
        }
    }
}

/// A number or an array of numbers, as [`PerItem`] reads them.
impl schemars::JsonSchema for PerItem {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "PerItem".into()
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "description": "One number for every entry, or an array with one number per entry.",
            "oneOf": [
                { "type": "number" },
                { "type": "array", "items": { "type": "number" } }
            ]
        })
    }
}
