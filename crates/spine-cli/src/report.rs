//! `spine report`: the figures' results gathered into `RESULTS/REPORT.md`.

use crate::args::ReportArgs;
use crate::output::{say, Output};
use crate::Failure;
use spine_paper::report::{report, FolderResult};

/// `Ok(true)` when every case had a result.
pub fn run(a: &ReportArgs) -> Result<bool, Failure> {
    let errata = std::fs::read_to_string(&a.errata)
        .map_err(|e| Failure::Input(format!("{}: cannot read: {e}", a.errata.display())))?;
    let mut results = Vec::new();
    let mut missing = Vec::new();
    for name in &a.cases {
        let file = a.results.join(name).join("result.json");
        match std::fs::read_to_string(&file).ok().and_then(|t| serde_json::from_str(&t).ok()) {
            Some(value) => results.push(FolderResult { name: name.clone(), value }),
            None => missing.push(name.clone()),
        }
    }
    Output::new(&a.results, false).write_text("REPORT.md", &report(&results, &errata, &missing))?;
    let path = a.results.join("REPORT.md");
    say(&format!("wrote {} ({} cases, {} missing)\n", path.display(), results.len(), missing.len()));
    Ok(missing.is_empty())
}
