//! `spine simulate`, `spine damping`, `spine periodic` end to end, and their input errors.

mod common;
use common::{spine, tmpdir, workspace};
use serde_json::{json, Value};

fn step_case(n: usize) -> Value {
    let theta0: Vec<f64> = (0..n).map(|i| 0.3 * (std::f64::consts::PI * (i as f64 + 0.5) / n as f64).cos()).collect();
    json!({
        "kind": "simulate",
        "chain": { "links": n, "length_x": 1.0, "masses": 0.5 },
        "design": { "theta0": theta0, "stiffness": 1000.0 },
        "loads": { "p_y": -5.0, "p_x": -400.0 },
        "damping": 30.0,
        "simulation": { "t_end": 2.0, "samples": 201 }
    })
}

fn write_case(dir: &std::path::Path, case: &Value) -> String {
    let path = dir.join("case.json");
    std::fs::write(&path, serde_json::to_string_pretty(case).unwrap()).unwrap();
    path.display().to_string()
}

#[test]
fn simulate_writes_the_response_and_a_deterministic_summary() {
    let dir = tmpdir("simulate");
    let case = write_case(&dir, &step_case(4));
    let out = dir.join("out");
    let o = spine(&["simulate", &case, "--out", out.to_str().unwrap(), "--deterministic"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(out.join("result.json")).unwrap();
    let r: Value = serde_json::from_str(&text).unwrap();
    let s = &r["step_response"];
    assert_eq!(s["settled"], true);
    assert!(s["rise_time"].as_f64().unwrap() > 0.0);
    assert!(s["drift"]["max_constraint"].as_f64().unwrap() <= 1e-9);
    assert!(s["fit"]["tau"].as_f64().unwrap() > 0.0);
    assert!(r.get("timings").is_none());
    let csv = std::fs::read_to_string(out.join("response.csv")).unwrap();
    assert!(csv.starts_with("t_s,load_factor,delta_m,end_displacement_m,theta_1_rad"));
    assert_eq!(csv.lines().count(), 202);
    let again = spine(&["simulate", &case, "--out", out.to_str().unwrap(), "--deterministic"]);
    assert!(again.status.success());
    assert_eq!(std::fs::read_to_string(out.join("result.json")).unwrap(), text, "same input, same bytes");
}

#[test]
fn bad_dynamic_input_exits_2_names_the_field_and_writes_nothing() {
    let dir = tmpdir("bad-dynamics");
    let out = dir.join("out");
    type Edit = Box<dyn Fn(&mut Value)>;
    let cases: Vec<(&str, Edit, &str)> = vec![
        ("simulate", Box::new(|c| c["chain"]["masses"] = json!(0.0)), "chain.masses[0]"),
        ("simulate", Box::new(|c| c["chain"]["masses"] = json!([0.5, -1.0, 0.5, 0.5])), "chain.masses[1]"),
        ("simulate", Box::new(|c| c["damping"] = json!(-2.0)), "damping[0]"),
        ("simulate", Box::new(|c| c["simulation"]["t_end"] = json!(0.0)), "simulation.t_end"),
        ("simulate", Box::new(|c| c["simulation"]["t_end"] = json!(-1.0)), "simulation.t_end"),
        (
            "simulate",
            Box::new(|c| c["forcing"] = json!({"type": "pulse_train", "period": 1.0, "duty": 1.5})),
            "forcing.duty",
        ),
        ("simulate", Box::new(|c| c["simulation"]["integrator"] = json!({"rtol": 0.0})), "simulation.integrator.rtol"),
        (
            "simulate",
            Box::new(|c| c["simulation"]["integrator"] = json!({"method": "rk4"})),
            "\"rk4\" is not allowed; allowed: \"radau5\" or \"trbdf2\"",
        ),
        // Issue 19: extreme but well-formed values are refused with their range, not run.
        ("simulate", Box::new(|c| c["simulation"]["samples"] = json!(1e15 as u64)), "simulation.samples"),
        ("simulate", Box::new(|c| c["simulation"]["t_end"] = json!(1e300)), "simulation.t_end"),
        (
            "simulate",
            Box::new(|c| c["simulation"]["integrator"] = json!({"newton_tolerance": 1e-300})),
            "simulation.integrator.newton_tolerance",
        ),
        (
            "simulate",
            Box::new(|c| c["simulation"]["integrator"] = json!({"max_steps": 1e12 as u64})),
            "simulation.integrator.max_steps",
        ),
        (
            "simulate",
            Box::new(|c| c["simulation"]["continuation"] = json!({"max_steps": 100_000_000})),
            "simulation.continuation.max_steps",
        ),
        (
            "simulate",
            Box::new(|c| c["forcing"] = json!({"type": "pulse_train", "period": 1.0, "duty": 0.5, "phase": 1})),
            "unknown field `phase`",
        ),
        // Issue 28: a unit forcing refuses unknown fields too.
        (
            "simulate",
            Box::new(|c| c["forcing"] = json!({"type": "step", "period": 5, "bogus": true})),
            "forcing: unknown field `bogus`",
        ),
        // A periodic simulation runs whole periods: the step section's t_end is refused, not ignored.
        (
            "simulate",
            Box::new(|c| c["forcing"] = json!({"type": "pulse_train", "period": 1.0, "duty": 0.5})),
            "simulation.t_end",
        ),
        ("damping", Box::new(|c| c["kind"] = json!("damping")), "damping_design"),
        // Issue 19: the eq. (35) and eq. (37) settings have ranges too.
        (
            "damping",
            Box::new(|c| {
                c["kind"] = json!("damping");
                c["damping_design"] = json!({"targets": [0.1, 1e300]});
            }),
            "damping_design.targets[1]",
        ),
        (
            "damping",
            Box::new(|c| {
                c["kind"] = json!("damping");
                c["damping_design"] = json!({"targets": [0.1], "tolerance": 1e-300});
            }),
            "damping_design.tolerance",
        ),
        (
            "damping",
            Box::new(|c| {
                c["kind"] = json!("damping");
                c["damping_design"] = json!({"targets": vec![0.1; 101]});
            }),
            "damping_design.targets",
        ),
        (
            "periodic",
            Box::new(|c| {
                c["kind"] = json!("periodic");
                c["forcing"] = json!({"type": "pulse_train", "period": 1.0, "duty": 0.5});
                c.as_object_mut().unwrap().remove("simulation");
                c["periodic_design"] =
                    json!({"delta_d": -0.05, "settings": {"response": {"samples_per_period": 1e12 as u64}}});
            }),
            "periodic_design.settings.response.samples_per_period",
        ),
        (
            "periodic",
            Box::new(|c| {
                c["kind"] = json!("periodic");
                c["forcing"] = json!({"type": "pulse_train", "period": 1.0, "duty": 0.5});
                c.as_object_mut().unwrap().remove("simulation");
                c["periodic_design"] = json!({"delta_d": -0.05, "settings": {"response": {"max_periods": 1e9 as u64}}});
            }),
            "periodic_design.settings.response.max_periods",
        ),
        (
            "periodic",
            Box::new(|c| {
                c["kind"] = json!("periodic");
                c["periodic_design"] = json!({"delta_d": -0.05});
            }),
            "forcing.type",
        ),
        // A shallow arch under a push far beyond its buckling load: θ2 is not a stable final state.
        (
            "simulate",
            Box::new(|c| {
                let t: Vec<f64> =
                    (0..4).map(|i| 0.02 * (std::f64::consts::PI * (i as f64 + 0.5) / 4.0).cos()).collect();
                c["design"] = json!({"theta0": t, "stiffness": [1000, 1000, 1000, 1000, 0]});
                c["loads"]["p_x"] = json!(-1.0e4);
            }),
            "design: the loaded equilibrium θ2 is not stable",
        ),
    ];
    for (kind, edit, field) in cases {
        let mut c = step_case(4);
        edit(&mut c);
        let case = write_case(&dir, &c);
        let o = spine(&[kind, &case, "--out", out.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{field}: {err}");
        assert!(err.contains(field), "the error names {field}: {err}");
        assert!(!out.exists(), "nothing written for {field}");
    }
}

/// A pulse train's first on-phase starts from rest at θ1 under the same load as a step, and lasts
/// longer than T_90: its reported rise equals the step response's T_90. No "paper" comparison is
/// printed for a case that is not the paper's.
#[test]
fn periodic_simulation_reports_the_first_on_phase_rise() {
    let dir = tmpdir("first-rise");
    let step = write_case(&dir, &step_case(4));
    let out = dir.join("step");
    assert!(spine(&["simulate", &step, "--out", out.to_str().unwrap(), "--deterministic"]).status.success());
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let t90 = r["step_response"]["rise_time"].as_f64().unwrap();

    let mut c = step_case(4);
    c.as_object_mut().unwrap().remove("simulation");
    c["forcing"] = json!({"type": "pulse_train", "period": 2.0, "duty": 0.5});
    c["periodic"] = json!({"max_periods": 2, "samples_per_period": 100});
    let pulse_dir = dir.join("pulse-case");
    std::fs::create_dir_all(&pulse_dir).unwrap();
    let pulse = write_case(&pulse_dir, &c);
    let out = dir.join("pulse");
    let o = spine(&["simulate", &pulse, "--out", out.to_str().unwrap(), "--deterministic"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("first on-phase") && !stdout.contains("paper"), "{stdout}");
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let first = r["periodic_response"]["first_rise_time"].as_f64().unwrap();
    assert!((first - t90).abs() <= 1e-5 * t90, "first on-phase rise {first} s vs step T_90 {t90} s");
}

/// Issue 19: a dynamic case whose embedded eq. (33) design fails is a run that did not end clean
/// (exit 3, its status written), not a program failure (it was exit 1 with nothing written).
#[test]
fn a_failed_embedded_design_exits_3_with_its_status_written() {
    let dir = tmpdir("failed-design");
    let mut c: Value =
        serde_json::from_str(&std::fs::read_to_string(workspace().join("paper-cases/step5.json")).unwrap()).unwrap();
    c["static_design"]["solver"] = json!({"max_iterations": 2});
    let case = write_case(&dir, &c);
    let out = dir.join("out");
    let o = spine(&["simulate", &case, "--out", out.to_str().unwrap(), "--deterministic"]);
    assert_eq!(o.status.code(), Some(3), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    let source = &r["design"]["source"];
    assert_eq!(source["status"], "maximum_iterations_exceeded");
    assert_eq!(source["clean"], false);
    assert!(!source["warnings"].as_array().unwrap().is_empty());
    assert!(r.get("step_response").is_none(), "no dynamics on a failed design");
    assert!(String::from_utf8_lossy(&o.stdout).contains("NOT clean: no dynamics ran on it"));
}

#[test]
fn damping_case_meets_each_target() {
    let dir = tmpdir("damping");
    let mut c = step_case(3);
    c["kind"] = json!("damping");
    c["simulation"]["integrator"] = json!({"rtol": 1e-8, "atol": 1e-10});
    c["damping_design"] = json!({"targets": [0.1, 0.05]});
    let case = write_case(&dir, &c);
    let out = dir.join("out");
    let o = spine(&["case", &case, "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    for (d, target) in r["damping_designs"].as_array().unwrap().iter().zip([0.1, 0.05]) {
        assert_eq!(d["converged"], true);
        assert!((d["rise_time"].as_f64().unwrap() - target).abs() <= 5e-3 * target);
        assert!(d["damping"].as_array().unwrap().iter().all(|c| (1.0..=1e3).contains(&c.as_f64().unwrap())));
    }
    assert!(out.join("response_T0.05.csv").exists());
}

#[test]
fn paper_step_case_runs() {
    let dir = tmpdir("paper-step5");
    let case = workspace().join("paper-cases/step5.json");
    let o = spine(&["case", case.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["design"]["source"]["source"], "eq. (33)");
    assert_eq!(r["step_response"]["settled"], true);
}

#[test]
fn animate_writes_a_gif_of_the_motion_with_the_asked_frames_and_the_same_bytes() {
    let dir = tmpdir("animate");
    let case = write_case(&dir, &step_case(4));
    let out = dir.join("out");
    let args = ["simulate", &case, "--out", out.to_str().unwrap(), "--deterministic"];
    let plain = spine(&args);
    assert!(plain.status.success(), "{}", String::from_utf8_lossy(&plain.stderr));
    assert!(!out.join("animation.gif").exists(), "no animation unless asked");
    let animated = [&args[..], &["--animate", "--frames", "12", "--frame-width", "480"]].concat();
    let o = spine(&animated);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let bytes = std::fs::read(out.join("animation.gif")).unwrap();
    assert_eq!(common::gif_width_and_frames(&bytes), (480, 12));
    assert!(bytes.len() < 2_000_000, "{} bytes", bytes.len());
    // The same input gives the same animation, byte for byte.
    assert!(spine(&animated).status.success());
    assert!(std::fs::read(out.join("animation.gif")).unwrap() == bytes);
    // --magnify alone asks for it too; bad options exit 2 naming the flag, and nothing is written.
    let fresh = dir.join("fresh");
    for (bad, flag) in [("--frames", "1"), ("--frame-width", "99999"), ("--magnify", "0")] {
        let o = spine(&["simulate", &case, "--out", fresh.to_str().unwrap(), bad, flag]);
        assert_eq!(o.status.code(), Some(2), "{bad} {flag}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(bad), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(!fresh.exists());
    }
    // A static case has nothing to animate.
    let eq = workspace().join("paper-cases/arch10.json");
    let o = spine(&["case", eq.to_str().unwrap(), "--out", fresh.to_str().unwrap(), "--animate"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("animation:"), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!fresh.exists());
}
