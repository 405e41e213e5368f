//! `spine case` on a `"kind": "continuum"` file: a short ladder end to end, byte-identical with
//! `--deterministic`, and bad fields refused with exit 2, naming the field, writing nothing.

mod common;

use common::{spine, tmpdir, workspace};
use serde_json::Value;

fn paper_case() -> Value {
    serde_json::from_str(&std::fs::read_to_string(workspace().join("paper-cases/continuum.json")).unwrap()).unwrap()
}

#[test]
fn a_short_ladder_writes_its_figure_tables_and_the_same_bytes_twice() {
    let mut case = paper_case();
    case["links"] = serde_json::json!([10, 20]);
    let dir = tmpdir("continuum-ladder");
    let file = dir.join("case.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let mut texts = Vec::new();
    for k in 0..2 {
        let out = dir.join(format!("out{k}"));
        let o = spine(&["case", file.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"]);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains("strict_minimum") || stdout.contains("weak_minimum"), "{stdout}");
        for name in ["continuum.svg", "continuum.pdf", "levels.csv", "profiles.csv"] {
            assert!(out.join(name).is_file(), "{name} missing");
        }
        let levels = std::fs::read_to_string(out.join("levels.csv")).unwrap();
        assert_eq!(levels.lines().count(), 3, "{levels}");
        // Two levels' profiles: N θ0 values and N + 1 EI values each.
        let profiles = std::fs::read_to_string(out.join("profiles.csv")).unwrap();
        assert_eq!(profiles.lines().count(), 1 + (10 + 11) + (20 + 21));
        texts.push((std::fs::read(out.join("result.json")).unwrap(), levels, profiles));
    }
    assert!(texts[0] == texts[1], "the same case gave different bytes");
    let result: Value = serde_json::from_slice(&texts[0].0).unwrap();
    assert_eq!(result["kind"], "continuum");
    let levels = result["study"]["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 2);
    // Each level: the first pass's attempts, then (below the finest) the second pass's.
    assert_eq!(levels[0]["attempts"][0]["from"], "arch");
    assert!(levels[0]["attempts"].as_array().unwrap().iter().any(|a| a["from"] == "finest"));
    assert!(levels[1]["attempts"].as_array().unwrap().iter().all(|a| a["from"] == "coarser"));
}

#[test]
fn bad_fields_exit_2_naming_the_field_and_write_nothing() {
    let cases: [(&str, Value, &str); 5] = [
        ("links", serde_json::json!([10, 5]), "links[1]"),
        ("links", serde_json::json!([]), "links"),
        ("rod.bending_stiffness_max", serde_json::json!(5.0), "rod.bending_stiffness_max"),
        ("rod.height_ramp", serde_json::json!(0.9), "rod.height_ramp"),
        ("solver.warm_barriers", serde_json::json!([0.0]), "solver.warm_barriers[0]"),
    ];
    let dir = tmpdir("continuum-bad");
    for (k, (field, value, named)) in cases.into_iter().enumerate() {
        let mut case = paper_case();
        let mut target = &mut case;
        let parts: Vec<&str> = field.split('.').collect();
        for part in &parts[..parts.len() - 1] {
            if target.get(*part).is_none() {
                target[*part] = serde_json::json!({});
            }
            target = &mut target[*part];
        }
        target[parts[parts.len() - 1]] = value;
        let file = dir.join(format!("bad{k}.json"));
        std::fs::write(&file, case.to_string()).unwrap();
        let out = dir.join(format!("out{k}"));
        let o = spine(&["case", file.to_str().unwrap(), "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{field}: {stderr}");
        assert!(stderr.contains(named), "{field}: {stderr}");
        assert!(!out.exists(), "{field}: wrote {}", out.display());
    }
}
