//! Property test of eq. (33): at every optimum reported clean, on random configurations (links,
//! transverse and axial loads, δ_d), the first-order (KKT) conditions of the full-space problem
//! hold at the reported design and states: multipliers exist (least squares over the equality rows
//! and the active bounds) that make the Lagrangian's gradient vanish, with the signs an inequality
//! at its bound requires.

use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use spine_design::fixtures::{arch_start, paper_problem};
use spine_design::full_space::FullSpaceNlp;
use spine_design::settings::SolverPreset;
use spine_design::solve::Solver;
use spine_design::{Formulation, SolverSettings};
use spine_ipopt::Problem;
use spine_model::State;

/// A variable or constraint is active when within this of its bound (relative to `max(1, |bound|)`).
const ACTIVE: f64 = 1e-5;

/// `‖∇f + Σ μ_a ∇c_a‖∞` at `x` over the largest term of that sum (`‖∇f‖∞`, `|μ_a| ‖∇c_a‖∞`, 1),
/// as Ipopt scales its dual infeasibility, with multipliers of the right sign (within 1e-4 of the
/// largest) on every inequality kept in the active set: the sign conditions hold by construction,
/// and stationarity on that set is what can fail.
fn stationarity_at(nlp: &mut FullSpaceNlp<'_>, x: &[f64]) -> f64 {
    let (n, m) = (nlp.num_variables(), nlp.num_constraints());
    // Unset bounds are infinite, as spine_ipopt::solve hands them to Ipopt.
    let (mut xl, mut xu) = (vec![f64::NEG_INFINITY; n], vec![f64::INFINITY; n]);
    let (mut gl, mut gu) = (vec![f64::NEG_INFINITY; m], vec![f64::INFINITY; m]);
    nlp.variable_bounds(&mut xl, &mut xu);
    nlp.constraint_bounds(&mut gl, &mut gu);
    let mut grad = vec![0.0; n];
    assert!(nlp.objective_gradient(x, true, &mut grad));
    let mut g = vec![0.0; m];
    assert!(nlp.constraints(x, false, &mut g));
    let pattern = nlp.jacobian_structure();
    let mut values = vec![0.0; pattern.len()];
    assert!(nlp.jacobian_values(x, false, &mut values));
    let mut jac = DMatrix::zeros(m, n);
    for (&(r, c), v) in pattern.iter().zip(&values) {
        jac[(r, c)] += v;
    }
    let near = |v: f64, b: f64| b.is_finite() && (v - b).abs() <= ACTIVE * b.abs().max(1.0);
    // Columns: ∇c for every equality row and active inequality row, ±e_i for active variable
    // bounds; `sign` is +1 where the multiplier must be ≥ 0 (an upper bound), −1 where ≤ 0 (a
    // lower bound), 0 where it is free (an equality).
    let mut columns: Vec<(DVector<f64>, f64)> = Vec::new();
    for r in 0..m {
        let row = jac.row(r).transpose();
        if gl[r] == gu[r] {
            columns.push((row, 0.0));
        } else if near(g[r], gu[r]) {
            columns.push((row, 1.0));
        } else if near(g[r], gl[r]) {
            columns.push((row, -1.0));
        }
    }
    for i in 0..n {
        let mut e = DVector::zeros(n);
        e[i] = 1.0;
        if near(x[i], xu[i]) {
            columns.push((e, 1.0));
        } else if near(x[i], xl[i]) {
            columns.push((e, -1.0));
        }
    }
    // Sign-constrained least squares over the candidate set: an active set on which multipliers
    // of the right signs make the gradient vanish is a KKT point. (Where the active constraints
    // are linearly dependent, the multipliers are not unique and the unconstrained least-squares
    // solution may have wrong signs although correct ones exist: hence Lawson and Hanson's
    // non-negative least squares, with the equality multipliers free.)
    let a =
        DMatrix::from_columns(&columns.iter().map(|(c, s)| c * if *s == 0.0 { 1.0 } else { *s }).collect::<Vec<_>>());
    let free: Vec<bool> = columns.iter().map(|(_, s)| *s == 0.0).collect();
    let rhs = -DVector::from_vec(grad.clone());
    let nu = signed_least_squares(&a, &rhs, &free);
    let residual = &a * &nu - &rhs;
    let mu = nu;
    let terms = columns.iter().zip(mu.iter()).map(|((c, _), m)| m.abs() * c.amax());
    let scale = grad.iter().map(|v| v.abs()).chain(terms).fold(1.0f64, f64::max);
    residual.amax() / scale
}

