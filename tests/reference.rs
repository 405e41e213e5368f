//! One reference answer through every solver: the two-link structure of Sec. 3, whose equilibria
//! are roots of the scalar eqs. (7) and (8), solved here by a scalar Newton iteration independent
//! of the N-link code. The fixture returns the problem with that answer; the N-link continuation
//! (Newton on `(θ, λ)`), eq. (33) with Ipopt in the full and the reduced space, and the damped step
//! response's final state must all reproduce it.

use num_dual::{first_derivative, Dual64};
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{DesignBounds, DesignProblem, Formulation, SolverSettings};
use spine_dynamics::{step_response, DynamicProblem, StepSettings};
use spine_model::twolink::TwoLink;
use spine_model::Design;
use spine_solve::twolink::general_problem;
use spine_solve::{solve_static, ContinuationOptions, StaticProblem};

/// The reference answer of the two-link structure with design angle `θ0` and middle spring `K`:
/// `θ1` (eq. (7)), `θ2` (eq. (8)), `δ` (eq. (9)) and `J = U(θ1)` (eq. (12)).
#[derive(Debug)]
struct Reference {
    theta0: f64,
    stiffness: f64,
    theta1: f64,
    theta2: f64,
    delta: f64,
    energy: f64,
}

/// A root of `f` by Newton from `x`, derivatives by a dual number; panics if it does not converge.
fn scalar_newton(mut x: f64, f: impl Fn(Dual64) -> Dual64) -> f64 {
    for _ in 0..50 {
        let (value, slope) = first_derivative(&f, x);
        let step = value / slope;
        x -= step;
        if step.abs() < 1e-15 {
            return x;
        }
    }
    panic!("scalar Newton did not converge");
}

/// The Sec. 3 structure as an N = 2 problem (links of 0.5 m, −10 N at the middle node, −400 N at
/// the end, K = 1000 N·m/rad, θ0 = 0.1 rad), with its reference answer.
fn two_link() -> (TwoLink, StaticProblem, Reference) {
    let tl = TwoLink { length: 0.5, p_y: -10.0, p_x: -400.0 };
    let (theta0, stiffness) = (0.1, 1000.0);
    let eq = |axial| move |t: Dual64| tl.equilibrium(t, Dual64::from(theta0), Dual64::from(stiffness), axial);
    let theta1 = scalar_newton(theta0, eq(false));
    let theta2 = scalar_newton(theta1, eq(true));
    let reference = Reference {
        theta0,
        stiffness,
        theta1,
        theta2,
        delta: tl.end_displacement(theta2, theta0),
        energy: tl.strain_energy(theta1, theta0, stiffness),
    };
    (tl, general_problem(&tl, stiffness, theta0), reference)
}

/// Link 1 at `θ`, link 2 at `−θ` (the symmetric two-link shape).
fn close(theta: &[f64], reference: f64, tol: f64, what: &str) {
    assert!(
        (theta[0] - reference).abs() <= tol && (theta[1] + reference).abs() <= tol,
        "{what}: {theta:?} vs ±{reference}"
    );
}

#[test]
fn the_reference_solves_eqs_7_and_8() {
    let (tl, _, r) = two_link();
    assert!(tl.equilibrium(r.theta1, r.theta0, r.stiffness, false).abs() < 1e-10);
    assert!(tl.equilibrium(r.theta2, r.theta0, r.stiffness, true).abs() < 1e-10);
    // The transverse load flattens the links (θ1 < θ0); the axial push raises them and the end
    // moves toward the base (θ2 > θ0, δ < 0).
    assert!(r.theta1 < r.theta0 && r.theta2 > r.theta0 && r.delta < 0.0, "{r:?}");
}

#[test]
fn continuation_newton_reproduces_the_reference() {
    let (_, problem, r) = two_link();
    let solution = solve_static(&problem, &ContinuationOptions::default());
    let loaded = solution.loaded.as_ref().expect("reached the full load");
    assert!(solution.passive.status.is_stable() && loaded.status.is_stable());
    close(&solution.passive.state.theta, r.theta1, 1e-12, "θ1");
    close(&loaded.state.theta, r.theta2, 1e-12, "θ2");
    assert!((solution.end_displacement.unwrap() - r.delta).abs() < 1e-13);
}

/// Eq. (33) with the spring pinned (`K_2 = K`, no end springs) and `δ_d` the reference `δ`: the
/// only feasible design is the reference one, so both formulations must end there from a start
/// 0.05 rad away.
#[test]
fn ipopt_full_and_reduced_space_reproduce_the_reference() {
    let (_, problem, r) = two_link();
    let stiffness = vec![0.0, r.stiffness, 0.0];
    let design_problem = DesignProblem {
        structure: problem.structure.clone(),
        delta_d: r.delta,
        bounds: DesignBounds {
            theta0_max: 1.0,
            relative_angle_max: 2.0,
            stiffness_min: stiffness.clone(),
            stiffness_max: stiffness.clone(),
            height_min: 1e-3,
            height_max: 1.0,
            height_ramp: 0.0,
        },
        stiffness_scale: 1.0,
        objective: Default::default(),
        strain_energy_max: None,
    };
    let start = Design { theta0: vec![r.theta0 + 0.05, -(r.theta0 + 0.05)], stiffness };
    for formulation in [Formulation::Full, Formulation::Reduced] {
        let result = Solver::new(SolverPreset::Exact, formulation, &SolverSettings::default())
            .solve(&design_problem, &start, &mut |_| true)
            .expect("the problem sets up");
        assert!(result.is_clean(), "{formulation:?}: {} {:?}", result.solver.status, result.warnings);
        close(&result.design.theta0, r.theta0, 1e-7, &format!("{formulation:?} θ0"));
        close(&result.passive.as_ref().unwrap().theta, r.theta1, 1e-7, &format!("{formulation:?} θ1"));
        close(&result.loaded.as_ref().unwrap().theta, r.theta2, 1e-7, &format!("{formulation:?} θ2"));
        assert!((result.objective - r.energy).abs() <= 1e-7 * r.energy, "{formulation:?} J");
    }
}

/// With link masses (0.5 kg, no gravity: the statics are unchanged) and dampers, the step of the
/// axial force carries the structure from `θ1` to rest at `θ2`.
#[test]
fn the_damped_step_response_ends_at_the_reference() {
    let (_, problem, r) = two_link();
    let mut structure = problem.structure.clone();
    structure.chain.masses = vec![0.5, 0.5];
    let dynamic = DynamicProblem { structure, design: problem.design.clone(), damping: vec![0.0, 20.0, 0.0] };
    let response = step_response(&dynamic, &StepSettings { t_end: 5.0, ..StepSettings::default() }, false).unwrap();
    close(&response.ends.theta1, r.theta1, 1e-12, "static start θ1");
    close(&response.ends.theta2, r.theta2, 1e-12, "static end θ2");
    assert!(response.settled, "settle error {}", response.settle_error);
    assert!(response.final_state_gap < 1e-4, "max |θ(t_end) − θ2| = {} rad", response.final_state_gap);
    assert!((response.ends.loaded_displacement - r.delta).abs() < 1e-12);
}
