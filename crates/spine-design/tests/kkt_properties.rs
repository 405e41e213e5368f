//! Property test of eq. (33): at every optimum reported clean, on random configurations (links,
//! transverse and axial loads, δ_d), the first-order (KKT) conditions of the full-space problem
//! hold at the reported design and states: multipliers exist (least squares over the equality rows
//! and the active bounds) that make the Lagrangian's gradient vanish, with the signs an inequality
//! at its bound requires.

use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use spine_design::fixtures::{arch_start, paper_problem};
use spine_design::full_space::FullSpaceNlp;
use spine_design::{solve_design, Formulation, SolverSettings};
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
    // Least squares over the candidate set; a candidate inequality whose multiplier comes out
    // with the wrong sign is dropped (the most wrong first) and the rest solved again: an active
    // set on which a sign-correct multiplier makes the gradient vanish is a KKT point.
    let rhs = -DVector::from_vec(grad.clone());
    let (mu, residual) = loop {
        let a = DMatrix::from_columns(&columns.iter().map(|(c, _)| c.clone()).collect::<Vec<_>>());
        let mu = a.clone().svd(true, true).solve(&rhs, 1e-12).expect("SVD solve");
        let largest = mu.iter().fold(1e-300f64, |s, v| s.max(v.abs()));
        let worst = columns
            .iter()
            .zip(mu.iter())
            .enumerate()
            .map(|(k, ((_, s), m))| (k, -s * m))
            .fold((0, 0.0), |best, (k, w)| if w > best.1 { (k, w) } else { best });
        if worst.1 > 1e-4 * largest {
            columns.remove(worst.0);
            continue;
        }
        let residual = &a * &mu - &rhs;
        break (mu, residual);
    };
    let terms = columns.iter().zip(mu.iter()).map(|((c, _), m)| m.abs() * c.amax());
    let scale = grad.iter().map(|v| v.abs()).chain(terms).fold(1.0f64, f64::max);
    residual.amax() / scale
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 10, ..ProptestConfig::default() })]
    #[test]
    fn every_clean_optimum_satisfies_the_kkt_conditions(
        n in 3usize..7,
        p_y in -8.0f64..-2.0,
        p_x in -400.0f64..-150.0,
        delta_d in -0.04f64..-0.01,
    ) {
        let problem = paper_problem(n, p_y, p_x, delta_d, 100.0);
        let settings = SolverSettings::default();
        let result = solve_design(&problem, &arch_start(n, 0.3, 1000.0), Formulation::Full, &settings, &mut |_| true)
            .expect("eq. (33) starts");
        prop_assume!(result.is_clean());
        let state = |s: &Option<spine_design::result::StateReport>| {
            let s = s.as_ref().expect("a clean result has both equilibria");
            State { theta: s.theta.clone(), lambda: s.lambda }
        };
        let (passive, loaded) = (state(&result.passive), state(&result.loaded));
        let mut nlp = FullSpaceNlp::new(&problem, &result.design, &passive, &loaded);
        let x = nlp.start.clone();
        let stationarity = stationarity_at(&mut nlp, &x);
        prop_assert!(stationarity < 1e-5, "N = {n}: ‖∇L‖∞ = {stationarity:.3e} relative");
    }
}
