//! The workspace's shape, checked: small source files, so that each holds one concept a reader
//! can take in (the rule of docs/contributing.md: at most 400 lines outside tests).

use std::path::{Path, PathBuf};

/// Lines of a source file before its in-file test module (`#[cfg(test)]` at the start of a line).
fn lines_outside_tests(text: &str) -> usize {
    text.lines().take_while(|l| !l.starts_with("#[cfg(test)]")).count()
}

/// Every `.rs` file under `dir`, skipping test folders, build output and virtual environments.
fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        if path.is_dir() {
            if !["tests", "target", ".venv", "fuzz"].contains(&name.as_str()) {
                sources(&path, out);
            }
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_source_file_is_over_400_lines_outside_its_tests() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut files = Vec::new();
    sources(&root.join("crates"), &mut files);
    sources(&root.join("benchmarks"), &mut files);
    assert!(files.len() > 100, "the walk found {} files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let n = lines_outside_tests(&std::fs::read_to_string(f).ok()?);
            (n > 400).then(|| format!("{} ({n} lines)", f.strip_prefix(root).unwrap_or(f).display()))
        })
        .collect();
    assert!(long.is_empty(), "over 400 lines outside tests: {}", long.join(", "));
}

#[test]
fn the_count_stops_at_the_test_module() {
    assert_eq!(lines_outside_tests("a\nb\n#[cfg(test)]\nmod tests {}\n"), 2);
    assert_eq!(lines_outside_tests("a\n    #[cfg(test)]\nb\n"), 3);
}
