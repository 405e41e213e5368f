//! The Python extension reuses the workspace's build: `just test` builds every target
//! (`cargo build --release --workspace --all-targets`) and then maturin builds `spine-py` alone,
//! so the packages of spine-py's tree must resolve to the same features both ways. Where one does
//! not (a new dev-dependency switching a feature on, say), every crate above it is compiled a
//! second time for the extension, several minutes of CI. crates/spine-py/Cargo.toml lists the
//! features it asks for to keep the two equal; this test names any package that differs.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;

/// `package version (path)` → its feature sets, as `cargo tree` resolves them with `args`.
fn resolved(args: &[&str]) -> BTreeMap<String, BTreeSet<String>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(root)
        .args(["tree", "--offline", "--locked", "--prefix", "none", "-f", "{p}|{f}"])
        .args(args)
        .output()
        .expect("cargo runs");
    assert!(out.status.success(), "cargo tree {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    let mut map: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        if let Some((package, features)) = line.trim_end_matches(" (*)").split_once('|') {
            let package = package.replace(" (proc-macro)", "");
            map.entry(package).or_default().insert(features.to_string());
        }
    }
    map
}

#[test]
fn the_python_extension_resolves_the_features_of_the_workspace_build() {
    let workspace = resolved(&["--workspace", "-e", "normal,build,dev"]);
    let python = resolved(&["-p", "spine-py", "-e", "normal,build"]);
    assert!(python.len() > 50 && python.keys().any(|p| p.starts_with("pyo3 v")), "{python:?}");
    let differ: Vec<String> = python
        .iter()
        .filter(|(package, features)| workspace.get(*package) != Some(features))
        .map(|(package, features)| {
            format!("{package}: spine-py alone {features:?}, the workspace {:?}", workspace.get(package))
        })
        .collect();
    assert!(differ.is_empty(), "add these features to crates/spine-py/Cargo.toml:\n{}", differ.join("\n"));
}
