//! `spine quotes`: the numbers the docs quote from the paper cases' runs, written from
//! `RESULTS/*/result.json` and `RESULTS/report.json` (`spine_paper::quotes`), or, with
//! `--check`, compared with them (exit 3 on a drift).

use crate::args::QuotesArgs;
use crate::output::say;
use crate::Failure;
use serde_json::Value;
use spine_paper::quotes::{quotes, rewrite, Drift};
use std::collections::BTreeMap;
use std::path::Path;

/// Largest doc read, bytes.
const MAX_DOC_BYTES: usize = 16 << 20;
/// Largest `result.json` read, bytes.
const MAX_RESULT_BYTES: usize = 512 << 20;

/// `Ok(true)` when no quote drifted (with `--check`) or every doc was written.
pub fn run(a: &QuotesArgs) -> Result<bool, Failure> {
    let mut docs = Vec::new();
    for file in &a.files {
        let text = spine_case::read_text(file, "doc", MAX_DOC_BYTES).map_err(|e| Failure::Input(e.to_string()))?;
        docs.push((file.display().to_string(), text));
    }
    // Every source the docs name, read once.
    let mut sources: BTreeMap<String, Value> = BTreeMap::new();
    let mut total = 0;
    for (name, text) in &docs {
        let found = quotes(name, text).map_err(|e| Failure::Input(e.to_string()))?;
        total += found.len();
        for q in found {
            if !sources.contains_key(&q.source) {
                let value =
                    source(&a.results, &q.source).map_err(|m| Failure::Input(format!("{name}:{}: {m}", q.line)))?;
                sources.insert(q.source.clone(), value);
            }
        }
    }
    let mut drifts: Vec<Drift> = Vec::new();
    let mut rewritten = Vec::new();
    for (name, text) in &docs {
        let (new, found) = rewrite(name, text, &|s| sources.get(s)).map_err(|e| Failure::Input(e.to_string()))?;
        if new != *text {
            rewritten.push((name.clone(), new));
        }
        drifts.extend(found);
    }
    for d in &drifts {
        eprintln!(
            "{}:{}: {} {}: the doc quotes \"{}\", the run gives \"{}\"",
            d.file, d.line, d.source, d.path, d.quoted, d.computed
        );
    }
    if a.check {
        say(&format!("{total} quotes in {} docs, {} drifted from {}\n", docs.len(), drifts.len(), a.results.display()));
        return Ok(drifts.is_empty());
    }
    for (name, text) in &rewritten {
        write_doc(Path::new(name), text)?;
    }
    say(&format!("{total} quotes in {} docs, {} rewritten in {} docs\n", docs.len(), drifts.len(), rewritten.len()));
    Ok(true)
}

/// The JSON a quote's source names: `report` is `RESULTS/report.json`, any other name the
/// `result.json` of that folder of RESULTS.
fn source(results: &Path, name: &str) -> Result<Value, String> {
    let plain = !name.is_empty()
        && name != "."
        && name != ".."
        && !name.contains(['/', '\\'])
        && !name.chars().any(char::is_control);
    if !plain {
        return Err(format!(
            "\"{}\": a quote's source is the name of a result folder or `report`",
            spine_check::shown(name)
        ));
    }
    let file = if name == "report" { results.join("report.json") } else { results.join(name).join("result.json") };
    let text = spine_case::read_text(&file, "result", MAX_RESULT_BYTES)
        .map_err(|e| format!("{e} (run `just paper`, or give the results folder with --results)"))?;
    serde_json::from_str(&text).map_err(|e| format!("{}: not JSON: {e}", file.display()))
}

/// Writes a doc through a new file beside it and a rename: the old text or the new, never a part.
fn write_doc(path: &Path, text: &str) -> Result<(), Failure> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("doc");
    let tmp = path.with_file_name(format!(".{name}.{}.tmp", std::process::id()));
    let io = |e: std::io::Error| Failure::Other(format!("{}: cannot write: {e}", path.display()));
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        io(e)
    })
}
