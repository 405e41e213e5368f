//! Parsing JSON into a case type with the path of the failing field in the error.

use crate::CaseError;
use serde::de::DeserializeOwned;

/// Marks a path inside a field whose deserialiser is hand-written (see [`DesignSpec`]).
pub(crate) const INNER_PATH: &str = "\u{1f}";

pub(crate) fn parse<T: DeserializeOwned>(value: serde_json::Value) -> Result<T, CaseError> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let mut field = if path == "." { "case file".to_string() } else { path };
        let mut message = e.into_inner().to_string();
        if let Some(rest) = message.strip_prefix(INNER_PATH) {
            if let Some((inner, msg)) = rest.split_once(INNER_PATH) {
                if inner != "." {
                    field = format!("{field}.{inner}");
                }
                message = msg.to_string();
            }
        }
        CaseError::parse(field, message)
    })
}

/// Largest case file accepted, bytes (the paper's cases are under 10 kB; a million-link design
/// with every value written out stays under 64 MiB).
pub const MAX_CASE_BYTES: usize = 64 << 20;

/// Checks the raw text before it becomes a value: size, and no object with a key given twice
/// (`serde_json` would keep the last one silently). The error names the key's path.
pub(crate) fn check_text(text: &str) -> Result<(), CaseError> {
    if text.len() > MAX_CASE_BYTES {
        return Err(CaseError::parse(
            "case file",
            format!("{} bytes; at most {MAX_CASE_BYTES} are accepted", text.len()),
        ));
    }
    let mut de = serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, NoDuplicateKeys>(&mut de) {
        Ok(_) => Ok(()),
        Err(e) => {
            let path = e.path().to_string();
            let message = e.into_inner().to_string();
            match message.strip_prefix(DUPLICATE) {
                Some(key) => {
                    let field = if path == "." { key.to_string() } else { format!("{path}.{key}") };
                    Err(CaseError::parse(field, "given twice; give each field once"))
                }
                // Not JSON: `Case::from_json` reports it with its position.
                None => Ok(()),
            }
        }
    }
}

const DUPLICATE: &str = "duplicate key: ";

/// Walks any JSON value and fails on the first object key given twice.
struct NoDuplicateKeys;

impl<'de> serde::Deserialize<'de> for NoDuplicateKeys {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(NoDuplicateKeysVisitor)
    }
}

struct NoDuplicateKeysVisitor;

impl<'de> serde::de::Visitor<'de> for NoDuplicateKeysVisitor {
    type Value = NoDuplicateKeys;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, _: bool) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_i64<E>(self, _: i64) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_u64<E>(self, _: u64) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_f64<E>(self, _: f64) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_str<E>(self, _: &str) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_unit<E>(self) -> Result<NoDuplicateKeys, E> {
        Ok(NoDuplicateKeys)
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<NoDuplicateKeys, A::Error> {
        while seq.next_element::<NoDuplicateKeys>()?.is_some() {}
        Ok(NoDuplicateKeys)
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<NoDuplicateKeys, A::Error> {
        let mut seen = std::collections::HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            if !seen.insert(key.clone()) {
                return Err(serde::de::Error::custom(format!("{DUPLICATE}{key}")));
            }
            map.next_value::<NoDuplicateKeys>()?;
        }
        Ok(NoDuplicateKeys)
    }
}
