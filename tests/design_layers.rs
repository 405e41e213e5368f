//! The layers inside `spine-design`, checked (docs/contributing.md, "The design run"): its modules
//! import one another downwards only (no circle between two modules), every import names the
//! defining module rather than a re-export of `lib.rs`, the optimality core stands below the
//! certificate and the sensitivities, neither of which reaches into the other or into the solve,
//! and the solve's stages import one another in their order.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The source of a file before its in-file test module, without `//` comments.
fn code_outside_tests(text: &str) -> String {
    let lines = text.lines().take_while(|l| !l.starts_with("#[cfg(test)]"));
    lines.map(|l| l.split("//").next().unwrap_or("")).collect::<Vec<_>>().join("\n")
}

/// What follows each `prefix` in `code` up to the next character that cannot be in a name.
fn names_after<'a>(code: &'a str, prefix: &str) -> Vec<&'a str> {
    code.match_indices(prefix)
        .filter(|(i, _)| !code[..*i].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':'))
        .map(|(i, _)| {
            let rest = &code[i + prefix.len()..];
            &rest[..rest.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '{')).unwrap_or(rest.len())]
        })
        .collect()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every source file of `spine-design` but `lib.rs`: its path under `src/` (`solve/run.rs`) and
/// its code outside tests.
fn design_sources() -> Vec<(String, String)> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap().join("crates/spine-design/src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut out: Vec<(String, String)> = files
        .iter()
        .map(|f| {
            let name = f.strip_prefix(&src).unwrap().to_string_lossy().replace('\\', "/");
            (name, code_outside_tests(&std::fs::read_to_string(f).unwrap()))
        })
        .filter(|(name, _)| name != "lib.rs")
        .collect();
    out.sort();
    assert!(out.len() > 40, "{} files", out.len());
    out
}

/// The top module a file belongs to: `solve/run.rs` → `solve`, `multistart.rs` → `multistart`.
fn module_of(file: &str) -> &str {
    file.split('/').next().unwrap().trim_end_matches(".rs")
}

/// Which modules each module imports (`crate::m` anywhere in its code), itself left out.
fn module_graph(sources: &[(String, String)]) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (file, code) in sources {
        let from = module_of(file).to_string();
        let entry = graph.entry(from.clone()).or_default();
        for name in names_after(code, "crate::") {
            if name != from && !name.is_empty() && !name.starts_with('{') {
                entry.insert(name.to_string());
            }
        }
    }
    graph
}

/// The modules on a circle of `graph`, if any (depth-first search).
fn circle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|p| p == node) {
            return Some(path[at..].to_vec());
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(c) = visit(next, graph, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|k| visit(k, graph, &mut Vec::new(), &mut done))
}

#[test]
fn the_scanner_reads_imports_and_finds_circles() {
    assert_eq!(names_after("use crate::solve::run; x(crate::problem::P)", "crate::"), vec!["solve", "problem"]);
    assert_eq!(names_after("use spine_crate::a;", "crate::"), Vec::<&str>::new());
    assert_eq!(code_outside_tests("a // crate::b\n#[cfg(test)]\ncrate::c"), "a ");
    let graph = |edges: &[(&str, &str)]| {
        let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
        for (a, b) in edges {
            g.entry(a.to_string()).or_default().insert(b.to_string());
        }
        g
    };
    assert_eq!(circle(&graph(&[("a", "b"), ("b", "c")])), None);
    assert!(circle(&graph(&[("a", "b"), ("b", "c"), ("c", "a")])).is_some());
}

#[test]
fn spine_design_modules_import_downwards_only() {
    let sources = design_sources();
    let graph = module_graph(&sources);
    assert!(graph["solve"].contains("certificate"), "the scan sees the solve's imports: {:?}", graph["solve"]);
    assert_eq!(circle(&graph), None, "modules of spine-design that import each other in a loop");
}

#[test]
fn spine_design_imports_name_the_defining_module() {
    // `lib.rs` re-exports a few types for other crates; inside the crate every import names the
    // module that defines what it takes.
    let through_root: Vec<String> = design_sources()
        .iter()
        .flat_map(|(file, code)| {
            names_after(code, "crate::")
                .into_iter()
                .filter(|n| n.starts_with('{') || n.starts_with(|c: char| c.is_uppercase()))
                .map(move |n| format!("{file}: crate::{n}"))
        })
        .collect();
    assert!(through_root.is_empty(), "imports through lib.rs: {}", through_root.join(", "));
}

#[test]
fn the_optimality_core_stands_below_the_certificate_and_the_sensitivities() {
    let graph = module_graph(&design_sources());
    let never: [(&str, &[&str]); 4] = [
        ("optimality", &["certificate", "sensitivity", "solve", "sweep", "multistart"]),
        ("certificate", &["sensitivity", "solve", "sweep", "multistart"]),
        ("sensitivity", &["certificate", "solve", "sweep", "multistart"]),
        ("solve", &["sensitivity", "sweep", "multistart"]),
    ];
    for (module, forbidden) in never {
        let imports = &graph[module];
        let broken: Vec<&&str> = forbidden.iter().filter(|f| imports.contains(**f)).collect();
        assert!(broken.is_empty(), "{module} imports {broken:?} (it imports {imports:?})");
    }
    assert!(graph["certificate"].contains("optimality") && graph["sensitivity"].contains("optimality"));
}

#[test]
fn the_solve_stages_import_one_another_in_their_order() {
    // Each stage may import only those after it in this list (its lower stages).
    let order = ["mod", "settle", "tight", "escape", "polish", "run", "ladder", "ipopt"];
    for (file, code) in design_sources().iter().filter(|(f, _)| f.starts_with("solve/")) {
        let stage = file.trim_start_matches("solve/").trim_end_matches(".rs");
        let at = order.iter().position(|s| *s == stage).unwrap_or_else(|| panic!("{file} is not in the stage list"));
        let mut used: Vec<&str> = names_after(code, "super::");
        used.extend(names_after(code, "crate::solve::").into_iter().filter(|n| order.contains(n)));
        let upward: Vec<&&str> =
            used.iter().filter(|u| order.iter().position(|s| s == *u).is_some_and(|p| p <= at)).collect();
        assert!(upward.is_empty(), "{file} imports the stages {upward:?}, which are not below it");
    }
}
