//! The peer case file states the same problem as the fixture, the exponent fit recovers known
//! power laws, and the comparison table says what each row shows.

use spine_benchmarks::peers::{table, CrossCheck, PeerRow, SolverRun};
use spine_benchmarks::report::{fit_exponent, targets, Measurement};
use spine_design::fixtures::{arch_start, scaled_family};

#[test]
fn the_peer_case_file_is_the_scaled_family_at_the_arch_start() {
    for n in [5, 10, 100] {
        let valid = spine_benchmarks::peers::scaled_family_design(n);
        let fixture = scaled_family(n);
        // No link mass, so switching self-weight off (gravity 0 in the case) changes nothing.
        assert_eq!(valid.problem.structure.chain.spans, fixture.structure.chain.spans);
        assert_eq!(valid.problem.structure.chain.masses, fixture.structure.chain.masses);
        assert_eq!(valid.problem.passive_loads(), fixture.passive_loads());
        assert_eq!(valid.problem.total_loads(), fixture.total_loads());
        assert_eq!(valid.problem.structure.passive, fixture.structure.passive);
        assert_eq!(valid.problem.structure.actuation, fixture.structure.actuation);
        assert_eq!(valid.problem.bounds, fixture.bounds);
        assert_eq!(valid.problem.delta_d, fixture.delta_d);
        assert_eq!(valid.problem.stiffness_scale, fixture.stiffness_scale);
        let s = n as f64 / 10.0;
        assert_eq!(valid.start, arch_start(n, 0.3, 1e3 * s * s));
    }
}

#[test]
fn exponent_fit_recovers_power_laws_from_the_fit_range_only() {
    let law = |p: f64| -> Vec<(usize, f64)> {
        [5, 10, 50, 100, 1000].iter().map(|&n| (n, 3e-7 * (n as f64).powf(p))).collect()
    };
    for p in [0.5, 1.0, 2.0] {
        assert!((fit_exponent(&law(p), 50).unwrap() - p).abs() < 1e-12);
    }
    // Small-N points (fixed costs) are left out of the fit.
    let mut bent = law(1.0);
    bent[0].1 *= 100.0;
    assert!((fit_exponent(&bent, 50).unwrap() - 1.0).abs() < 1e-12);
    assert!(fit_exponent(&bent[..3], 50).is_none());
}

fn run(objective: f64, seconds: f64, converged: bool) -> SolverRun {
    SolverRun {
        status: if converged { "Solve_Succeeded".into() } else { "Maximum_Iterations_Exceeded".into() },
        converged,
        iterations: 40,
        wall_seconds: seconds,
        objective,
        constraint_violation: 1e-12,
        theta0: vec![],
        stiffness: vec![],
        ipopt_version: "3.11.9".into(),
        levels: vec![],
        warnings: vec![],
    }
}

#[test]
fn the_table_tells_same_optimum_different_optima_and_failures_apart() {
    let row = |ours: SolverRun, casadi: Option<SolverRun>, cross_check: Option<CrossCheck>| PeerRow {
        n: 100,
        case: "c.json".into(),
        ours,
        casadi,
        casadi_error: Some("not installed".into()),
        cross_check,
        ours_refined: None,
        ipopt314: None,
        ipopt314_refined: None,
        casadi_refined: None,
        ours_mumps: None,
    };
    let same = row(run(1.0, 0.5, true), Some(run(1.0 + 1e-8, 2.0, true)), None);
    assert_eq!(same.verdict(), "same optimum");
    assert_eq!(same.ratio(), Some(0.25));
    let back = CrossCheck { status: "solve_succeeded".into(), converged: true, iterations: 3, objective: 1.1 };
    let different = row(run(1.0, 0.5, true), Some(run(1.1, 2.0, true)), Some(back));
    assert!(
        different.verdict().starts_with("different local optima; ours from CasADi's optimum stays there (3 iterations"),
        "{}",
        different.verdict()
    );
    let failed = row(run(1.0, 0.5, true), Some(run(1.1, 2.0, false)), None);
    assert_eq!(failed.verdict(), "CasADi did not converge (Maximum_Iterations_Exceeded)");
    // Ipopt's success at a point the certificate refuses is neither a failure to converge nor ✓.
    let mut saddle = run(0.9, 0.5, false);
    saddle.status = "solve_succeeded".into();
    saddle.warnings = vec!["not a minimum".into()];
    assert!(saddle.cell().starts_with("✗ 40 it"), "{}", saddle.cell());
    let refused = row(saddle, Some(run(1.0, 2.0, true)), None);
    assert_eq!(refused.verdict(), "ours solve_succeeded, but: not a minimum");
    let missing = row(run(1.0, 0.5, true), None, None);
    assert_eq!(missing.verdict(), "CasADi gave no result: not installed");
    // The best converged run of ours is compared with CasADi's cold run.
    let mut best = row(run(1.0, 0.5, true), Some(run(1.0, 2.0, true)), None);
    best.ours_refined = Some(run(1.0, 0.2, true));
    best.ipopt314_refined = Some(run(1.0, 0.1, false));
    assert_eq!(best.best().map(|(name, _)| name), Some("refined 3.11"));
    assert_eq!(best.best_ratio(), Some(0.1));
    best.ours_mumps = Some(run(1.0, 0.3, true));
    let md = table(&[same, missing, best]);
    assert_eq!(md.lines().count(), 5);
    assert!(
        md.contains("| 100 | ✓ 40 it, 0.500 s | – | – | – | – | ✓ 40 it, 2.000 s | – | 0.25 (cold 3.11) |"),
        "{md}"
    );
    assert!(md.contains("| 100 | ✓ 40 it, 0.500 s | ✓ 40 it, 0.200 s | ✓ 40 it, 0.300 s |"), "{md}");
    assert!(md.contains("Maximum_Iterations_Exceeded 40 it, 0.100 s"), "{md}");
}

#[test]
fn targets_report_the_ad_to_hand_ratio_and_unmeasured_targets() {
    let m = |method: &str, n: usize, seconds: f64| Measurement {
        group: "jacobian".into(),
        method: method.into(),
        n,
        seconds,
    };
    let measurements = vec![m("ad", 100, 3e-6), m("hand", 100, 2e-6), m("ad", 1000, 3e-5), m("hand", 1000, 1e-5)];
    let t = targets(&measurements, &[]);
    assert!(t[0].measured.contains("N=100: 1.50×") && t[0].measured.contains("N=1000: 3.00×"), "{}", t[0].measured);
    assert_eq!(t[0].met, Some(false));
    assert!(t.iter().filter(|t| t.statement.contains("CasADi")).all(|t| t.met.is_none()));
}

#[test]
fn the_readme_block_is_replaced_between_its_markers_only() {
    use spine_benchmarks::report::replace_block;
    let text = "intro\n<!-- BEGIN t -->\nold\n<!-- END t -->\nrest\n";
    assert_eq!(replace_block(text, "t", "new\n").unwrap(), "intro\n<!-- BEGIN t -->\nnew\n<!-- END t -->\nrest\n");
    assert!(replace_block(text, "other", "x").is_none());
}
