//! Parsing JSON into a case type with the path of the failing field in the error.

use crate::error::CaseError;
use serde::de::DeserializeOwned;

/// Marks a path inside a field whose deserialiser is hand-written (see [`DesignSpec`]).
pub(crate) const INNER_PATH: &str = "\u{1f}";

pub fn parse<T: DeserializeOwned>(value: serde_json::Value) -> Result<T, CaseError> {
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
        CaseError::parse(field, plain(&message))
    })
}

/// JSON text (a shard, a file the workspace wrote and a person may have edited) parsed into `T`
/// without a value in between (a shard may hold hundreds of megabytes): text that is not JSON is
/// reported with its line and column, a field of the wrong form by its path in the workspace's
/// wording (`batch: a whole number ≥ 0 is expected, got "2"`), never serde's.
pub fn from_json_text<T: DeserializeOwned>(text: &str) -> Result<T, CaseError> {
    let syntax = |e: &serde_json::Error| {
        let what = e.to_string();
        let what = what.split(" at line ").next().unwrap_or_default().to_string();
        CaseError::parse("JSON", format!("not valid JSON at line {}, column {}: {what}", e.line(), e.column()))
    };
    let mut de = serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        if inner.is_syntax() || inner.is_eof() {
            return syntax(&inner);
        }
        let message = inner.to_string();
        let message = message.rsplit_once(" at line ").map_or(message.as_str(), |(m, _)| m);
        let field = if path == "." { "the file".to_string() } else { path };
        CaseError::parse(field, plain(message))
    })?;
    de.end().map_err(|e| syntax(&e))?;
    Ok(value)
}

/// What a field of an untagged choice (a value that may take one of several forms) allows, by the
/// type's name in serde's `data did not match any variant of untagged enum NAME`.
fn untagged_forms(name: &str) -> Option<&'static str> {
    Some(match name {
        "Refine" => "\"auto\", \"off\", or a ladder such as {\"from\": 50, \"factor\": 2}",
        "ExtraOption" => "a number, a whole number or a text (an Ipopt option's value)",
        _ => return None,
    })
}

/// serde's wording for a person: `invalid type: null, expected f64` becomes `a number is
/// expected, got null`; `invalid value: integer `-1`, expected usize` becomes `a whole number ≥ 0
/// is expected, got -1`; `unknown field `x`, expected one of `a`, `b`` becomes `unknown field;
/// allowed: a, b`; a choice that needs its settings given as a bare name (`"peak_moment"`), or one
/// without settings given as an object, says how to write it; an untagged choice lists its forms.
/// Other messages are kept.
pub(crate) fn plain(message: &str) -> String {
    if let Some(name) = message.strip_prefix("data did not match any variant of untagged enum ") {
        return match untagged_forms(name.trim()) {
            Some(forms) => format!("not one of the allowed forms: {forms}"),
            None => "not one of the allowed forms of this field (docs/case-format.md lists them)".into(),
        };
    }
    if message.starts_with("invalid type: unit variant, expected newtype variant")
        || message.starts_with("invalid type: unit variant, expected struct variant")
    {
        return "this choice takes settings: write it as an object, {\"NAME\": {…}} (an empty {} keeps the defaults of the settings that have one)".into();
    }
    if message.ends_with("expected unit variant") {
        return "this choice takes no settings: write its name alone, as a text (\"NAME\")".into();
    }
    let expected = |what: &str| -> String {
        let what = what.trim();
        match what {
            "f64" | "f32" => "a number".into(),
            "usize" | "u64" | "u32" | "u16" | "u8" => "a whole number ≥ 0".into(),
            "i64" | "i32" => "a whole number".into(),
            "a boolean" | "bool" => "true or false".into(),
            w if w.starts_with("struct ") || w.starts_with("a map") => "an object".into(),
            w if w.starts_with("a sequence") => "a list".into(),
            w => w.replace('`', ""),
        }
    };
    let given = |what: &str| -> String {
        let what = what.trim();
        let unquoted = |w: &str| w.split('`').nth(1).map(String::from).unwrap_or_else(|| w.to_string());
        match what {
            "sequence" => "a list".into(),
            "map" => "an object".into(),
            w if w.starts_with("integer ") || w.starts_with("floating point ") => unquoted(w),
            w if w.starts_with("string ") => w.trim_start_matches("string ").to_string(),
            w if w.starts_with("boolean ") => unquoted(w),
            w => w.to_string(),
        }
    };
    for prefix in ["invalid type: ", "invalid value: "] {
        if let Some(rest) = message.strip_prefix(prefix) {
            if let Some((got, want)) = rest.rsplit_once(", expected ") {
                return format!("{} is expected, got {}", expected(want), given(got));
            }
        }
    }
    // `NAME`, expected one of `a`, `b`  or  `NAME`, expected `a` or `b`: the name and the list.
    let named = |rest: &'_ str| -> Option<(String, String)> {
        let (name, allowed) = rest.split_once("`, expected one of ").or_else(|| rest.split_once("`, expected "))?;
        Some((name.to_string(), allowed.to_string()))
    };
    if let Some(rest) = message.strip_prefix("unknown field `") {
        if let Some((name, allowed)) = named(rest) {
            return format!("unknown field `{name}`; allowed: {}", allowed.replace('`', ""));
        }
        if let Some(name) = rest.strip_suffix("`, there are no fields") {
            return format!("unknown field `{name}`; this section has no fields");
        }
    }
    if let Some((name, allowed)) = message.strip_prefix("unknown variant `").and_then(named) {
        return format!("\"{name}\" is not allowed; allowed: {}", allowed.replace('`', "\""));
    }
    if let Some(rest) = message.strip_prefix("missing field `") {
        if let Some(name) = rest.strip_suffix('`') {
            return format!("missing: give `{name}`");
        }
    }
    message.to_string()
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