/// The clean optimum that random sampling found where the plain least-squares test failed
/// (‖∇L‖∞ 1.3e-5 relative): two θ0 bounds, two relative-angle bounds and the end-height row meet
/// on five angles, the active gradients are dependent, and the minimum-norm multipliers had a
/// wrong sign where sign-correct ones exist.
#[test]
fn a_degenerate_active_set_still_has_sign_correct_multipliers() {
    let (n, p_y, p_x, delta_d) = (5, -4.837701883212651, -295.0527510032976, -0.015420921331445358);
    let problem = paper_problem(n, p_y, p_x, delta_d, 100.0);
    let settings = SolverSettings::default();
    let result = Solver::new(SolverPreset::Exact, Formulation::Full, &settings)
        .solve(&problem, &arch_start(n, 0.3, 1000.0), &mut |_| true)
        .expect("eq. (33) starts");
    assert!(result.is_clean(), "{:?}", result.warnings);
    let state = |s: &Option<spine_design::result::StateReport>| {
        let s = s.as_ref().expect("a clean result has both equilibria");
        State { theta: s.theta.clone(), lambda: s.lambda }
    };
    let form = result.solver.state_variables.expect("a full-space run says how its states were variables");
    let mut nlp = FullSpaceNlp::new(&problem, form, &result.design, &state(&result.passive), &state(&result.loaded));
    let x = nlp.start.clone();
    let stationarity = stationarity_at(&mut nlp, &x);
    assert!(stationarity < 1e-5, "‖∇L‖∞ = {stationarity:.3e} relative");
}

/// The sign constraints bind: `ν ≥ 0` cannot reach `b = −a`, a free multiplier can.
#[test]
fn signed_least_squares_keeps_the_signs() {
    let a = DMatrix::from_row_slice(2, 2, &[1.0, 0.0, 0.0, 1.0]);
    let b = DVector::from_vec(vec![-1.0, 2.0]);
    let nu = signed_least_squares(&a, &b, &[false, false]);
    assert_eq!(nu[0], 0.0);
    assert!((nu[1] - 2.0).abs() < 1e-12);
    let nu = signed_least_squares(&a, &b, &[true, false]);
    assert!((nu[0] + 1.0).abs() < 1e-12 && (nu[1] - 2.0).abs() < 1e-12);
}

/// `min ‖A ν − b‖` subject to `ν_j ≥ 0` where `free[j]` is false (Lawson and Hanson's active-set
/// method, with the free columns always in the passive set).
fn signed_least_squares(a: &DMatrix<f64>, b: &DVector<f64>, free: &[bool]) -> DVector<f64> {
    let k = a.ncols();
    let solve_on = |passive: &[bool]| -> DVector<f64> {
        let cols: Vec<usize> = (0..k).filter(|&j| passive[j]).collect();
        let mut z = DVector::zeros(k);
        if cols.is_empty() {
            return z;
        }
        let sub = DMatrix::from_fn(a.nrows(), cols.len(), |r, c| a[(r, cols[c])]);
        let sol = sub.svd(true, true).solve(b, 1e-12).expect("SVD solve");
        for (c, &j) in cols.iter().enumerate() {
            z[j] = sol[c];
        }
        z
    };
    let mut passive: Vec<bool> = free.to_vec();
    let mut x = solve_on(&passive);
    let scale = a.amax().max(1e-300) * b.amax().max(1e-300);
    for _ in 0..10 * k + 10 {
        let w = a.transpose() * (b - a * &x);
        let entering =
            (0..k).filter(|&j| !passive[j]).max_by(|&i, &j| w[i].total_cmp(&w[j])).filter(|&j| w[j] > 1e-12 * scale);
        let Some(j) = entering else { break };
        passive[j] = true;
        loop {
            let z = solve_on(&passive);
            let blocking: Vec<usize> = (0..k).filter(|&q| passive[q] && !free[q] && z[q] <= 0.0).collect();
            if blocking.is_empty() {
                x = z;
                break;
            }
            let alpha = blocking.iter().map(|&q| x[q] / (x[q] - z[q])).fold(1.0f64, f64::min);
            x = &x + (z - &x) * alpha;
            for q in 0..k {
                if passive[q] && !free[q] && x[q] <= 1e-15 * x.amax().max(1.0) {
                    passive[q] = false;
                    x[q] = 0.0;
                }
            }
        }
    }
    x
}

proptest! {
    // A fixed seed: the same ten configurations in every run (a failure is reproducible and CI does
    // not depend on luck); change the seed to explore others.
    #![proptest_config(ProptestConfig {
        cases: 10,
        rng_seed: proptest::test_runner::RngSeed::Fixed(33),
        ..ProptestConfig::default()
    })]
    #[test]
    fn every_clean_optimum_satisfies_the_kkt_conditions(
        n in 3usize..7,
        p_y in -8.0f64..-2.0,
        p_x in -400.0f64..-150.0,
        delta_d in -0.04f64..-0.01,
    ) {
        let problem = paper_problem(n, p_y, p_x, delta_d, 100.0);
        let settings = SolverSettings::default();
        let result = Solver::new(SolverPreset::Exact, Formulation::Full, &settings).solve(&problem, &arch_start(n, 0.3, 1000.0), &mut |_| true)
            .expect("eq. (33) starts");
        prop_assume!(result.is_clean());
        let state = |s: &Option<spine_design::result::StateReport>| {
            let s = s.as_ref().expect("a clean result has both equilibria");
            State { theta: s.theta.clone(), lambda: s.lambda }
        };
        let (passive, loaded) = (state(&result.passive), state(&result.loaded));
        let form = result.solver.state_variables.expect("a full-space run says how its states were variables");
        let mut nlp = FullSpaceNlp::new(&problem, form, &result.design, &passive, &loaded);
        let x = nlp.start.clone();
        let stationarity = stationarity_at(&mut nlp, &x);
        prop_assert!(stationarity < 1e-5, "N = {n}: ‖∇L‖∞ = {stationarity:.3e} relative");
    }
}
