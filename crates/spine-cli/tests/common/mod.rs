//! Helpers shared by the CLI test binaries.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh folder for one test (per process and tag).
pub fn tmpdir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spine-cli-test-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs the `spine` binary.
pub fn spine(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spine")).args(args).output().unwrap()
}

/// A GIF's width (px) and its number of frames, decoding every frame.
pub fn gif_width_and_frames(bytes: &[u8]) -> (u16, usize) {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options.read_info(bytes).unwrap();
    let mut frames = 0;
    while decoder.read_next_frame().unwrap().is_some() {
        frames += 1;
    }
    (decoder.width(), frames)
}

/// Rust debug formatting in text meant for a person (`Some(`, `None`, `Ok(`, `Err(`, `{ .. }`,
/// `Name { field: …`, a list of quoted strings `["…`), if any: the first such piece, with what
/// surrounds it.
pub fn debug_text(text: &str) -> Option<String> {
    let around = |at: usize| {
        let start = text[..at].char_indices().rev().nth(30).map_or(0, |(i, _)| i);
        let end = text[at..].char_indices().nth(40).map_or(text.len(), |(i, _)| at + i);
        text[start..end].to_string()
    };
    for piece in ["Some(", "Ok(", "Err(", "{ .. }", "Error {", "[\""] {
        if let Some(at) = text.find(piece) {
            return Some(around(at));
        }
    }
    let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
    for (at, _) in text.match_indices("None") {
        if !word(text[..at].chars().next_back()) && !word(text[at + 4..].chars().next()) {
            return Some(around(at));
        }
    }
    // `Name { field: …`: a capitalised word, " { ", a snake_case name and a colon.
    for (at, _) in text.match_indices(" { ") {
        let name = text[..at].rsplit(|c: char| !c.is_alphanumeric()).next().unwrap_or("");
        let field: String = text[at + 3..].chars().take_while(|c| c.is_ascii_lowercase() || *c == '_').collect();
        let colon = text[at + 3 + field.len()..].starts_with(':');
        if name.starts_with(|c: char| c.is_ascii_uppercase()) && !field.is_empty() && colon {
            return Some(around(at));
        }
    }
    None
}

/// Every string value in a JSON document, with its path.
pub fn json_strings<'a>(v: &'a serde_json::Value, path: String, out: &mut Vec<(String, &'a str)>) {
    match v {
        serde_json::Value::String(s) => out.push((path, s)),
        serde_json::Value::Object(map) => {
            for (k, child) in map {
                json_strings(child, format!("{path}.{k}"), out);
            }
        }
        serde_json::Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                json_strings(child, format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}
