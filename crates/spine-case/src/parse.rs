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
        CaseError::Parse { field, message }
    })
}
