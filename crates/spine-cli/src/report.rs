//! `spine report`: the figures' results gathered into `RESULTS/REPORT.md`, the self-contained
//! `RESULTS/report.html` and the counts in `RESULTS/report.json` (which the docs quote).

use crate::args::ReportArgs;
use crate::output::{say, Output};
use crate::Failure;
use spine_paper::report::{report, report_html, report_json, FolderResult};

/// Largest errata file read, bytes.
const MAX_ERRATA_BYTES: usize = 16 << 20;
/// Largest `result.json` read, bytes.
const MAX_RESULT_BYTES: usize = 512 << 20;

/// `Ok(true)` when every case had a result.
pub fn run(a: &ReportArgs) -> Result<bool, Failure> {
    // Names of sub-folders of RESULTS only: the report reads nothing outside it.
    if let Some(bad) = a.cases.iter().find(|n| {
        n.is_empty()
            || *n == "."
            || *n == ".."
            || n.contains('/')
            || n.contains('\\')
            || n.chars().any(char::is_control)
    }) {
        return Err(Failure::Input(format!(
            "--cases: \"{}\" is not the name of a folder in {}; give names such as fig6,study-ck",
            spine_check::shown(bad),
            spine_check::shown(&a.results.display().to_string())
        )));
    }
    let out = Output::new(&a.results, false);
    out.check_text("REPORT.md")?;
    out.check_text("report.html")?;
    out.check_text("report.json")?;
    let errata =
        spine_case::read_text(&a.errata, "errata", MAX_ERRATA_BYTES).map_err(|e| Failure::Input(e.to_string()))?;
    let mut results = Vec::new();
    let mut missing = Vec::new();
    for name in &a.cases {
        let file = a.results.join(name).join("result.json");
        match spine_case::read_text(&file, "result", MAX_RESULT_BYTES).ok().and_then(|t| serde_json::from_str(&t).ok())
        {
            Some(value) => {
                let assets = assets(&a.results.join(name), &value);
                results.push(FolderResult { name: name.clone(), value, assets })
            }
            None => missing.push(name.clone()),
        }
    }
    out.write_text("REPORT.md", &report(&results, &errata, &missing))?;
    out.write_text("report.html", &report_html(&results, &errata, &missing))?;
    let counts = serde_json::to_string_pretty(&report_json(&results)).map_err(|e| Failure::Other(e.to_string()))?;
    out.write_text("report.json", &(counts + "\n"))?;
    say(&format!(
        "wrote {}, {} and report.json ({} cases, {} missing)\n",
        a.results.join("REPORT.md").display(),
        a.results.join("report.html").display(),
        results.len(),
        missing.len()
    ));
    Ok(missing.is_empty())
}

/// The figures (SVG) and animations (GIF) a result lists, read from its folder; a listed file
/// that cannot be read is left out (the report then shows the rest).
fn assets(folder: &std::path::Path, value: &serde_json::Value) -> Vec<(String, Vec<u8>)> {
    let files = value.get("files").and_then(|f| f.as_array()).into_iter().flatten();
    files
        .filter_map(|f| f.as_str())
        // Plain names of files in the folder only.
        .filter(|f| !f.contains('/') && !f.contains('\\') && !f.starts_with('.'))
        .filter(|f| f.ends_with(".svg") || f.ends_with(".gif"))
        .filter_map(|f| std::fs::read(folder.join(f)).ok().map(|bytes| (f.to_string(), bytes)))
        .collect()
}
