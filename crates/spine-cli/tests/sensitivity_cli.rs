//! `spine sensitivity` end to end: the result, a CSV per parameter, exit codes.

mod common;

use common::{debug_text, spine, tmpdir, workspace};

#[test]
fn sensitivity_writes_derivatives_and_a_csv_per_parameter() {
    let case = workspace().join("paper-cases/design5.json");
    let out = tmpdir("sensitivity-design5");
    let args = ["sensitivity", case.to_str().unwrap(), "--param", "delta_d", "--param", "loads.p_y[2]"];
    let output = spine(&[&args[..], &["--out", out.to_str().unwrap(), "--deterministic"]].concat());
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(json["kind"], "sensitivity");
    let conditions = &json["sensitivity"]["conditions"];
    assert_eq!(conditions["second_order_sufficient"], true);
    assert!(conditions["dependent_rows"].as_array().is_some_and(|d| !d.is_empty()), "design5's angle vertex");
    let delta = &json["sensitivity"]["parameters"][0];
    assert_eq!(delta["name"], "delta_d");
    assert_eq!(delta["derivative"]["stiffness"].as_array().unwrap().len(), 6);
    let (envelope, direct) =
        (delta["derivative"]["objective"].as_f64().unwrap(), delta["derivative"]["objective_direct"].as_f64().unwrap());
    assert!((envelope - direct).abs() < 1e-9 * envelope.abs(), "{envelope} {direct}");
    let csv = std::fs::read_to_string(out.join("sensitivity_loads_p_y_2.csv")).unwrap();
    assert!(csv.starts_with("direction,link,dtheta0_rad"), "{csv}");
    assert_eq!(csv.lines().count(), 1 + 6, "a header and one row per spring");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("second-order sufficient") && stdout.contains("delta_d = -0.02"), "{stdout}");
}

