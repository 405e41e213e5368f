//! The workspace's shape, checked: small source files, so that each holds one concept a reader
//! can take in (the rule of docs/contributing.md: at most 400 lines outside tests), and crate docs
//! that name every module of the crate.

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

/// The modules a crate root (`lib.rs`, `main.rs`) declares (`mod x;`, `pub mod x;`,
/// `pub(crate) mod x;`), and those its crate docs (`//!`) do not name as `` `x` `` or `` `x::…` ``.
fn unnamed_modules(root: &str) -> Vec<String> {
    let docs: String = root.lines().filter(|l| l.starts_with("//!")).collect::<Vec<_>>().join("\n");
    root.lines()
        .filter_map(|l| {
            let rest = l.strip_prefix("pub(crate) ").or_else(|| l.strip_prefix("pub ")).unwrap_or(l);
            rest.strip_prefix("mod ")?.strip_suffix(';').map(str::to_string)
        })
        .filter(|m| !docs.contains(&format!("`{m}`")) && !docs.contains(&format!("`{m}::")))
        .collect()
}

#[test]
fn every_crate_names_its_modules_in_its_docs() {
    assert_eq!(unnamed_modules("//! * `a`: A.\nmod a;\npub mod b;\n"), vec!["b".to_string()]);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut roots: Vec<PathBuf> = vec![root.join("benchmarks/src/lib.rs")];
    for entry in std::fs::read_dir(root.join("crates")).unwrap().flatten() {
        roots.extend(["src/lib.rs", "src/main.rs"].map(|f| entry.path().join(f)).into_iter().filter(|p| p.exists()));
    }
    assert!(roots.len() >= 20, "{} crate roots", roots.len());
    let missing: Vec<String> = roots
        .iter()
        .filter_map(|f| {
            let unnamed = unnamed_modules(&std::fs::read_to_string(f).unwrap());
            (!unnamed.is_empty())
                .then(|| format!("{}: {}", f.strip_prefix(root).unwrap().display(), unnamed.join(", ")))
        })
        .collect();
    assert!(missing.is_empty(), "crate docs that do not name their modules: {}", missing.join("; "));
}