#[cfg(test)]
mod plain_tests {
    use super::plain;

    #[test]
    fn serde_wording_becomes_plain() {
        assert_eq!(plain("invalid type: null, expected f64"), "a number is expected, got null");
        assert_eq!(plain("invalid value: integer `-1`, expected usize"), "a whole number ≥ 0 is expected, got -1");
        assert_eq!(plain("invalid type: string \"5\", expected usize"), "a whole number ≥ 0 is expected, got \"5\"");
        assert_eq!(plain("invalid type: sequence, expected f64"), "a number is expected, got a list");
        assert_eq!(plain("unknown field `q`, expected one of `p_y`, `p_x`"), "unknown field `q`; allowed: p_y, p_x");
        assert_eq!(
            plain("unknown variant `x`, expected `full` or `reduced`"),
            "\"x\" is not allowed; allowed: \"full\" or \"reduced\""
        );
        assert_eq!(plain("something else"), "something else");
        let refine = plain("data did not match any variant of untagged enum Refine");
        assert!(refine.contains("\"auto\", \"off\"") && refine.contains("from"), "{refine}");
        let bare = plain("invalid type: unit variant, expected newtype variant");
        assert!(bare.contains("object") && !bare.contains("variant"), "{bare}");
        let settings = plain("invalid type: map, expected unit variant");
        assert!(settings.contains("no settings") && !settings.contains("variant"), "{settings}");
    }

    #[test]
    fn json_text_errors_name_the_field_in_our_words() {
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct Shard {
            batch: usize,
            runs: Vec<f64>,
        }
        let e = super::from_json_text::<Shard>(r#"{"batch": "2", "runs": []}"#).unwrap_err().to_string();
        assert_eq!(e, "batch: a whole number ≥ 0 is expected, got \"2\"");
        let e = super::from_json_text::<Shard>(r#"{"batch": 2, "runs": [1, null]}"#).unwrap_err().to_string();
        assert_eq!(e, "runs[1]: a number is expected, got null");
        let e = super::from_json_text::<Shard>("{\"batch\": 2,\n \"runs\": [1,").unwrap_err().to_string();
        assert!(e.starts_with("JSON: not valid JSON at line 2, column") && !e.contains(" at line 2 column"), "{e}");
        let e = super::from_json_text::<Shard>(r#"{"batch": 2, "runs": []} x"#).unwrap_err().to_string();
        assert!(e.contains("not valid JSON"), "{e}");
    }
}
