//! `benchmarks/RESULTS.md` written by a run that measured part of it: `just bench-peers` has no
//! criterion data unless `just bench` ran in the same tree, and a fresh clone has none. The
//! criterion sections and the targets this run did not measure are kept from the file before;
//! what it measured (the CasADi comparison, its targets) and the hand-written analysis are the
//! run's.

/// The heading of the section that `just bench-peers` writes.
const PEERS: &str = "## Eq. (33) against CasADi";
/// What follows that section (the criterion figure, then the analysis).
const FIGURE: &str = "![scaling]";
/// The first heading of `benchmarks/analysis.md`.
const ANALYSIS: &str = "## What is compared";
const TARGETS: &str = "## Targets";

/// `fresh` (a RESULTS.md written without criterion measurements) with `earlier`'s criterion
/// sections, and `earlier`'s targets rows where `fresh` has them `not measured`. `None` when
/// either lacks a section the merge needs (then `fresh` is written as it is).
pub fn keep_earlier_measurements(earlier: &str, fresh: &str) -> Option<String> {
    let (head, earlier_rows, earlier_rest) = split_targets(earlier)?;
    let (_, fresh_rows, fresh_rest) = split_targets(fresh)?;
    let fresh_measured: Vec<&str> =
        fresh_rows.iter().copied().filter(|row| !row.trim_end().ends_with("| not measured |")).collect();
    let mut rows: Vec<&str> = earlier_rows
        .iter()
        .map(|&row| fresh_measured.iter().find(|f| key(f) == key(row)).copied().unwrap_or(row))
        .collect();
    rows.extend(fresh_measured.iter().filter(|f| earlier_rows.iter().all(|e| key(e) != key(f))));
    let section = |text: &str, from: &str, to: &str| -> Option<(usize, usize)> {
        let a = text.find(from)?;
        Some((a, text[a..].find(to)? + a))
    };
    let (ea, eb) = section(earlier_rest, PEERS, FIGURE)?;
    let (fa, fb) = section(fresh_rest, PEERS, FIGURE)?;
    let ec = earlier_rest[eb..].find(ANALYSIS)? + eb;
    let fc = fresh_rest.find(ANALYSIS)?;
    let table = format!("{TARGETS}\n\n| target | measured | met |\n|---|---|---|\n{}\n\n", rows.join("\n"));
    Some(format!(
        "{head}{table}{}{}{}{}",
        &earlier_rest[..ea],
        &fresh_rest[fa..fb],
        &earlier_rest[eb..ec],
        &fresh_rest[fc..]
    ))
}

/// A targets row's statement (its first cell), which names it in both files.
fn key(row: &str) -> &str {
    row.split(" | ").next().unwrap_or_default()
}

/// The text before the targets table, its rows, and the text after it (from the next heading).
fn split_targets(text: &str) -> Option<(&str, Vec<&str>, &str)> {
    let a = text.find(TARGETS)?;
    let b = text[a + TARGETS.len()..].find("\n## ")? + a + TARGETS.len() + 1;
    let rows = text[a..b].lines().filter(|l| l.starts_with("| ") && !l.starts_with("| target |")).collect();
    Some((&text[..a], rows, &text[b..]))
}

#[cfg(test)]
mod tests {
    use super::keep_earlier_measurements;

    fn file(targets: &[&str], times: &str, peers: &str, analysis: &str) -> String {
        format!(
            "# Benchmark results\n\n## Targets\n\n| target | measured | met |\n|---|---|---|\n{}\n\n## Times per N\n\n{times}\n\n## Eq. (33) against CasADi + IPOPT\n\n{peers}\n\n![scaling](scaling.svg)\n\n## What is compared\n\n{analysis}\n",
            targets.join("\n")
        )
    }

    #[test]
    fn a_peers_run_keeps_the_criterion_sections_and_unmeasured_targets() {
        let earlier = file(
            &["| AD ≤ 1.1 × hand | 0.5× | yes |", "| N = 1000 under 20 s | 1.4 s | yes |"],
            "| residual | 1 µs |",
            "old peers table",
            "old analysis",
        );
        let fresh = file(
            &["| AD ≤ 1.1 × hand | – | not measured |", "| N = 1000 under 20 s | 1.9 s | yes |", "| new | x | no |"],
            "",
            "new peers table",
            "new analysis",
        );
        let merged = keep_earlier_measurements(&earlier, &fresh).unwrap();
        assert!(merged.contains("| AD ≤ 1.1 × hand | 0.5× | yes |"), "{merged}");
        assert!(merged.contains("| N = 1000 under 20 s | 1.9 s | yes |") && !merged.contains("1.4 s"), "{merged}");
        assert!(merged.contains("| new | x | no |"), "{merged}");
        assert!(merged.contains("| residual | 1 µs |") && merged.contains("new peers table"), "{merged}");
        assert!(!merged.contains("old peers table") && !merged.contains("old analysis"), "{merged}");
        assert!(merged.contains("new analysis") && merged.contains("![scaling]"), "{merged}");
        // A file without the sections is not merged.
        assert!(keep_earlier_measurements("# nothing", &fresh).is_none());
    }
}