#[test]
fn bad_sensitivity_input_exits_2_names_the_field_and_writes_nothing() {
    let design = workspace().join("paper-cases/design5.json");
    let step = workspace().join("paper-cases/step5.json");
    for (case, param, field) in
        [(&design, "no.such.field", "--param"), (&design, "loads.p_y[99]", "--param"), (&step, "delta_d", "kind")]
    {
        let out = tmpdir("sensitivity-bad");
        let output = spine(&["sensitivity", case.to_str().unwrap(), "--param", param, "--out", out.to_str().unwrap()]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{param}: {stderr}");
        assert!(stderr.contains(field), "{param}: {stderr}");
        assert!(!out.join("result.json").exists());
    }
}

#[test]
fn design_with_sensitivity_adds_the_block_and_without_it_the_result_has_none() {
    let case = workspace().join("paper-cases/design5.json");
    let (with, without) = (tmpdir("design-sensitivity"), tmpdir("design-no-sensitivity"));
    for (out, extra) in [(&with, Some("--sensitivity")), (&without, None)] {
        let mut args = vec!["design", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"];
        args.extend(extra);
        let output = spine(&args);
        assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    }
    let read = |dir: &std::path::Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap()
    };
    let (a, b) = (read(&with), read(&without));
    assert!(b.get("sensitivity").is_none());
    let parameters = a["sensitivity"]["parameters"].as_array().unwrap();
    assert!(parameters.iter().any(|p| p["name"] == "delta_d" && p["derivative"]["stiffness"].is_array()));
    assert_eq!(a["objective"], b["objective"], "the reported optimum is the same");
}

#[test]
fn starts_zero_differentiates_the_optimum_of_the_case_s_own_start() {
    let case = workspace().join("paper-cases/design10.json");
    let out = tmpdir("sensitivity-design10-own-start");
    let args =
        ["sensitivity", case.to_str().unwrap(), "--param", "delta_d", "--starts", "0", "--out", out.to_str().unwrap()];
    let output = spine(&args);
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert!(json["design"]["multistart"].is_null(), "no multi-start with --starts 0");
    assert_eq!(json["sensitivity"]["conditions"]["hold"], true, "{}", json["sensitivity"]["conditions"]);
}

#[test]
fn sweep_writes_one_row_per_point_a_figure_and_the_events() {
    let case = workspace().join("paper-cases/fig5-base.json");
    let out = tmpdir("sweep-fig5");
    let args = ["sweep", case.to_str().unwrap(), "--param", "loads.p_y", "--from", "-1", "--to", "-3", "--points", "5"];
    let output = spine(&[&args[..], &["--out", out.to_str().unwrap(), "--deterministic"]].concat());
    assert_eq!(output.status.code(), Some(0), "{}", String::from_utf8_lossy(&output.stderr));
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert!(csv.starts_with("loads.p_y,objective_J,theta0_1_rad"), "{csv}");
    assert_eq!(csv.lines().count(), 1 + 5, "a header and one row per point");
    assert!(csv.lines().skip(1).all(|l| l.contains(",followed,")), "{csv}");
    for f in ["sweep.svg", "sweep.png", "sweep.pdf"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(json["kind"], "sweep");
    assert_eq!(json["sweep"]["points"].as_array().unwrap().len(), 5);
    assert!(json["sweep"]["events"].as_array().is_some_and(|e| !e.is_empty()), "stiffness bounds become active");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("5 followed") && stdout.contains("bound_active"), "{stdout}");
}

#[test]
fn bad_sweep_input_exits_2_names_the_flag_and_writes_nothing() {
    let design = workspace().join("paper-cases/fig5-base.json");
    let step = workspace().join("paper-cases/step5.json");
    for (case, extra, field) in [
        (&design, vec!["--param", "loads.p_y", "--from", "-1", "--to", "-1"], "--to"),
        (&design, vec!["--param", "loads.p_y", "--from", "-1", "--to", "-2", "--points", "1"], "--points"),
        (&design, vec!["--param", "no.such", "--from", "-1", "--to", "-2"], "--param"),
        (&design, vec!["--param", "loads.p_y", "--from", "-1", "--to", "inf"], "--to"),
        (&step, vec!["--param", "delta_d", "--from", "-0.01", "--to", "-0.02"], "kind"),
    ] {
        let out = tmpdir("sweep-bad");
        let output =
            spine(&[&["sweep", case.to_str().unwrap()][..], &extra, &["--out", out.to_str().unwrap()]].concat());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(field), "{extra:?}: {stderr}");
        assert!(!out.join("result.json").exists());
    }
}

