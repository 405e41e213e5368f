//! Issue 18, item 1: the reported design is the design whose numbers are reported. Ipopt 3.11's
//! default `honor_original_bounds = yes` moves `θ0` back onto its bound after the solve; the
//! equilibria of the moved design are then not satisfied although Ipopt says `solve_succeeded`.
//! Two configurations where this happened (found by a user, issue 18).

use spine_design::fixtures::{arch_start, paper_bounds, paper_five_link_start, paper_problem};
use spine_design::result::DesignWarning;
use spine_design::settings::ExtraOption;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{DesignProblem, DesignResult, Formulation, SolverSettings};
use spine_model::{Chain, Design};

/// 5 links over `L_x = 0.5 m`, −10 N per node, −400 N at the end, `δ_d = −0.0375 m`, `C_K = 1`.
fn five_links() -> (DesignProblem, Design) {
    let mut p = paper_problem(5, -10.0, -400.0, -0.0375, 1.0);
    p.structure.chain = Chain::uniform(5, 0.5);
    p.bounds = paper_bounds(5, 0.5, 1e2, 1e4, 0.01);
    (p, paper_five_link_start())
}

/// 10 links over `L_x = 0.5 m`, nodes 1–5 at −20 N, −400 N at the end, `δ_d = −0.075 m`.
fn ten_links() -> (DesignProblem, Design) {
    let mut p = paper_problem(10, 0.0, -400.0, -0.075, 1.0);
    p.structure.chain = Chain::uniform(10, 0.5);
    p.bounds = paper_bounds(10, 0.5, 1e2, 1e4, 0.01);
    for j in 1..=5 {
        p.structure.passive.p_y[j] = -20.0;
    }
    (p, arch_start(10, 0.3, 1e3))
}

fn run(problem: &DesignProblem, start: &Design, honor: Option<&str>) -> DesignResult {
    let mut settings = SolverSettings::default();
    if let Some(h) = honor {
        settings.ipopt_options.insert("honor_original_bounds".into(), ExtraOption::Str(h.into()));
    }
    Solver::new(SolverPreset::Exact, Formulation::Full, &settings).solve(problem, start, &mut |_| true).unwrap()
}

/// With the workspace's settings (`honor_original_bounds = no`) the run is clean and its numbers
/// are those of its design: equilibria to 1e-9 N·m, `J` the strain energy of the reported state,
/// `θ0` at most Ipopt's bound relaxation (1e-8 rad) past `π/6`. With Ipopt 3.11's default the
/// design is moved after the solve: the same check must then refuse to call it clean and name
/// the broken equilibria.
fn check(name: &str, (problem, start): (DesignProblem, Design)) {
    let r = run(&problem, &start, None);
    assert!(r.solver.optimal && r.is_clean(), "{name}: {} {:?}", r.solver.status, r.warnings);
    let v = r.violations.as_ref().unwrap();
    assert!(v.passive_equilibrium <= 1e-9 && v.loaded_equilibrium <= 1e-9, "{name}: {v:?}");
    assert!(v.theta0_bounds <= 1e-8, "{name}: θ0 beyond its bound by {}", v.theta0_bounds);
    let s1 = &r.passive.as_ref().unwrap().theta;
    let energy = spine_model::energy::strain_energy(s1, &r.design.theta0, &r.design.stiffness);
    assert_eq!(r.objective, energy, "{name}");
    let on_bound = r.design.theta0.iter().filter(|t| (t.abs() - problem.bounds.theta0_max).abs() <= 1e-7).count();
    assert!(on_bound >= 2, "{name}: the case is meant to have θ0 on its bound: {:?}", r.design.theta0);

    let clipped = run(&problem, &start, Some("yes"));
    assert_eq!(clipped.solver.status, spine_ipopt::Status::SolveSucceeded, "{name}");
    let moved = clipped.design.theta0.iter().zip(&r.design.theta0).any(|(a, b)| a != b);
    if !moved {
        // Ipopt 3.14 no longer moves the point when its relaxed bounds are left within round-off;
        // 3.11 does, and that is the case this test was written for.
        assert!(
            !spine_ipopt::IPOPT_VERSION.starts_with("3.11"),
            "{name}: Ipopt 3.11 no longer moves θ0 after the solve; this test has lost its case"
        );
        assert!(clipped.is_clean(), "{name}: {:?}", clipped.warnings);
        return;
    }
    let broken: Vec<&str> = clipped
        .warnings
        .iter()
        .filter_map(|w| match w {
            DesignWarning::ConstraintViolated { part, violation, allowed } => {
                assert!(violation > allowed);
                Some(*part)
            }
            _ => None,
        })
        .collect();
    assert!(broken.contains(&"passive_equilibrium") && broken.contains(&"loaded_equilibrium"), "{name}: {broken:?}");
    let text = clipped.warnings.iter().map(ToString::to_string).collect::<Vec<_>>().join("; ");
    assert!(text.contains("violates eq. (33): passive_equilibrium"), "{text}");
}

#[test]
fn five_link_design_on_its_angle_bound_is_reported_as_solved() {
    check("5 links, L_x = 0.5 m", five_links());
}

#[test]
fn ten_link_design_on_its_angle_bound_is_reported_as_solved() {
    check("10 links, L_x = 0.5 m", ten_links());
}
