//! The global certificate of issue 45, item 4: SCIP's dual bound on eq. (33) for design5's loads
//! with two links closes to 1e-4 of the census's best (`benchmarks/peers/scip_global.py`).
//!
//! SCIP is optional: this test runs only where `just certify` has made
//! `benchmarks/peers/.venv-scip` (the `pyscipopt` wheel), and says so on stderr when it skips.

mod common;

use common::{spine, tmpdir, workspace};
use serde_json::Value;
use std::process::Command;

#[test]
fn scip_certifies_the_two_link_census_optimum_to_1e_4() {
    let root = workspace();
    let python = root.join("benchmarks/peers/.venv-scip/bin/python");
    if !python.exists() {
        eprintln!("skipped: {} is absent (run `just certify` once to make it)", python.display());
        return;
    }
    let case = root.join("benchmarks/peers/certify/design5-2links.json");
    let out = tmpdir("global-certificate");
    let census = spine(&[
        "design",
        case.to_str().unwrap(),
        "--confidence",
        "0.01",
        "--deterministic",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(census.status.success(), "{}", String::from_utf8_lossy(&census.stderr));
    let result = out.join("result.json");
    let scip = Command::new(&python)
        .arg(root.join("benchmarks/peers/scip_global.py"))
        .args([case.to_str().unwrap(), result.to_str().unwrap(), "--time", "300", "--incumbent"])
        .output()
        .expect("runs scip_global.py");
    assert!(scip.status.success(), "{}", String::from_utf8_lossy(&scip.stderr));
    let report: Value = serde_json::from_slice(&scip.stdout).expect("scip_global.py prints JSON");
    let census_j = report["census_J"].as_f64().unwrap();
    let lower = report["dual_bound"].as_f64().unwrap();
    // The census's point solves the same equations SCIP was given.
    assert!(report["check"]["largest_residual"].as_f64().unwrap() < 1e-9, "{report}");
    assert!(report["incumbent_accepted"].as_bool().unwrap(), "{report}");
    assert_eq!(report["status"], "gaplimit", "{report}");
    // No design has J below the dual bound, and the census's J is within 1e-4 above it.
    assert!(lower <= census_j, "{report}");
    assert!((census_j - lower) / census_j <= 1e-4, "{report}");
    assert!((6.4679e-3..6.4680e-3).contains(&census_j), "{report}");
}
