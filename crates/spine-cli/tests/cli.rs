//! The `spine` binary end to end: good cases write `result.json`, bad input exits with code 2, a
//! one-line error naming the field, and writes nothing.

mod common;

use common::{spine, tmpdir, workspace};
use std::path::PathBuf;
use std::process::Output;

const GOOD: &str = r#"{
  "kind": "equilibrium",
  "chain": { "links": 4, "length_x": 1.0, "masses": 0.1 },
  "design": { "theta0": [0.3, 0.1, -0.1, -0.3], "stiffness": [800, 800, 800, 800, 0] },
  "loads": { "p_y": -5.0, "p_x": -100.0 }
}"#;

fn run_case(text: &str, tag: &str, extra: &[&str]) -> (Output, PathBuf) {
    let dir = tmpdir(tag);
    let case = dir.join("case.json");
    std::fs::write(&case, text).unwrap();
    let out = dir.join("out");
    let mut args = vec!["case", case.to_str().unwrap(), "--out", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    (spine(&args), out)
}

#[test]
fn good_case_writes_result_with_status_and_stability() {
    let (o, out) = run_case(GOOD, "good", &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    for key in ["passive", "loaded"] {
        assert_eq!(r[key]["status"]["kind"], "stable");
        assert!(r[key]["residual_norm"].as_f64().unwrap() <= 1e-10);
        assert_eq!(r[key]["stability"]["stable"], true);
        assert_eq!(r[key]["theta"].as_array().unwrap().len(), 4);
        assert_eq!(r[key]["nodes"].as_array().unwrap().len(), 5);
    }
    assert!(r["timings"]["passive_seconds"].as_f64().unwrap() >= 0.0);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("converged, stable"), "{stdout}");
}

/// `loads.p_x` as one number is the axial force at the end node; as `N + 1` numbers, one per node.
/// The end-only array gives the same bytes as the number; interior axial forces reach an
/// equilibrium of their own (checked: every joint row balanced, stable).
#[test]
fn axial_loads_per_node() {
    let read = |out: &PathBuf| std::fs::read_to_string(out.join("result.json")).unwrap();
    let (o, scalar) = run_case(GOOD, "px-scalar", &["--deterministic"]);
    assert!(o.status.success());
    let end_only = GOOD.replace("\"p_x\": -100.0", "\"p_x\": [0, 0, 0, 0, -100.0]");
    let (o, array) = run_case(&end_only, "px-array", &["--deterministic"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&scalar), read(&array));
    let interior = GOOD.replace("\"p_x\": -100.0", "\"p_x\": [0, -40.0, 0, 25.0, -100.0]");
    let (o, spread) = run_case(&interior, "px-interior", &["--deterministic"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b): (serde_json::Value, serde_json::Value) =
        (serde_json::from_str(&read(&scalar)).unwrap(), serde_json::from_str(&read(&spread)).unwrap());
    assert_eq!(b["loaded"]["status"]["kind"], "stable");
    assert!(b["loaded"]["residual_norm"].as_f64().unwrap() <= 1e-10);
    assert_ne!(a["loaded"]["theta"], b["loaded"]["theta"], "interior axial forces change the loaded state");
    assert_eq!(a["passive"]["theta"], b["passive"]["theta"], "the passive state has no axial force");
}

#[test]
fn same_input_same_bytes_with_deterministic() {
    let (a, out_a) = run_case(GOOD, "det-a", &["--deterministic"]);
    let (b, out_b) = run_case(GOOD, "det-b", &["--deterministic"]);
    assert!(a.status.success() && b.status.success());
    let (ra, rb) =
        (std::fs::read(out_a.join("result.json")).unwrap(), std::fs::read(out_b.join("result.json")).unwrap());
    assert_eq!(ra, rb);
    assert!(!String::from_utf8_lossy(&ra).contains("timings"));
}

#[test]
fn unstable_result_is_reported_not_hidden() {
    // A straight chain pushed far beyond its buckling load: converges on the unstable branch.
    let text = r#"{"kind": "equilibrium", "chain": {"links": 4, "length_x": 1.0},
      "design": {"theta0": [0, 0, 0, 0], "stiffness": 100},
      "loads": {"p_y": 0.0, "p_x": -100000.0}}"#;
    let (o, out) = run_case(text, "unstable", &[]);
    assert_eq!(o.status.code(), Some(3));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["loaded"]["status"]["kind"], "unstable");
    assert_eq!(r["loaded"]["stability"]["stable"], false);
    assert!(String::from_utf8_lossy(&o.stdout).contains("UNSTABLE"));
}