/// A figure case: each static run differentiated, its CSVs prefixed with the run's name; a
/// figure without design runs (fig. 9: dynamics) exits 2 naming `runs`.
#[test]
fn sensitivity_of_a_figure_case_differentiates_each_design_run() {
    let full = workspace().join("paper-cases/fig3.json");
    let out = tmpdir("sensitivity-fig3");
    // fig3's runs under the text's stiffness bound 1000 put every spring on that bound (and the
    // 10-link one its angles on theirs): the conditions fail there, and the run says which.
    let args = ["sensitivity", full.to_str().unwrap(), "--param", "delta_d", "--starts", "0"];
    let out_full = tmpdir("sensitivity-fig3-full");
    let output = spine(&[&args[..], &["--out", out_full.to_str().unwrap(), "--deterministic"]].concat());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("n10-k1000") && stderr.contains("conditions fail"), "{stderr}");
    // The paper's two runs (bound 10⁴).
    let mut text: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&full).unwrap()).unwrap();
    text["runs"].as_array_mut().unwrap().truncate(2);
    let case = out.with_extension("json");
    std::fs::write(&case, text.to_string()).unwrap();
    let args = ["sensitivity", case.to_str().unwrap(), "--param", "delta_d", "--starts", "0"];
    let output = spine(&[&args[..], &["--out", out.to_str().unwrap(), "--deterministic"]].concat());
    let stderr = String::from_utf8_lossy(&output.stderr);
    // fig3's 5-link run sits on a vertex with dependent rows (LICQ fails), so the result is not
    // clean for the angle bounds; for delta_d both runs have derivatives.
    assert_eq!(output.status.code(), Some(0), "{stderr}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(json["kind"], "figure_sensitivity");
    let runs = json["runs"].as_array().unwrap();
    assert_eq!(runs.iter().map(|r| r["name"].as_str().unwrap()).collect::<Vec<_>>(), ["n10", "n5"]);
    for run in runs {
        let name = run["name"].as_str().unwrap();
        let p = &run["result"]["sensitivity"]["parameters"][0];
        assert!(p["derivative"]["objective"].is_f64(), "{name}: {p}");
        assert!(out.join(format!("{name}_sensitivity_delta_d.csv")).exists(), "{name}");
    }
    let fig9 = workspace().join("paper-cases/fig9.json");
    let out = tmpdir("sensitivity-fig9");
    let output = spine(&["sensitivity", fig9.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("runs") && stderr.contains("no design runs"), "{stderr}");
    assert!(!out.join("result.json").exists());
}

/// A parameter at the edge of its allowed range (`bounds.stiffness_min` = 0, where `p − h` would
/// leave it) is differentiated like any other: the rates are exact at `p`, nothing is evaluated
/// beside it. Its `dJ*/dp` by the envelope theorem and directly agree, and the report carries no
/// difference stencil any more.
#[test]
fn a_parameter_at_the_edge_of_its_range_is_differentiated_exactly() {
    let dir = tmpdir("one-sided");
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(workspace().join("paper-cases/design5.json")).unwrap()).unwrap();
    case["bounds"] = serde_json::json!({"stiffness_min": 0});
    let file = dir.join("case.json");
    std::fs::write(&file, case.to_string()).unwrap();
    let out = dir.join("out");
    let o = spine(&[
        "sensitivity",
        file.to_str().unwrap(),
        "--param",
        "bounds.stiffness_min",
        "--param",
        "delta_d",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.code() == Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let parameters = json["sensitivity"]["parameters"].as_array().unwrap();
    assert_eq!(parameters[0]["name"], "bounds.stiffness_min");
    for p in parameters {
        assert!(p.get("difference").is_none() && p.get("step").is_none(), "{p}");
        let d = &p["derivative"];
        let (envelope, direct) = (d["objective"].as_f64().unwrap(), d["objective_direct"].as_f64().unwrap());
        assert!((envelope - direct).abs() <= 1e-6 * envelope.abs().max(1e-9), "{}: {envelope} vs {direct}", p["name"]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_sensitivity_that_is_not_clean_says_why_on_stderr_and_in_the_result() {
    // design5's optimum sits on an angle vertex whose active rows are dependent (LICQ fails): the
    // bounds cannot be followed, so those parameters have no derivative, and the run exits 3.
    let case = workspace().join("paper-cases/design5.json");
    let out = tmpdir("sensitivity-not-clean");
    let output = spine(&["sensitivity", case.to_str().unwrap(), "--out", out.to_str().unwrap(), "--deterministic"]);
    assert_eq!(output.status.code(), Some(3), "{}", String::from_utf8_lossy(&output.stderr));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("not clean: no derivative with respect to bounds.theta0_max: the active rows are dependent"),
        "{stderr}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let reasons = json["not_clean"].as_array().expect("not_clean in result.json");
    assert!(
        reasons.iter().any(|r| r["reason"] == "no_derivative" && r["parameter"] == "bounds.theta0_max"),
        "{reasons:?}"
    );
    for text in [String::from_utf8_lossy(&output.stdout), stderr] {
        assert!(debug_text(&text).is_none(), "{:?}", debug_text(&text));
    }
    // A clean one has no such field.
    let clean = tmpdir("sensitivity-clean");
    let args = ["sensitivity", case.to_str().unwrap(), "--param", "delta_d", "--out", clean.to_str().unwrap()];
    assert_eq!(spine(&args).status.code(), Some(0));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(clean.join("result.json")).unwrap()).unwrap();
    assert!(json.get("not_clean").is_none());
}