/// Each bad case: `(tag, case text, field the error must name)`.
fn bad_cases() -> Vec<(&'static str, String, &'static str)> {
    let good: serde_json::Value = serde_json::from_str(GOOD).unwrap();
    let with = |path: &[&str], v: serde_json::Value| {
        let mut g = good.clone();
        let mut node = &mut g;
        for p in &path[..path.len() - 1] {
            node = &mut node[*p];
        }
        node[path[path.len() - 1]] = v;
        g.to_string()
    };
    use serde_json::json;
    vec![
        ("malformed", "{\"kind\": \"equilibrium\", ".to_string(), "case file"),
        ("not-object", "[1, 2]".to_string(), "case file"),
        ("no-kind", r#"{"chain": {}}"#.to_string(), "kind"),
        ("bad-kind", with(&["kind"], json!("statics")), "kind"),
        ("unknown-top", with(&["colour"], json!("red")), "colour"),
        ("unknown-chain", with(&["chain", "linkz"], json!(3)), "chain"),
        ("zero-links", with(&["chain", "links"], json!(0)), "chain.links"),
        ("neg-links", with(&["chain", "links"], json!(-3)), "chain.links"),
        ("both-lengths", with(&["chain", "spans"], json!([0.25, 0.25, 0.25, 0.25])), "chain"),
        ("spans-len", with(&["chain", "masses"], json!([0.1, 0.1])), "chain.masses"),
        ("neg-mass", with(&["chain", "masses"], json!(-1.0)), "chain.masses[0]"),
        ("theta0-len", with(&["design", "theta0"], json!([0.1, -0.1])), "design.theta0"),
        ("theta0-string", with(&["design", "theta0"], json!(["a", 0, 0, 0])), "design.theta0[0]"),
        ("theta0-halfpi", with(&["design", "theta0"], json!([1.6, 0.0, 0.0, -1.6])), "design.theta0[0]"),
        ("phi-nonzero", with(&["design", "theta0"], json!([0.3, 0.1, -0.1, -0.2])), "design.theta0"),
        ("neg-stiffness", with(&["design", "stiffness"], json!([800, -5, 800, 800, 0])), "design.stiffness[1]"),
        ("stiffness-len", with(&["design", "stiffness"], json!([800, 800])), "design.stiffness"),
        ("mechanism", with(&["design", "stiffness"], json!(0.0)), "design.stiffness"),
        ("design-keyword", with(&["design"], json!("optimize")), "design"),
        ("optimise-in-equilibrium", with(&["design"], json!("optimise")), "design"),
        ("py-len", with(&["loads", "p_y"], json!([1, 2, 3])), "loads.p_y"),
        ("px-len", with(&["loads", "p_x"], json!([0, -100])), "loads.p_x"),
        ("px-string", with(&["loads", "p_x"], json!([0, 0, "x", 0, -100])), "loads.p_x"),
        // JSON has no infinities: an overflowing literal is refused by the parser with its position.
        ("huge-number", GOOD.replace("-100.0", "-1e999"), "line 5 column"),
        // Issue 19: a key given twice is an error naming it (JSON parsers keep the last silently).
        ("duplicate-key", GOOD.replace("\"p_x\": -100.0", "\"p_x\": -100.0, \"p_x\": 0"), "loads.p_x"),
        (
            "duplicate-top",
            GOOD.replacen("\"kind\": \"equilibrium\",", "\"kind\": \"equilibrium\", \"kind\": \"design\",", 1),
            "kind",
        ),
        ("solver-unknown", with(&["solver"], json!({"tolerance": 1e-9})), "solver"),
        ("solver-step", with(&["solver"], json!({"initial_step": 2.0})), "solver.initial_step"),
    ]
}

#[test]
fn bad_input_exits_2_names_the_field_and_writes_nothing() {
    for (tag, text, field) in bad_cases() {
        let (o, out) = run_case(&text, tag, &[]);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{tag}: exit {:?}, stderr {stderr}", o.status.code());
        assert_eq!(stderr.trim_end().lines().count(), 1, "{tag}: one line, got {stderr}");
        assert!(stderr.contains(field), "{tag}: error should name `{field}`: {stderr}");
        assert!(!stderr.contains("panicked"), "{tag}: {stderr}");
        assert!(!out.exists(), "{tag}: nothing may be written");
    }
}

#[test]
fn bad_input_does_not_overwrite_an_earlier_result() {
    let (o, out) = run_case(GOOD, "keep", &[]);
    assert!(o.status.success());
    let before = std::fs::read(out.join("result.json")).unwrap();
    let case = out.parent().unwrap().join("bad.json");
    std::fs::write(&case, GOOD.replace("\"links\": 4", "\"links\": 0")).unwrap();
    let o = spine(&["case", case.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(out.join("result.json")).unwrap(), before);
}

#[test]
fn missing_file_and_wrong_kind_exit_2() {
    let o = spine(&["case", "/nonexistent/case.json"]);
    assert_eq!(o.status.code(), Some(2));
    let twolink = workspace().join("paper-cases/twolink.json");
    let o = spine(&["equilibrium", twolink.to_str().unwrap(), "--out", tmpdir("kind").join("o").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("kind"));
}

fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// Issue 19: an output folder is replaced as a whole. Files of an earlier run into the same folder
/// do not survive beside the new ones, two runs racing into one folder each leave a complete set,
/// and no staging folder is left behind.
#[test]
fn output_folders_are_all_or_nothing_even_when_two_runs_race() {
    let dir = tmpdir("race");
    let case = dir.join("case.json");
    std::fs::write(&case, GOOD).unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // Issue 49: a file the program did not write is never removed: refused before any work.
    std::fs::write(out.join("stale.csv"), "a user's file").unwrap();
    let o = spine(&["case", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), vec!["stale.csv"]);
    std::fs::remove_file(out.join("stale.csv")).unwrap();
    let o = spine(&["case", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(files_in(&out), vec![".spine-output", "result.json"], "the folder holds exactly the new run's files");
    let expected = std::fs::read(out.join("result.json")).unwrap();

    let runs: Vec<_> = (0..6)
        .map(|_| {
            std::process::Command::new(env!("CARGO_BIN_EXE_spine"))
                .args(["case", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"])
                .stdout(std::process::Stdio::null())
                .spawn()
                .unwrap()
        })
        .collect();
    for mut r in runs {
        assert!(r.wait().unwrap().success());
    }
    assert_eq!(files_in(&out), vec![".spine-output", "result.json"]);
    assert_eq!(std::fs::read(out.join("result.json")).unwrap(), expected);
    assert_eq!(files_in(&dir), vec!["case.json", "out"], "no staging folder left behind");
}

/// Issue 19: Ctrl-C stops a long multi-start through Ipopt's user stop, exits 130, and leaves the
/// previous complete result untouched and nothing partial.
#[test]
fn an_interrupted_run_leaves_the_previous_result_untouched() {
    let dir = tmpdir("interrupt");
    let out = dir.join("out");
    let case = workspace().join("paper-cases/design10.json");
    let first = spine(&["design", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--starts", "0"]);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let before = std::fs::read(out.join("result.json")).unwrap();
    let long = std::process::Command::new(env!("CARGO_BIN_EXE_spine"))
        .args(["design", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--starts", "400"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let killed = std::process::Command::new("kill").args(["-INT", &long.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let clock = std::time::Instant::now();
    let o = long.wait_with_output().unwrap();
    // Ipopt stops at its next iteration through its user-stop hook: well within the grace period.
    assert!(clock.elapsed().as_secs_f64() < 2.5, "took {:?} to stop", clock.elapsed());
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("interrupted"));
    assert_eq!(std::fs::read(out.join("result.json")).unwrap(), before, "the previous result is untouched");
    assert_eq!(files_in(&out), vec![".spine-output", "result.json"]);
    assert_eq!(files_in(&dir), vec!["out"], "nothing partial beside it");
}

/// Issue 19: `--time-limit` bounds a long run. The GA of eq. (37) stops at its next generation,
/// the result reached so far is written marked `"stopped": "time_limit"` with the search's own
/// status, and the exit code is 3.
#[test]
fn a_time_limit_stops_a_long_search_and_writes_what_it_reached() {
    let dir = tmpdir("time-limit");
    let out = dir.join("out");
    let case = workspace().join("paper-cases/periodic7.json");
    let clock = std::time::Instant::now();
    let o = spine(&["periodic", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--time-limit", "0.5"]);
    let took = clock.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    // The unlimited search takes several seconds; the stop comes at the next integrator step.
    assert!(took < 5.0, "took {took} s");
    let r: serde_json::Value = serde_json::from_slice(&std::fs::read(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["stopped"], "time_limit");
    assert_eq!(r["periodic_design"]["search"]["status"], "time_limit");
    assert!(String::from_utf8_lossy(&o.stdout).contains("STOPPED EARLY (time_limit)"));
}

/// Issue 19: a time limit that leaves a figure without its runs writes nothing and exits 3; a
/// limit outside (0, 1e6] s is bad input (exit 2).
#[test]
fn a_time_limit_that_leaves_nothing_to_report_writes_nothing() {
    let dir = tmpdir("time-limit-figure");
    let out = dir.join("out");
    let case = workspace().join("paper-cases/fig9.json");
    let o = spine(&["case", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--time-limit", "0.001"]);
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("time limit: 0.001 s passed"));
    assert!(!out.exists());
    for bad in ["0", "-1", "nan", "inf", "2e6"] {
        let o =
            spine(&["case", case.to_str().unwrap(), "--out", out.to_str().unwrap(), &format!("--time-limit={bad}")]);
        assert_eq!(o.status.code(), Some(2), "--time-limit {bad}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("--time-limit"), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert!(!out.exists());
}

/// Issue 19: Ctrl-C stops a dynamic search (no Ipopt in it) at the integrator's next step, well
/// within the grace period, exit 130, nothing written.
#[test]
fn an_interrupted_search_stops_at_its_next_step() {
    let dir = tmpdir("interrupt-search");
    let out = dir.join("out");
    let case = workspace().join("paper-cases/periodic7.json");
    let long = std::process::Command::new(env!("CARGO_BIN_EXE_spine"))
        .args(["periodic", case.to_str().unwrap(), "--out", out.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(800));
    let killed = std::process::Command::new("kill").args(["-INT", &long.id().to_string()]).status().unwrap();
    assert!(killed.success());
    let clock = std::time::Instant::now();
    let o = long.wait_with_output().unwrap();
    assert!(clock.elapsed().as_secs_f64() < 2.0, "took {:?} to stop", clock.elapsed());
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!out.exists());
}

/// Issue 49: a followed sweep stops on its time limit and on Ctrl-C within about a step: exit 3
/// with only the computed points written (their count in `result.json` and `sweep.csv`, none
/// with a zero objective), and exit 130 with nothing written.
#[test]
fn a_long_sweep_stops_on_its_time_limit_and_on_ctrl_c() {
    let dir = tmpdir("sweep-stop");
    let case = workspace().join("paper-cases/design5.json");
    let out = dir.join("limited");
    let sweep = |out: &std::path::Path, extra: &[&str]| {
        let mut args = vec!["sweep", case.to_str().unwrap(), "--param", "loads.p_y", "--from", "-10", "--to", "-30"];
        args.extend(["--points", "100000", "--census", "3", "--census-every", "2", "--out", out.to_str().unwrap()]);
        args.extend(extra);
        std::process::Command::new(env!("CARGO_BIN_EXE_spine"))
            .args(args)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap()
    };
    let clock = std::time::Instant::now();
    let o = sweep(&out, &["--time-limit", "0.5"]).wait_with_output().unwrap();
    let took = clock.elapsed().as_secs_f64();
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(took < 2.5, "took {took} s for a 0.5 s limit");
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(result["stopped"], "time_limit");
    assert_eq!(result["sweep"]["stopped"], "time_limit");
    let points = result["sweep"]["points"].as_array().unwrap();
    assert!(!points.is_empty() && points.len() < 100_000, "{}", points.len());
    assert!(points.iter().all(|p| p["objective"].as_f64().unwrap() > 0.0 && p["status"] != "failed"));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), points.len() + 1);
    assert!(String::from_utf8_lossy(&o.stdout).contains("STOPPED (time_limit) after"));
    // Ctrl-C: the loop sees the stop flag at its next step.
    let interrupted = dir.join("interrupted");
    let child = sweep(&interrupted, &[]);
    std::thread::sleep(std::time::Duration::from_millis(1000));
    assert!(std::process::Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap().success());
    let clock = std::time::Instant::now();
    let o = child.wait_with_output().unwrap();
    assert!(clock.elapsed().as_secs_f64() < 1.5, "took {:?} to stop", clock.elapsed());
    assert_eq!(o.status.code(), Some(130), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!interrupted.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A dynamic case whose eq. (33) design does not end clean (links of 10¹⁹ kg: the equilibria
/// diverge) runs no dynamics on it: exit 3, the reason on stderr, nothing written.
#[test]
fn a_dynamic_case_on_an_unclean_static_design_exits_3_and_writes_nothing() {
    let dir = tmpdir("unclean-static");
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(workspace().join("paper-cases/fig11.json")).unwrap()).unwrap();
    case["base"]["chain"]["masses"] = serde_json::json!(1e19);
    case["runs"] = serde_json::json!([case["runs"][0]]);
    let path = dir.join("case.json");
    std::fs::write(&path, case.to_string()).unwrap();
    let out = dir.join("out");
    let o = spine(&["case", path.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("the static design of eq. (33) did not end clean"), "{stderr}");
    assert!(!out.exists());
}
